/* fit/exp_lanes.h against libm's exp: error in units in the last place
 * over the whole clamped range and near 0 (where the sigmoid and exp(-x)
 * outputs of the networks live), the clamps, NaN passing through. */
#include <math.h>
#include <stdio.h>

#include "fit/exp_lanes.h"
#include "tests/check.h"

static double ulp_error(double got, double want) {
  double ulp = nextafter(want, INFINITY) - want;
  return fabs(got - want) / ulp;
}

static double worst_ulp(double lo, double hi, int n) {
  double worst = 0.0;
  for (int i = 0; i <= n; ++i) {
    double x = lo + (hi - lo) * i / n;
    worst = worst_of(worst, ulp_error(sf_exp_lanes(x), exp(x)));
  }
  return worst;
}

int main(void) {
  double whole = worst_ulp(-708.0, 709.0, 2000003);
  double near0 = worst_ulp(-20.0, 20.0, 1000003);
  double tiny = worst_ulp(-1e-6, 1e-6, 100001);
  printf("worst error vs libm exp: [-708, 709] %.3g ulp, [-20, 20] %.3g ulp, [-1e-6, 1e-6] %.3g ulp\n", whole, near0,
         tiny);
  CHECK(whole <= 2.0);
  CHECK(near0 <= 2.0);
  CHECK(tiny <= 1.0);
  CHECK(sf_exp_lanes(0.0) == 1.0);
  /* clamps: finite, never 0 or inf */
  CHECK_REL(sf_exp_lanes(-1000.0), exp(-708.0), 1e-15);
  CHECK_REL(sf_exp_lanes(1000.0), exp(709.0), 1e-15);
  CHECK(isnan(sf_exp_lanes(NAN)));
  return check_summary();
}
