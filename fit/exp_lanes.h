/* e^x in plain IEEE double arithmetic that a compiler can vectorise: the
 * training kernels (fit/mlp_backward.c) evaluate thousands of exponentials
 * per mini-batch, and libm's exp is a scalar call, the largest cost of a
 * sigmoid network's epoch.
 *
 * Method (Cody & Waite range reduction, as fdlibm's e_exp.c):
 *   n = round(x / ln 2)                 (by the 1.5 * 2^52 shift: exact,
 *                                        round to nearest, no conversion)
 *   r = (x - n ln2_hi) - n ln2_lo,      |r| <= ln 2 / 2, ln2_hi has 32
 *                                        significant bits so n ln2_hi is exact
 *   e^r = sum_{k=0}^{13} r^k / k!       (truncation < 5e-18 relative)
 *   e^x = e^r 2^n                       (n added to the exponent bits)
 * Relative error <= 2 ulp over the clamped range (tests/test_exp_lanes.c
 * measures it against libm). Inputs are clamped to [-708, 709]: e^x then
 * never overflows nor goes subnormal (e^-708 = 3.3e-308 stands for anything
 * smaller, e^709 = 8.2e307 for anything larger: in training both mean a
 * saturated unit or a diverged run, which the caller detects from the loss);
 * NaN stays NaN. No branches, no table, no libm call: every lane does the
 * same operations in the same order, so a vectorised loop gives bit for bit
 * the scalar result on any vector width. */
#ifndef SKYFIT_FIT_EXP_LANES_H
#define SKYFIT_FIT_EXP_LANES_H

#include <stdint.h>
#include <string.h>

static inline double sf_exp_lanes(double x) {
  const double log2e = 1.4426950408889634074;
  const double ln2_hi = 6.93147180369123816490e-01; /* fdlibm: 32 significant bits */
  const double ln2_lo = 1.90821492927058770002e-10;
  const double shift = 6755399441055744.0;          /* 1.5 * 2^52 */
  double c = x < -708.0 ? -708.0 : x;
  c = c > 709.0 ? 709.0 : c;
  double shifted = c * log2e + shift;
  double n = shifted - shift;
  double r = (c - n * ln2_hi) - n * ln2_lo;
  double p = 1.0 / 6227020800.0;                    /* 1/13! */
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  /* The low bits of shifted hold n (two's complement, |n| <= 1023). */
  uint64_t nbits, pbits;
  memcpy(&nbits, &shifted, sizeof nbits);
  memcpy(&pbits, &p, sizeof pbits);
  pbits += nbits << 52;
  double e;
  memcpy(&e, &pbits, sizeof e);
  return x == x ? e : x;
}

#endif
