/* Segments of a sigmoid transmittance fitted for a low scene (SPEC §7.1,
 * seed 000 §9.5 and eq. 43; models/sigmoid_transmittance.h).
 *
 * A scene's viewers may all be low (a flight scene: 0-15 km), but their
 * segments end anywhere along their rays, up to the top of the
 * atmosphere, where eq. 43 evaluates the fitted T_top. Checked on viewers
 * of such a domain against two statements that do not come from the model:
 *  1. the transmittance of a longer segment of one ray is never larger than
 *     that of a shorter one: T(0, d2) = T(0, d1) T(d1, d2) <= T(0, d1);
 *  2. segments against the exact optical depth (models/optical_depth.h):
 *     RMSE within 0.07 (the fit over the whole atmosphere measured 0.061
 *     here; fitted on the domain's altitudes alone, the segment ends had
 *     extrapolated the fit, 0.080, and a longer segment was up to 0.19 more
 *     transparent than a shorter one, the ozone's T_top falling with
 *     altitude). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "fit/fit_sigmoid.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/ray_geometry.h"

int main(void) {
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_atmosphere_default(atm);
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  /* examples/scenes/flight.json's (h, mu) domain */
  sf_scene_domain dom = {0.0, 15.0, -1.0, 1.0, -0.17364817766693033, 1.0};
  sf_sigmoid_fit_options o;
  sf_sigmoid_fit_options_default(&o);
  o.n_h = 24;
  o.n_mu = 48;
  sf_sigmoid_model *m = malloc(sizeof *m);
  sf_sigmoid_fit_report *rep = malloc(sizeof *rep);
  sf_error err = {0};
  CHECK(sf_fit_sigmoid(atm, &dom, &o, m, rep, &err) == SF_OK);

  static const double hs[] = {0.0, 0.5, 2.0, 7.0, 15.0};
  static const double offsets[] = {-1e-3, -1e-6, 1e-6, 1e-3};
  const int n_mu = 81, n_d = 120;
  double worst_rise = 0.0, rise_h = 0.0, rise_mu = 0.0, sse = 0.0;
  int rays = 0, n = 0;
  for (int i = 0; i < 5; ++i) {
    double h = hs[i], mu_h = sf_horizon_mu(R + h, R);
    for (int j = 0; j < n_mu + 4; ++j) {
      double mu = j < n_mu ? -1.0 + 2.0 * j / (n_mu - 1) : mu_h + offsets[j - n_mu];
      double t0, t1;
      int hits;
      if (!sf_ray_atmosphere_segment(R + h, mu, R, Rt, &t0, &t1, &hits) || !(t1 > 0.0)) continue;
      ++rays;
      double least[SF_MAX_CHANNELS];   /* the least T of the shorter segments */
      for (int s = 1; s <= n_d; ++s) {
        double d = t1 * s / n_d, T[SF_MAX_CHANNELS];
        sf_sigmoid_model_eval_segment(m, h, mu, d, T);
        for (int k = 0; k < m->n_channels; ++k) {
          double rise = s > 1 ? T[k] - least[k] : 0.0;
          if (!(rise <= worst_rise)) {
            worst_rise = rise;
            rise_h = h;
            rise_mu = mu;
          }
          least[k] = s > 1 ? fmin(least[k], T[k]) : T[k];
        }
        if (s % 6 == 0) {
          double depth[SF_MAX_CONSTITUENTS], ref[SF_MAX_CHANNELS];
          sf_optical_depth_segment(atm, R + h, mu, 0.0, d, depth);
          sf_transmittance_from_depth(atm, depth, ref);
          for (int k = 0; k < m->n_channels; ++k, ++n) sse += (T[k] - ref[k]) * (T[k] - ref[k]);
        }
      }
    }
  }
  double rmse = sqrt(sse / n);
  printf("%d rays of the flight domain, %d segment ends each: largest excess of T over a shorter segment's %.3g (h %g km, "
         "mu %.6g); segments against the exact optical depth rmse %.4g over %d values\n",
         rays, n_d, worst_rise, rise_h, rise_mu, rmse, n);
  CHECK(worst_rise <= 1e-12);
  CHECK(rmse <= 0.07);
  free(rep);
  free(m);
  free(atm);
  return check_summary();
}
