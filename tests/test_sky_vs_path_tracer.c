/* Sky radiance from the reference tables (data/sky_lookup.h: single
 * scattering of every constituent times its phase function, plus multiple
 * scattering) against the Monte Carlo path tracer (models/path_tracer.h, all
 * orders) at points that cover the scene domain of SPEC §5: ground at noon
 * and at sunset, 5 km, the top of the atmosphere, a viewer in space, the
 * planet's shadow, ground albedo 0 and 0.3 (issue 3), and SPEC §10's
 * tangent rays (and 1e-6 either side), nu = +-1 and a horizontal ray from
 * the ground. Each point and channel must agree within max(3 standard
 * errors, 2 %; 3 % at the tangent, below).
 *
 * The tables are computed at a reduced resolution so that the test stays
 * short: 16 altitudes (half the default), 128 mu, 32 mu_s, 8 nu. The mu axis
 * keeps its default size because Bruneton's mu mapping of rays that hit the
 * ground is linear in the distance to the ground, which crowds the steep
 * downward rays of a low viewer into the first one or two intervals of the
 * ground half: with 64 mu those rays (5 km, looking down) come out 3-6 %
 * low, an interpolation error that each order inherits from the previous
 * one through the scattering density's lookups. Measured at "albedo 0.3, 5
 * km, looking down", blue, 4 orders, table against table: 16x64 -2.8 %,
 * 16x128 -0.9 %, 16x256 -0.3 % from 32x128, which agrees with the path
 * tracer cut at 4 orders (-0.6 % +- 0.5 %, 2e5 paths).
 *
 * `test_sky_vs_path_tracer RES SAMPLES ORDERS` reruns it at another
 * resolution ("MUxH,HxMUxMU_SxNU"), path count and number of orders, e.g.
 * the default resolution, to separate interpolation error from the rest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/atmosphere.h"
#include "models/atmosphere_file.h"
#include "models/path_tracer.h"
#include "models/ray_geometry.h"
#include "tests/check.h"

/* Orders kept in the tables. The slowest convergence is blue light looking
 * down onto a bright ground (each order about 0.4 of the one before), where
 * orders beyond 7 add about 0.4 %: the test measures that tail with the path
 * tracer and requires it below TRUNCATION_BOUND. */
#define TABLE_ORDERS 7
#define TRUNCATION_BOUND 0.005
/* The point of that slowest convergence (an index into points[] below). */
#define SLOWEST_POINT 12

typedef struct sky_point {
  const char *name;
  int albedo_case;            /* 0: ground albedo 0; 1: 0.3 */
  double h, mu, mu_s, nu;
  double rel_bound;           /* the relative part of the bound */
  int paths_factor;           /* paths: SAMPLES times this */
} sky_point;

static double seconds_now(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int make_tables(const sf_atmosphere *atm, const char *res, int orders, sf_table_set *set) {
  sf_table_set_options o;
  sf_table_set_options_default(&o);
  sf_error err = {0};
  if (sf_table_resolution_parse(res, &o.res, &err) != SF_OK) {
    printf("%s\n", err.message);
    return 1;
  }
  o.orders = orders;
  o.stop_fraction = 0.0;   /* exactly these orders */
  o.run.n_threads = 2;
  int status = sf_table_set_make(set, atm, &o, &err);
  if (status) printf("sf_table_set_make failed: %s\n", err.message);
  return status;
}

int main(int argc, char **argv) {
  const char *res = argc > 1 ? argv[1] : "64x16,16x128x32x8";
  long long samples = argc > 2 ? atoll(argv[2]) : 40000;
  int orders = argc > 3 ? atoi(argv[3]) : TABLE_ORDERS;
  sf_atmosphere atm[2];
  sf_atmosphere_default(&atm[0]);
  atm[1] = atm[0];
  for (int ch = 0; ch < atm[1].n_channels; ++ch) atm[1].ground_albedo[ch] = 0.3;
  double R = atm[0].bottom_radius_km;

  double t0 = seconds_now();
  sf_table_set set[2];
  for (int a = 0; a < 2; ++a)
    if (make_tables(&atm[a], res, orders, &set[a])) {
      CHECK(0);
      return check_summary();
    }
  double t_tables = seconds_now() - t0;
  sf_sky_tables sky[2];
  for (int a = 0; a < 2; ++a) sf_sky_tables_of_set(&sky[a], &atm[a], &set[a]);

  /* The horizon cosine of a viewer at 400 km, to aim at the limb, and of
   * one at 5 km (SPEC §10: tangent rays, and 1e-6 either side). */
  double mu_limb_400 = sf_horizon_mu(R + 400.0, R), mu_h5 = sf_horizon_mu(R + 5.0, R);
  const sky_point points[] = {
      {"ground, noon, zenith", 0, 0.0, 1.0, 0.999, 0.999, 0.02, 1},
      {"ground, noon, low sky", 0, 0.0, 0.1, 0.98, 0.25, 0.02, 1},
      {"ground, sunset, towards the sun", 0, 0.0, 0.15, 0.02, 0.95, 0.02, 1},
      {"ground, sunset, away from the sun", 0, 0.0, 0.3, 0.02, -0.6, 0.02, 1},
      {"5 km, looking down", 0, 5.0, -0.4, 0.6, 0.1, 0.02, 1},
      {"5 km, near the horizon", 0, 5.0, 0.02, 0.3, 0.5, 0.02, 1},
      {"100 km, looking down", 0, 100.0, -0.6, 0.7, -0.2, 0.02, 1},
      {"400 km, nadir", 0, 400.0, -1.0, 0.8, -0.8, 0.02, 1},
      {"400 km, limb", 0, 400.0, mu_limb_400 + 0.01, 0.3, 0.2, 0.02, 1},
      /* In the shadow few paths find the lit air: at 40,000 the tracer's
       * standard error at the ground point was 12 % of the value, 1.7-2.2 %
       * at 50 times as many. At 20 km it stays 9 % even so (2e8 paths give
       * 0.9 %): that point's multiple scattering is held to an independent
       * quadrature instead (test_multiple_order2_shadow.c). */
      {"planet shadow, ground, sun -5 deg", 0, 0.0, 0.2, -0.0872, -0.5, 0.02, 50},
      {"planet shadow, 20 km, sun -8 deg, away", 0, 20.0, 0.05, -0.139, -0.9, 0.02, 1},
      {"albedo 0.3, ground, noon", 1, 0.0, 0.5, 0.95, 0.6, 0.02, 1},
      {"albedo 0.3, 5 km, looking down", 1, 5.0, -0.5, 0.7, -0.1, 0.02, 1},
      {"albedo 0.3, 400 km, nadir", 1, 400.0, -1.0, 0.8, -0.8, 0.02, 1},
      {"albedo 0.3, ground, sunset", 1, 0.0, 0.2, 0.05, 0.3, 0.02, 1},
      /* SPEC §10's hard cases. At the tangent the table's 16 altitudes
       * (half the default) show: red -2.1 % just below it, where the
       * default resolution gives -0.50 % (and -0.47 % on it, -0.11 % above;
       * `test_sky_vs_path_tracer 256x64,32x128x32x8 1000000 7`): 3 % there */
      {"5 km, tangent to the ground", 0, 5.0, mu_h5, 0.3, 0.2, 0.03, 1},
      {"5 km, 1e-6 above the tangent", 0, 5.0, mu_h5 + 1e-6, 0.3, 0.2, 0.03, 1},
      {"5 km, 1e-6 below the tangent", 0, 5.0, mu_h5 - 1e-6, 0.3, 0.2, 0.03, 1},
      {"ground, towards the sun (nu = 1)", 0, 0.0, 0.3, 0.3, 1.0, 0.02, 1},
      {"5 km, away from the sun (nu = -1)", 0, 5.0, -0.5, 0.5, -1.0, 0.02, 1},
      {"ground, horizontal (mu = 0)", 0, 0.0, 0.0, 0.4, 0.1, 0.02, 1},
  };
  int n_points = (int)(sizeof points / sizeof points[0]);
  printf("tables %s, %d orders, computed in %.1f s (2 atmospheres); path tracer %lld paths per channel\n",
         res, orders, t_tables, samples);
  printf("%-40s %2s %12s %12s %10s %8s %8s\n", "point", "ch", "table", "path tracer", "sigma", "rel diff",
         "bound");
  double t1 = seconds_now();
  int worst_point = -1;
  double worst_ratio = 0.0;
  for (int p = 0; p < n_points; ++p) {
    const sky_point *pt = &points[p];
    const sf_atmosphere *a = &atm[pt->albedo_case];
    sf_sky_sample table;
    sf_sky_lookup(&sky[pt->albedo_case], pt->h, pt->mu, pt->mu_s, pt->nu, &table);
    sf_path_tracer_options po = {samples * pt->paths_factor, 1000u + (unsigned)p, 0, 2};
    sf_path_tracer_result mc;
    sf_error err = {0};
    if (sf_path_trace_sky_radiance(a, pt->h, pt->mu, pt->mu_s, pt->nu, &po, &mc, &err) != 0) {
      printf("%s: path tracer failed: %s\n", pt->name, err.message);
      CHECK(0);
      continue;
    }
    for (int ch = 0; ch < a->n_channels; ++ch) {
      double got = table.radiance[ch], want = mc.radiance[ch], sigma = mc.std_error[ch];
      double bound = fmax(3.0 * sigma, pt->rel_bound * fabs(want));
      double diff = fabs(got - want);
      int ok = isfinite(got) && want > 0.0 && diff <= bound;
      printf("%s %-35s %2d %12.5g %12.5g %10.3g %+7.2f%% %7.2f%%\n", ok ? "ok  " : "FAIL", pt->name, ch, got,
             want, sigma, 100.0 * (got - want) / want, 100.0 * bound / want);
      check_report(ok, pt->name, __FILE__, __LINE__);
      if (diff / bound > worst_ratio) {
        worst_ratio = diff / bound;
        worst_point = p;
      }
    }
  }
  printf("path tracing took %.1f s; largest |difference| / bound %.2f at \"%s\"\n", seconds_now() - t1,
         worst_ratio, worst_point >= 0 ? points[worst_point].name : "-");

  /* The orders the tables leave out: the same paths (same seed) cut after
   * `orders` scattering events, so the difference is a low-noise estimate
   * of the tail. */
  {
    const sky_point *pt = &points[SLOWEST_POINT];
    const sf_atmosphere *a = &atm[pt->albedo_case];
    sf_path_tracer_options all = {samples, 1000u + SLOWEST_POINT, 0, 2};
    sf_path_tracer_options cut = {samples, 1000u + SLOWEST_POINT, orders, 2};
    sf_path_tracer_result r_all, r_cut;
    sf_error err = {0};
    int ok = sf_path_trace_sky_radiance(a, pt->h, pt->mu, pt->mu_s, pt->nu, &all, &r_all, &err) == 0 &&
             sf_path_trace_sky_radiance(a, pt->h, pt->mu, pt->mu_s, pt->nu, &cut, &r_cut, &err) == 0;
    CHECK(ok);
    for (int ch = 0; ok && ch < a->n_channels; ++ch) {
      double tail = (r_all.radiance[ch] - r_cut.radiance[ch]) / r_all.radiance[ch];
      printf("orders beyond %d at \"%s\", channel %d: %.3f %% of the radiance (bound %.1f %%)\n", orders,
             pt->name, ch, 100.0 * tail, 100.0 * TRUNCATION_BOUND);
      check_report(tail >= 0.0 && tail < TRUNCATION_BOUND, "truncated orders", __FILE__, __LINE__);
    }
  }
  printf("total %.1f s\n", seconds_now() - t0);
  for (int a = 0; a < 2; ++a) sf_table_set_free(&set[a]);
  return check_summary();
}
