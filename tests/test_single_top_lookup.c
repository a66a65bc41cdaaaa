/* The single scattering looked up from the tables near the top of the
 * atmosphere, against the exact single-scattering quadrature
 * (models/single_scattering.h, every constituent times its phase; its own
 * adaptive rule, no table). Between the tables' last two altitudes (93.7
 * and 100 km at the default 32) the samples' linear interpolation in rho
 * had the light of rays that keep to the thin air there too bright: from
 * 99 km, sun 20 deg up, 60 deg up +35.7 %, straight up +40.9 %; 95 km,
 * 30 deg up +5.5 %; 99.9 km, 10 deg up +8.8 % (every channel alike; it
 * depends on the altitude count alone, data/sky_lookup.c). Such rays now
 * go through the sunlit air (data/sunlit_ray.h): within 0.01 %. A ray
 * that dips from there into dense air keeps the samples' own
 * interpolation, which suits it, where F's coarse rule does not (from
 * 92.55 km, passing 1 km above the ground: -2.5 % in red by the samples;
 * +15.3 % in blue had the viewer's altitude, not the ray's lowest, chosen
 * F). The default altitude and view counts, half the default sun
 * count to keep the test short (the sun is high here). */
#include <math.h>
#include <stdio.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/atmosphere_file.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "tests/check.h"
#include "tests/lookup_test_tables.h"
#include "tests/exact_single_radiance.h"
#include "util/constants.h"

int main(void) {
  sf_atmosphere a;
  sf_table_set set;
  sf_sky_tables sky;
  /* single scattering alone */
  if (!CHECK(lookup_test_tables("256x64,32x128x16x8", 1, &a, &set, &sky) == 0)) return check_summary();
  /* elevation and azimuth from the sun in degrees; the relative bound */
  static const struct { const char *name; double h, sun, el, az, bound; } views[] = {
      {"99 km, sun 20, 60 deg up towards", 99.0, 20.0, 60.0, 0.0, 0.001},
      {"99 km, sun 20, zenith", 99.0, 20.0, 90.0, 0.0, 0.001},
      {"95 km, sun 45, 30 deg up across", 95.0, 45.0, 30.0, 90.0, 0.001},
      {"99.9 km, sun 70, 10 deg up away", 99.9, 70.0, 10.0, 180.0, 0.001},
      {"99 km, sun 20, 9 deg down towards", 99.0, 20.0, -9.0, 0.0, 0.02},
      {"92.55 km, sun 63.88, 1 km above the ground", 92.55, 63.88, -9.6604, 11.8, 0.03},
  };
  for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
    double mu, mu_s, nu;
    view_cosines(views[v].sun, views[v].el, views[v].az, &mu, &mu_s, &nu);
    check_single_lookup(&sky, &a, views[v].name, views[v].h, mu, mu_s, nu, 1e-7, views[v].bound);
  }
  sf_table_set_free(&set);
  return check_summary();
}
