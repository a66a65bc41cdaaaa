/* 1/d on the lanes without the divider, rounded exactly as the division
 * 1.0 / d is: for the sigmoids of the training kernel's AVX-512 build for
 * Intel cores (fit/mlp_kernel_avx512_newton.c), whose 8-lane division
 * takes the divider 16 cycles while the rest of a sigmoid needs about 10
 * of the two multiply-add ports. Only for fit/mlp_lanes.h's AVX-512
 * representation (one zmm register).
 *
 * Method (Markstein's reciprocal iteration: P. Markstein, IBM J. Res. Dev.
 * 34(1), 1990; u = 2^-53):
 *   y0 = vrcp14pd(d)              relative error |e0| < 2^-14 (the bound
 *                                 Intel's and AMD's manuals give; its
 *                                 exact bits are neither's promise)
 *   y <- y + y RN(1 - d y)        twice, each two multiply-adds; a step
 *                                 takes |e| to at most (e^2 + u e (1 + e))
 *                                 (1 + u) + u, so |e1| < 2^-28 (1 + 2^-24)
 *                                 and |e2| < 1.126 u
 *   y3 = y2 + y2 RN(1 - d y2)     = RN(1/d), but for one significand.
 * Why y3 is the division's result: scale d into [1, 2), d = B 2^-52 with B
 * a 53-bit integer, 1/d in (1/2, 1], y2 = Y 2^-53. Then 1 - d y2 = (2^105
 * - B Y) 2^-105 with |1 - d y2| = |e2| < 2^-52: an integer below 2^53
 * times a power of two, so RN(1 - d y2) = -e2 exactly, and the last
 * multiply-add rounds y2 (1 - e2) = (1/d)(1 - e2^2) once. That rounds
 * otherwise than 1/d only if a midpoint m between two doubles lies in
 * [(1/d)(1 - e2^2), 1/d) (1/d is never one): 0 < 1 - d m <= e2^2 < 1.27
 * 2^-106. With m = M 2^-54, M odd (midpoints of 1/d's binade), 1 - d m =
 * (2^106 - B M) 2^-106, so B M = 2^106 - 1 = (2^53 - 1)(2^53 + 1). Of the
 * 64 divisors of 2^106 - 1 (its prime factors: 3, 107, 6361, 69431,
 * 20394401, 28059810762433) only B = 2^53 - 1 lies in [2^52, 2^53) with a
 * cofactor in (2^53, 2^54): d = (2 - 2^-52) 2^k, significand all ones.
 * There 1/d = 2^-(k+1) (1 + 2^-53 + 2^-106 + ...) lies just above a
 * midpoint, RN(1/d) is 2^-(k+1) (1 + 2^-52), and y3 is that or 2^-(k+1):
 * the last bit of y3 is set on those lanes. So the bits are the divider's
 * on every CPU, whatever vrcp14pd returns within its bound
 * (tests/test_mlp_lanes_reciprocal.c compares them with 1.0 / d on the
 * hard cases: all-ones significands, and d = 2 - a 2^-52 for odd a, whose
 * 1/d lies a^2 2^-106 from a midpoint).
 *
 * Domain: 1 <= d <= 2^1020, where 1/d and every step stay normal (the
 * kernel's sigmoid: d = 1 + e^-z with e^-z capped at e^700 < 2^1010); NaN
 * gives NaN. */
#ifndef SKYFIT_FIT_MLP_LANES_RECIPROCAL_H
#define SKYFIT_FIT_MLP_LANES_RECIPROCAL_H

#if !defined(__AVX512F__) || !defined(__GNUC__) || defined(SF_LANES_PORTABLE)
#error "fit/mlp_lanes_reciprocal.h is for fit/mlp_lanes.h's AVX-512 representation"
#endif

#include <immintrin.h>

#include "fit/mlp_lanes.h"

/* d[k] = 1/d[k] on every lane of the n vectors d[0..n-1] (n <=
 * SF_LANES_EXP_MAX, a constant where it is called), each step on all n
 * before the next (their chains side by side, as sf_lanes_exp_n's). The
 * two Newton steps and the last one are the loop's three. */
SF_LANES_INLINE void sf_lanes_reciprocal_n(sf_lanes *d, int n) {
  const __m512d one = _mm512_set1_pd(1.0);
  const __m512i significand = _mm512_set1_epi64(INT64_C(0x000FFFFFFFFFFFFF));
  __m512d y[SF_LANES_EXP_MAX];
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) y[k] = _mm512_rcp14_pd((__m512d)d[k]);
  SF_LANES_UNROLL
  for (int step = 0; step < 3; ++step)
    SF_LANES_UNROLL
    for (int k = 0; k < n; ++k) {
      __m512d r = _mm512_fnmadd_pd((__m512d)d[k], y[k], one);   /* RN(1 - d y) */
      y[k] = _mm512_fmadd_pd(y[k], r, y[k]);
    }
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) {
    __m512i bits = _mm512_castpd_si512((__m512d)d[k]);
    /* d's significand all ones: RN(1/d) has its last bit set */
    __mmask8 all_ones = _mm512_cmpeq_epi64_mask(_mm512_and_si512(bits, significand), significand);
    __m512i yb = _mm512_castpd_si512(y[k]);
    d[k] = (sf_lanes)_mm512_castsi512_pd(_mm512_mask_or_epi64(yb, all_ones, yb, _mm512_set1_epi64(1)));
  }
}

#endif
