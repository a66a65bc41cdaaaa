/* fit/rsqrt_lanes.h against 1/sqrt in long double (rounded to double):
 * error in units in the last place over the range the Hosek fits use
 * (1 + H^2 - 2 H cos gamma for H in [-2, 2]: about [1e-4, 9]) and over
 * the whole normal range, exact powers of 4, and NaN for everything
 * outside the normal positive range. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "fit/rsqrt_lanes.h"
#include "tests/check.h"

static double ulp_error(double x) {
  double want = (double)(1.0L / sqrtl((long double)x));
  double ulp = nextafter(want, INFINITY) - want;
  return fabs(sf_rsqrt_lanes(x) - want) / ulp;
}

int main(void) {
  double fit_range = 0.0, whole = 0.0, lowest = 0.0;
  for (int i = 0; i <= 2000000; ++i) fit_range = fmax(fit_range, ulp_error(1e-4 + 9.0 * i / 2000000));
  /* every binade of the normal range, 2000 mantissas each (xorshift) */
  uint64_t s = 88172645463325252u;
  for (int e = -1021; e <= 1023; ++e)
    for (int k = 0; k < 2000; ++k) {
      s ^= s << 13;
      s ^= s >> 7;
      s ^= s << 17;
      double err = ulp_error(ldexp(1.0 + (double)(s >> 11) * 0x1.0p-53, e - 1));
      /* in the lowest binade x/2 is subnormal and loses a bit */
      if (e == -1021) lowest = fmax(lowest, err);
      else whole = fmax(whole, err);
    }
  printf("worst error vs 1/sqrtl: [1e-4, 9] %.3g ulp, normal range above 2 DBL_MIN %.3g ulp, "
         "[DBL_MIN, 2 DBL_MIN) %.3g ulp\n", fit_range, whole, lowest);
  CHECK(fit_range <= 1.0);
  CHECK(whole <= 1.0);
  CHECK(lowest <= 2.0);
  CHECK(sf_rsqrt_lanes(1.0) == 1.0);
  CHECK(sf_rsqrt_lanes(4.0) == 0.5);
  CHECK(sf_rsqrt_lanes(0.25) == 2.0);
  CHECK(isnan(sf_rsqrt_lanes(0.0)));
  CHECK(isnan(sf_rsqrt_lanes(-1.0)));
  CHECK(isnan(sf_rsqrt_lanes(DBL_MIN / 4)));
  CHECK(isnan(sf_rsqrt_lanes(INFINITY)));
  CHECK(isnan(sf_rsqrt_lanes(NAN)));
  return check_summary();
}
