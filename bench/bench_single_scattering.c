/* Benchmark: reference single scattering evaluations per second on one core
 * (target >= 1000 at <= 1e-7, issue "Foundation"), and the accuracy bought by
 * the default tolerance, measured against the same integral at a tolerance
 * 1000 times tighter. Prints a table. */
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "models/atmosphere_file.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"
#include "util/clock.h"

typedef struct query { double h, mu, mu_s, nu; } query;

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  /* A fixed grid: viewers from the ground to space, views over the sphere
   * including the horizon, suns from noon to below the horizon. */
  enum { MAXQ = 4096 };
  static query q[MAXQ];
  int n = 0;
  double heights[] = {0.0, 1.0, 5.0, 20.0, 60.0, 99.0, 200.0};
  double sun[] = {1.0, 0.5, 0.1, 0.02, -0.05, -0.2};
  for (int hi = 0; hi < 7; ++hi)
    for (int si = 0; si < 6; ++si)
      for (int mi = 0; mi < 12; ++mi) {
        double r = atm.bottom_radius_km + heights[hi];
        double mu_h = heights[hi] > 0 ? sf_horizon_mu(r, atm.bottom_radius_km) : 0.0;
        double mus[12] = {-1.0, -0.6, -0.3, mu_h - 1e-6, mu_h + 1e-6, 0.0, 0.01, 0.05, 0.2, 0.5, 0.8, 1.0};
        for (int k = 0; k < 3 && n < MAXQ; ++k) {
          double nu_rel[3] = {-1.0, 0.0, 1.0};
          q[n++] = (query){heights[hi], mus[mi], sun[si], nu_rel[k]};
        }
      }
  double max_rel = 0.0, sum_rel = 0.0;
  int counted = 0;
  double out[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS], tight[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  double checksum = 0.0;
  double start = sf_wall_seconds();
  for (int i = 0; i < n; ++i) {
    sf_view_ray ray;
    const char *why;
    sf_view_ray_make(&atm, q[i].h, q[i].mu, SF_RAY_END_NEAREST, -1.0, &ray, &why);
    sf_single_scattering(&atm, &ray, q[i].mu_s, q[i].nu, out);
    checksum += out[0];
  }
  double elapsed = sf_wall_seconds() - start;
  for (int i = 0; i < n; i += 7) {
    sf_view_ray ray;
    const char *why;
    sf_view_ray_make(&atm, q[i].h, q[i].mu, SF_RAY_END_NEAREST, -1.0, &ray, &why);
    sf_single_scattering(&atm, &ray, q[i].mu_s, q[i].nu, out);
    sf_single_scattering_tol(&atm, &ray, q[i].mu_s, q[i].nu, SF_SINGLE_SCATTERING_REL_TOL * 1e-3, tight);
    for (int k = 0; k < atm.n_constituents * atm.n_channels; ++k) {
      if (tight[k] <= 1e-300) continue;
      double e = fabs(out[k] - tight[k]) / tight[k];
      if (e > max_rel) max_rel = e;
      sum_rel += e;
      ++counted;
    }
  }
  printf("| quantity | evaluations | evals/s (1 core) | max rel. err | mean rel. err | target |\n");
  printf("|---|---|---|---|---|---|\n");
  printf("| single scattering (all constituents, %d channels) | %d | %.0f | %.2e | %.2e | >= 1000/s at <= 1e-7 |\n",
         atm.n_channels, n, n / elapsed, max_rel, counted ? sum_rel / counted : 0.0);
  printf("(checksum %.6g)\n", checksum);
  return 0;
}
