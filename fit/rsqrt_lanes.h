/* 1/sqrt(x) in plain IEEE double arithmetic that a compiler can vectorise.
 * libm's sqrt is not: C's errno (set for x < 0) makes GCC guard each call
 * with a branch to libm, and a loop with that branch stays scalar (the sky
 * fits' residual kernels, fit/fit_sky_config.c, take a 1/den^(3/2) per
 * sample).
 *
 * Method: the exponent-halving initial guess y0 = bits(0x5FE6EB50C7B537A9 -
 * bits(x) / 2) (relative error < 3.5e-2, Lomont 2003 for the double
 * constant), then Newton steps y <- y (3/2 - x y^2 / 2), whose relative error
 * goes e -> 3/2 e^2: 3.5e-2, 1.8e-3, 4.9e-6, 3.6e-11, then the last step in
 * the form y + y (1/2 - x/2 y^2), whose small correction keeps rounding
 * within 1 ulp (2 ulp for x < 2 DBL_MIN, where x/2 is subnormal;
 * tests/test_rsqrt_lanes.c measures it against 1 / sqrtl). Valid for normal positive finite x; anything else (0, negative,
 * subnormal, infinite, NaN) gives NaN, which the callers treat as a failed
 * evaluation. No branches, no table, no libm call: every lane does the same
 * operations in the same order. */
#ifndef SKYFIT_FIT_RSQRT_LANES_H
#define SKYFIT_FIT_RSQRT_LANES_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

static inline double sf_rsqrt_lanes(double x) {
  uint64_t bits;
  memcpy(&bits, &x, sizeof bits);
  bits = UINT64_C(0x5FE6EB50C7B537A9) - (bits >> 1);
  double y;
  memcpy(&y, &bits, sizeof y);
  const double half_x = 0.5 * x;
  y = y * (1.5 - half_x * y * y);
  y = y * (1.5 - half_x * y * y);
  y = y * (1.5 - half_x * y * y);
  y = y + y * (0.5 - half_x * y * y);
  y = x >= DBL_MIN ? y : NAN;
  return x <= DBL_MAX ? y : NAN;
}

#endif
