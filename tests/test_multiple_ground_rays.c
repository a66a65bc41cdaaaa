/* Order 2 of the multiple-scattering table on rays that hit the ground,
 * seen from 10 km looking down (default atmosphere, default tables), against
 * the independent quadrature of tests/order2_reference.h (no tables).
 *
 * Step 3 of data/precompute_multiple.h reads the density G at every node of
 * the view ray; Bruneton's ground half, linear in the distance to the
 * ground, put most downward directions of the low nodes in its first
 * interval (1 km up: mu -1 to -0.36), and G, smooth in mu, was read there
 * as if the ray were steeper: blue -1.5 % (mu -0.5) and -2.8 % (mu -0.7),
 * the sun at mu_s 0.6; -1.4 % and -3.0 % at mu_s 0.2; red -2.5 %..-5.2 %.
 * With G's ground half linear in mu (data/density_mu.h): -0.22 %..-0.51 %
 * at mu -0.5 in every channel, -0.89 %..-1.39 % at mu -0.7, where what is
 * left lies between the grid's two steepest ground samples at 10 km (mu -1
 * and -0.65). All orders against the path tracer (7 orders each, 1.6e7
 * paths, blue, mu -0.5 / -0.7, mu_s 0.6): the sky radiance from -1.00 % /
 * -1.50 % to -0.49 % / -0.67 %.
 *
 * The reference at 8 view nodes, 4 per mu panel and 16 half-azimuths;
 * doubling the mu nodes raises it by at most 0.30 % (red), 0.08 % (blue)
 * at these points, the other two by less than 0.02 %. */
#include <math.h>
#include <stdio.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/atmosphere_file.h"
#include "tests/check.h"
#include "tests/lookup_test_tables.h"
#include "tests/order2_reference.h"

int main(void) {
  sf_atmosphere a;
  sf_table_set set;
  sf_sky_tables sky;
  /* the default resolution (the error is its mu axis'); the multiple
   * table is order 2 alone */
  if (!CHECK(lookup_test_tables("256x64,32x128x32x8", 2, &a, &set, &sky) == 0)) return check_summary();
  const order2_nodes nodes = {8, 4, 16};
  static const struct { const char *name; double h, mu, mu_s, nu, rel_bound; } points[] = {
      {"10 km, mu -0.5, sun mu_s 0.6", 10.0, -0.5, 0.6, 0.1, 0.010},
      {"10 km, mu -0.7, sun mu_s 0.6", 10.0, -0.7, 0.6, 0.1, 0.018},
      {"10 km, mu -0.5, sun mu_s 0.2", 10.0, -0.5, 0.2, 0.3, 0.010},
      {"10 km, mu -0.7, sun mu_s 0.2", 10.0, -0.7, 0.2, 0.3, 0.018},
  };
  for (size_t p = 0; p < sizeof points / sizeof points[0]; ++p)
    check_order2_point(&sky, &a, points[p].name, points[p].h, points[p].mu, points[p].mu_s, points[p].nu, &nodes,
                       points[p].rel_bound);
  sf_table_set_free(&set);
  return check_summary();
}
