/* Speed against accuracy of the optical-depth methods (SPEC §7.6): the
 * reference (adaptive Gauss-Kronrod, models/optical_depth.h), N-step
 * raymarching, Schuler's Chapman, Gałaj's Taylor and Leenman's flat model,
 * on the built-in default atmosphere. One core, no threads.
 *
 * Rays: viewers at 9 altitudes, 200 view cosines each (140 evenly spaced in
 * [-1, 1] and 60 within +-0.02 of that viewer's horizon cosine), each ray to
 * its nearest end (ground or top). Every timed evaluation includes the ray's
 * geometry (where it leaves the air), as sf_optical_depth_ray does.
 * Relative errors are against the reference, per constituent, over the rays
 * whose reference depth exceeds 1e-9 of that constituent's vertical column
 * (so an ozone ray from 60 km looking up, with depth 0, counts for nothing). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "models/atmosphere.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/optical_depth_chapman.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_raymarch.h"
#include "models/optical_depth_taylor.h"
#include "models/ray_geometry.h"
#include "util/clock.h"

#define N_HEIGHTS 9
#define N_UNIFORM_MU 140
#define N_HORIZON_MU 60
#define N_MU (N_UNIFORM_MU + N_HORIZON_MU)
#define N_RAYS (N_HEIGHTS * N_MU)
#define MIN_SECONDS 0.3

static const double heights_km[N_HEIGHTS] = {0, 0.5, 2, 5, 10, 20, 35, 60, 99.9};

typedef struct ray { double h, mu; } ray;

typedef enum method_kind {
  METHOD_REFERENCE, METHOD_RAYMARCH, METHOD_CHAPMAN, METHOD_TAYLOR, METHOD_FLAT
} method_kind;

typedef struct method {
  char name[64];
  method_kind kind;
  int steps;
  sf_raymarch_rule rule;
  sf_flat_model flat;
} method;

typedef struct stats {
  double evals_per_s;
  int applicable[SF_MAX_CONSTITUENTS];      /* any ray gave a number */
  int nonfinite[SF_MAX_CONSTITUENTS];       /* rays that gave NaN/Inf where applicable */
  double max_rel[2][SF_MAX_CONSTITUENTS];   /* [0] all rays, [1] mu >= 0 */
  double sum_rel[2][SF_MAX_CONSTITUENTS];
  int count[2][SF_MAX_CONSTITUENTS];
} stats;

static void make_rays(const sf_atmosphere *atm, ray *rays) {
  int n = 0;
  for (int k = 0; k < N_HEIGHTS; ++k) {
    double h = heights_km[k];
    double horizon = sf_horizon_mu(atm->bottom_radius_km + h, atm->bottom_radius_km);
    for (int j = 0; j < N_UNIFORM_MU; ++j)
      rays[n++] = (ray){h, -1.0 + 2.0 * j / (N_UNIFORM_MU - 1)};
    for (int j = 0; j < N_HORIZON_MU; ++j) {
      double mu = horizon - 0.02 + 0.04 * j / (N_HORIZON_MU - 1);
      rays[n++] = (ray){h, mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu)};
    }
  }
}

static void evaluate(const method *m, const sf_atmosphere *atm, ray q, double *out) {
  if (m->kind == METHOD_REFERENCE) {
    sf_optical_depth_ray(atm, q.h, q.mu, SF_RAY_END_NEAREST, out);
    return;
  }
  double r = atm->bottom_radius_km + q.h, t0 = 0.0, t1 = 0.0;
  int hits_ground;
  if (!sf_ray_atmosphere_segment(r, q.mu, atm->bottom_radius_km, atm->top_radius_km, &t0,
                                 &t1, &hits_ground))
    t0 = t1 = 0.0;
  switch (m->kind) {
    case METHOD_RAYMARCH:
      sf_optical_depth_raymarch_segment(atm, r, q.mu, t0, t1, m->steps, m->rule, out);
      break;
    case METHOD_CHAPMAN: sf_optical_depth_chapman_segment(atm, r, q.mu, t0, t1, out); break;
    case METHOD_TAYLOR:
      sf_optical_depth_taylor_segment(atm, r, q.mu, t0, t1, SF_TAYLOR_A, SF_TAYLOR_B, out);
      break;
    case METHOD_FLAT:
      sf_optical_depth_flat_segment(atm, r, q.mu, t0, t1, &m->flat, out);
      break;
    default: break;
  }
}

/* Evaluations per second over the whole ray set, repeated for >= seconds. */
static double time_method(const method *m, const sf_atmosphere *atm, const ray *rays,
                          double seconds, double *sink) {
  double out[SF_MAX_CONSTITUENTS];
  long evals = 0;
  double start = sf_wall_seconds(), elapsed = 0.0, acc = 0.0;
  do {
    for (int k = 0; k < N_RAYS; ++k) {
      evaluate(m, atm, rays[k], out);
      for (int i = 0; i < atm->n_constituents; ++i)
        if (isfinite(out[i])) acc += out[i];
    }
    evals += N_RAYS;
    elapsed = sf_wall_seconds() - start;
  } while (elapsed < seconds);
  *sink += acc;
  return evals / elapsed;
}

static void measure_errors(const method *m, const sf_atmosphere *atm, const ray *rays,
                           const double (*ref)[SF_MAX_CONSTITUENTS],
                           const double *floor_km, stats *s) {
  double out[SF_MAX_CONSTITUENTS];
  for (int k = 0; k < N_RAYS; ++k) {
    evaluate(m, atm, rays[k], out);
    for (int i = 0; i < atm->n_constituents; ++i) {
      if (isnan(out[i]) && !s->applicable[i]) continue;   /* method n/a so far */
      if (!s->applicable[i]) s->applicable[i] = 1;
      if (!isfinite(out[i])) { ++s->nonfinite[i]; continue; }
      if (!(ref[k][i] > floor_km[i])) continue;
      double rel = fabs(out[i] - ref[k][i]) / ref[k][i];
      for (int up = 0; up <= (rays[k].mu >= 0.0); ++up) {
        if (rel > s->max_rel[up][i]) s->max_rel[up][i] = rel;
        s->sum_rel[up][i] += rel;
        ++s->count[up][i];
      }
    }
  }
}

static void print_table(const sf_atmosphere *atm, const method *methods,
                        const stats *all, int n_methods, int up_only) {
  printf("\n%s\n\n", up_only ? "Up-looking rays only (mu >= 0):"
                             : "All rays (to the ground or the top):");
  printf("| %-34s | %12s |", "method", "evals/s");
  for (int i = 0; i < atm->n_constituents; ++i) {
    char max_label[64], mean_label[64];
    snprintf(max_label, sizeof max_label, "%.12s max", atm->constituents[i].name);
    snprintf(mean_label, sizeof mean_label, "%.12s mean", atm->constituents[i].name);
    printf(" %17s | %17s |", max_label, mean_label);
  }
  printf("\n|%s|%s|", "------------------------------------", "-------------:");
  for (int i = 0; i < atm->n_constituents; ++i) printf("------------------:|------------------:|");
  printf("\n");
  for (int m = 0; m < n_methods; ++m) {
    const stats *s = &all[m];
    printf("| %-34s | %12.0f |", methods[m].name, s->evals_per_s);
    for (int i = 0; i < atm->n_constituents; ++i) {
      if (!s->applicable[i]) {
        printf(" %17s | %17s |", "n/a", "n/a");
      } else if (s->nonfinite[i]) {
        printf(" %11d NaN! | %17s |", s->nonfinite[i], "");
      } else {
        int c = s->count[up_only][i];
        printf(" %17.3e | %17.3e |", s->max_rel[up_only][i],
               c ? s->sum_rel[up_only][i] / c : 0.0);
      }
    }
    printf("\n");
  }
}

int main(void) {
  static sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  static ray rays[N_RAYS];
  make_rays(&atm, rays);

  static method methods[32];
  int n_methods = 0;
  methods[n_methods++] = (method){.name = "reference (adaptive Gauss-Kronrod)",
                                  .kind = METHOD_REFERENCE};
  for (int rule = 0; rule < 2; ++rule)
    for (int steps = 8; steps <= 1024; steps *= 2) {
      method *m = &methods[n_methods++];
      memset(m, 0, sizeof *m);
      m->kind = METHOD_RAYMARCH;
      m->steps = steps;
      m->rule = rule == 0 ? SF_RAYMARCH_MIDPOINT : SF_RAYMARCH_TRAPEZOID;
      snprintf(m->name, sizeof m->name, "raymarch %s N=%d",
               rule == 0 ? "midpoint" : "trapezoid", steps);
    }
  methods[n_methods++] = (method){.name = "chapman (Schuler, 000 eq. 24)",
                                  .kind = METHOD_CHAPMAN};
  methods[n_methods++] = (method){.name = "taylor (Galaj, a = b = 0.45)",
                                  .kind = METHOD_TAYLOR};
  methods[n_methods] = (method){.name = "flat (eq. 53 at the viewer)", .kind = METHOD_FLAT};
  sf_flat_model_make(&atm, SF_FLAT_DESCENT_VIEWER, &methods[n_methods++].flat);
  methods[n_methods] = (method){.name = "flat (eq. 53 at closest point)",
                                .kind = METHOD_FLAT};
  sf_flat_model_make(&atm, SF_FLAT_DESCENT_CLOSEST, &methods[n_methods++].flat);

  static double ref[N_RAYS][SF_MAX_CONSTITUENTS];
  double floor_km[SF_MAX_CONSTITUENTS], column[SF_MAX_CONSTITUENTS];
  sf_optical_depth_ray(&atm, 0.0, 1.0, SF_RAY_END_TOP, column);
  for (int i = 0; i < atm.n_constituents; ++i) floor_km[i] = 1e-9 * column[i];
  for (int k = 0; k < N_RAYS; ++k)
    evaluate(&methods[0], &atm, rays[k], ref[k]);

  printf("optical depth benchmark: atmosphere %s, %d rays (%d altitudes x %d mu), "
         "each method timed >= %.1f s on one core\n",
         atm.name, N_RAYS, N_HEIGHTS, N_MU, MIN_SECONDS);

  double sink = 0.0;
  double reference_rate = time_method(&methods[0], &atm, rays, 1.0, &sink);
  printf("reference: %.0f evals/s (target >= 100000)\n", reference_rate);

  static stats all[32];
  memset(all, 0, sizeof all);
  for (int m = 0; m < n_methods; ++m) {
    all[m].evals_per_s = time_method(&methods[m], &atm, rays, MIN_SECONDS, &sink);
    measure_errors(&methods[m], &atm, rays, (const double (*)[SF_MAX_CONSTITUENTS])ref,
                   floor_km, &all[m]);
  }
  print_table(&atm, methods, all, n_methods, 0);
  print_table(&atm, methods, all, n_methods, 1);
  printf("\n(checksum %.6g)\n", sink);
  return 0;
}
