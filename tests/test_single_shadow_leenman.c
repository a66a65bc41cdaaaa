/* The single scattering looked up from Leenman-parameterised tables (seed
 * 000 §9.1: cosines linear; default resolution) with the sun low, against
 * the exact single-scattering quadrature (tests/exact_single_radiance.h).
 * The lookup divides the samples by the ray's sunlit air F
 * (data/sunlit_ray.h) and multiplies back. F had taken its sun and view
 * transmittances from Leenman's table, whose linear mu cannot follow T
 * near the horizontal, and 19 of these 21 values were off by more than 2 %:
 * 0.9 km looking 10.8 deg down towards a sun 0.57 deg below the horizon
 * +244 / +2878 / +512007 % (r / g / b), 0.4 km 1.5 deg down +311 / +3783 /
 * +745133 %, 20 km zenith -14 / -28 / -60 %. F now integrates the
 * reference optical depth with these tables: all within 0.32 %. */
#include "tests/check.h"
#include "tests/lookup_test_tables.h"

#define REL_BOUND 0.02

int main(void) {
  sf_atmosphere a;
  sf_table_set set;
  sf_sky_tables sky;
  /* single scattering alone */
  if (!CHECK(lookup_test_tables_of(SF_PARAM_LEENMAN, "256x64,32x128x32x8", 1, &a, &set, &sky) == 0))
    return check_summary();
  /* elevation and azimuth from the sun in degrees */
  static const struct { const char *name; double h, sun, el, az; } views[] = {
      {"0.9 km, sun -0.57, 10.8 deg down towards", 0.9, -0.57, -10.8, 8.6},
      {"0.9 km, sun -0.29, 10.8 deg down towards", 0.9, -0.29, -10.8, 8.6},
      {"0.9 km, sun 0, 10.8 deg down towards", 0.9, 0.0, -10.8, 8.6},
      {"0.4 km, sun -0.35, 1.5 deg down away", 0.4, -0.35, -1.5, 135.0},
      {"ground, sun 0.5, 1 deg up away", 0.0, 0.5, 1.0, 180.0},
      {"20 km, sun -8, zenith", 20.0, -8.0, 90.0, 0.0},
      {"20 km, sun -8, 30 deg up towards", 20.0, -8.0, 30.0, 0.0},
  };
  for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
    double mu, mu_s, nu;
    view_cosines(views[v].sun, views[v].el, views[v].az, &mu, &mu_s, &nu);
    check_single_lookup(&sky, &a, views[v].name, views[v].h, mu, mu_s, nu, 1e-6, REL_BOUND);
  }
  sf_table_set_free(&set);
  return check_summary();
}
