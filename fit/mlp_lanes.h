/* Eight doubles operated on together: the lanes of the training kernel
 * (fit/mlp_backward.c), which takes 8 samples through the network at once.
 *
 * With GCC or Clang the type is a generic vector (vector_size 64): one
 * AVX-512 register, two AVX2 or four SSE2 registers, whatever the function
 * is compiled for, so an accumulator stays in registers across a loop with
 * a run-time trip count (what plain 8-element arrays did not reliably get).
 * Elsewhere it is a struct of 8 doubles with the same per-lane operations.
 * Every operation is lane-wise IEEE arithmetic, and a multiply-add is
 * fused exactly where written (sf_lanes_fma; the including file turns
 * implicit contraction off), so results are bit for bit the same on every
 * instruction set and in both forms.
 *
 * sf_lanes_exp is fit/exp_lanes.h's exponential with its polynomial
 * evaluated by Estrin's scheme (below): within 2 ulp of libm, not always
 * the same last bit as sf_exp_lanes. */
#ifndef SKYFIT_FIT_MLP_LANES_H
#define SKYFIT_FIT_MLP_LANES_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#define SF_LANES 8

#if defined(__GNUC__) && !defined(SF_LANES_PORTABLE)
/* Every function taking or returning lanes is inlined (never called), so
 * the vector-argument ABI GCC warns about (-Wpsabi) never applies. */
#pragma GCC diagnostic ignored "-Wpsabi"
#define SF_LANES_INLINE __attribute__((always_inline)) static inline
typedef double sf_lanes __attribute__((vector_size(64)));
typedef int64_t sf_lanes_mask __attribute__((vector_size(64)));   /* -1 or 0 per lane */
typedef uint64_t sf_lanes_bits __attribute__((vector_size(64)));

SF_LANES_INLINE sf_lanes sf_lanes_load(const double *p) {
  sf_lanes v;
  memcpy(&v, p, sizeof v);
  return v;
}
SF_LANES_INLINE void sf_lanes_store(double *p, sf_lanes v) { memcpy(p, &v, sizeof v); }
/* x on every lane. (Not the constructor {x, x, ...}: GCC 12 builds that
 * lane by lane in a target_clones function; a scalar operand of a vector
 * operation is broadcast in one instruction, and x * 1 is x exactly.) */
SF_LANES_INLINE sf_lanes sf_lanes_set1(double x) { return (sf_lanes){1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0} * x; }
/* a * w and a + w, w on every lane */
SF_LANES_INLINE sf_lanes sf_lanes_scale(sf_lanes a, double w) { return a * w; }
SF_LANES_INLINE sf_lanes sf_lanes_add_scalar(sf_lanes a, double w) { return a + w; }
SF_LANES_INLINE sf_lanes sf_lanes_add(sf_lanes a, sf_lanes b) { return a + b; }
SF_LANES_INLINE sf_lanes sf_lanes_sub(sf_lanes a, sf_lanes b) { return a - b; }
SF_LANES_INLINE sf_lanes sf_lanes_mul(sf_lanes a, sf_lanes b) { return a * b; }
SF_LANES_INLINE sf_lanes sf_lanes_div(sf_lanes a, sf_lanes b) { return a / b; }
SF_LANES_INLINE sf_lanes sf_lanes_neg(sf_lanes a) { return -a; }
/* a * b + c rounded once (IEEE fused multiply-add), lane by lane: one
 * instruction in a function compiled for AVX-512F or FMA, libm's fma
 * (correctly rounded: the same bits) elsewhere. */
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], b[k], c[k]);
  return r;
}
/* a * w + c rounded once, w on every lane */
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalar(sf_lanes a, double w, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], w, c[k]);
  return r;
}
/* a * w + u rounded once, w and u on every lane */
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalars(sf_lanes a, double w, double u) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], w, u);
  return r;
}
SF_LANES_INLINE sf_lanes_mask sf_lanes_lt(sf_lanes a, sf_lanes b) { return (sf_lanes_mask)(a < b); }
SF_LANES_INLINE sf_lanes_mask sf_lanes_gt(sf_lanes a, sf_lanes b) { return (sf_lanes_mask)(a > b); }
SF_LANES_INLINE sf_lanes_mask sf_lanes_eq(sf_lanes a, sf_lanes b) { return (sf_lanes_mask)(a == b); }
/* m ? a : b, lane by lane */
SF_LANES_INLINE sf_lanes sf_lanes_select(sf_lanes_mask m, sf_lanes a, sf_lanes b) {
  return (sf_lanes)((m & (sf_lanes_mask)a) | (~m & (sf_lanes_mask)b));
}
SF_LANES_INLINE sf_lanes sf_lanes_abs(sf_lanes a) {
  return (sf_lanes)((sf_lanes_bits)a & (UINT64_MAX >> 1));
}
/* The bits of a plus n << 52 (n in the low bits of nb, two's complement). */
SF_LANES_INLINE sf_lanes sf_lanes_add_exponent(sf_lanes a, sf_lanes nb) {
  return (sf_lanes)((sf_lanes_bits)a + ((sf_lanes_bits)nb << 52));
}
SF_LANES_INLINE double sf_lanes_get(sf_lanes a, int k) { return a[k]; }
/* Lanes i0..i7 of the 16 lanes of a then b (constants). */
#if defined(__clang__)
#define SF_LANES_SHUFFLE(a, b, i0, i1, i2, i3, i4, i5, i6, i7) \
  __builtin_shufflevector(a, b, i0, i1, i2, i3, i4, i5, i6, i7)
#else
#define SF_LANES_SHUFFLE(a, b, i0, i1, i2, i3, i4, i5, i6, i7) \
  __builtin_shuffle(a, b, (sf_lanes_mask){i0, i1, i2, i3, i4, i5, i6, i7})
#endif
/* v[r][c] becomes v[c][r]: 8 rows of 8 into 8 columns, in three rounds of
 * two-input shuffles (pairs of lanes, then pairs of pairs, then halves). */
SF_LANES_INLINE void sf_lanes_transpose8(sf_lanes v[8]) {
  sf_lanes t[8], u[8];
  for (int k = 0; k < 8; k += 2) {
    t[k] = SF_LANES_SHUFFLE(v[k], v[k + 1], 0, 8, 2, 10, 4, 12, 6, 14);
    t[k + 1] = SF_LANES_SHUFFLE(v[k], v[k + 1], 1, 9, 3, 11, 5, 13, 7, 15);
  }
  for (int k = 0; k < 8; k += 4) {
    u[k] = SF_LANES_SHUFFLE(t[k], t[k + 2], 0, 1, 8, 9, 4, 5, 12, 13);
    u[k + 1] = SF_LANES_SHUFFLE(t[k + 1], t[k + 3], 0, 1, 8, 9, 4, 5, 12, 13);
    u[k + 2] = SF_LANES_SHUFFLE(t[k], t[k + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    u[k + 3] = SF_LANES_SHUFFLE(t[k + 1], t[k + 3], 2, 3, 10, 11, 6, 7, 14, 15);
  }
  for (int k = 0; k < 4; ++k) {
    v[k] = SF_LANES_SHUFFLE(u[k], u[k + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    v[k + 4] = SF_LANES_SHUFFLE(u[k], u[k + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
}
#else
#define SF_LANES_INLINE static inline
typedef struct sf_lanes {
  double v[SF_LANES];
} sf_lanes;
typedef struct sf_lanes_mask {
  int v[SF_LANES];
} sf_lanes_mask;

SF_LANES_INLINE sf_lanes sf_lanes_load(const double *p) {
  sf_lanes r;
  memcpy(r.v, p, sizeof r.v);
  return r;
}
SF_LANES_INLINE void sf_lanes_store(double *p, sf_lanes v) { memcpy(p, v.v, sizeof v.v); }
SF_LANES_INLINE sf_lanes sf_lanes_set1(double x) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = x;
  return r;
}
#define SF_LANES_BINARY(name, op)                                                 \
  SF_LANES_INLINE sf_lanes name(sf_lanes a, sf_lanes b) {                        \
    sf_lanes r;                                                                   \
    for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] op b.v[k];                 \
    return r;                                                                     \
  }
SF_LANES_BINARY(sf_lanes_add, +)
SF_LANES_BINARY(sf_lanes_sub, -)
SF_LANES_BINARY(sf_lanes_mul, *)
SF_LANES_BINARY(sf_lanes_div, /)
#undef SF_LANES_BINARY
SF_LANES_INLINE sf_lanes sf_lanes_scale(sf_lanes a, double w) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] * w;
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_add_scalar(sf_lanes a, double w) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] + w;
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_neg(sf_lanes a) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = -a.v[k];
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = fma(a.v[k], b.v[k], c.v[k]);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalar(sf_lanes a, double w, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = fma(a.v[k], w, c.v[k]);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalars(sf_lanes a, double w, double u) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = fma(a.v[k], w, u);
  return r;
}
#define SF_LANES_COMPARE(name, op)                                                \
  SF_LANES_INLINE sf_lanes_mask name(sf_lanes a, sf_lanes b) {                   \
    sf_lanes_mask r;                                                              \
    for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] op b.v[k];                 \
    return r;                                                                     \
  }
SF_LANES_COMPARE(sf_lanes_lt, <)
SF_LANES_COMPARE(sf_lanes_gt, >)
SF_LANES_COMPARE(sf_lanes_eq, ==)
#undef SF_LANES_COMPARE
SF_LANES_INLINE sf_lanes sf_lanes_select(sf_lanes_mask m, sf_lanes a, sf_lanes b) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = m.v[k] ? a.v[k] : b.v[k];
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_abs(sf_lanes a) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) {
    uint64_t u;
    memcpy(&u, &a.v[k], sizeof u);
    u &= UINT64_MAX >> 1;
    memcpy(&r.v[k], &u, sizeof u);
  }
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_add_exponent(sf_lanes a, sf_lanes nb) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) {
    uint64_t ua, un;
    memcpy(&ua, &a.v[k], sizeof ua);
    memcpy(&un, &nb.v[k], sizeof un);
    ua += un << 52;
    memcpy(&r.v[k], &ua, sizeof ua);
  }
  return r;
}
SF_LANES_INLINE double sf_lanes_get(sf_lanes a, int k) { return a.v[k]; }
SF_LANES_INLINE void sf_lanes_transpose8(sf_lanes v[8]) {
  for (int r = 0; r < 8; ++r)
    for (int c = r + 1; c < 8; ++c) {
      double t = v[r].v[c];
      v[r].v[c] = v[c].v[r];
      v[c].v[r] = t;
    }
}
#endif

/* e^x on every lane, by fit/exp_lanes.h's method (Cody & Waite reduction
 * to |r| <= ln 2 / 2 with the same constants, the degree-13 Taylor
 * polynomial of e^r, the same clamping to [-708, 709] and NaN passed
 * through) but with the polynomial evaluated as
 *   e^r = 1 + (r + r^2 P(r)),  P(r) = sum_{k=2}^{13} r^(k-2) / k!
 * with P by Estrin's scheme (pairs, then powers r^2, r^4): a dependency
 * chain of 6 multiply-adds instead of Horner's 13, so that a kernel bound
 * by its exponentials runs about twice as fast. Every multiply-add is fused
 * (sf_lanes_fma: half the instructions, one rounding each). The bits may
 * differ from sf_exp_lanes in the last place; the relative error stays
 * within 2 ulp of libm's exp (tests/test_mlp_lanes.c: 1 ulp measured). */
SF_LANES_INLINE sf_lanes sf_lanes_exp(sf_lanes x) {
  const sf_lanes lo = sf_lanes_set1(-708.0), hi = sf_lanes_set1(709.0);
  const double shift = 6755399441055744.0;   /* 1.5 * 2^52: round to nearest integer */
  sf_lanes c = sf_lanes_select(sf_lanes_lt(x, lo), lo, x);
  c = sf_lanes_select(sf_lanes_gt(c, hi), hi, c);
  sf_lanes shifted = sf_lanes_fma_scalars(c, 1.4426950408889634074, shift);
  sf_lanes n = sf_lanes_add_scalar(shifted, -shift);
  /* ln 2 = 6.93147180369123816490e-01 (32 significant bits: n ln2_hi is
   * exact) + 1.90821492927058770002e-10 */
  sf_lanes r_hi = sf_lanes_fma_scalar(n, -6.93147180369123816490e-01, c);
  sf_lanes r = sf_lanes_fma_scalar(n, -1.90821492927058770002e-10, r_hi);
  sf_lanes r2 = sf_lanes_mul(r, r), r4 = sf_lanes_mul(r2, r2);
  sf_lanes q0 = sf_lanes_fma_scalars(r, 1.0 / 6.0, 1.0 / 2.0);
  sf_lanes q1 = sf_lanes_fma_scalars(r, 1.0 / 120.0, 1.0 / 24.0);
  sf_lanes q2 = sf_lanes_fma_scalars(r, 1.0 / 5040.0, 1.0 / 720.0);
  sf_lanes q3 = sf_lanes_fma_scalars(r, 1.0 / 362880.0, 1.0 / 40320.0);
  sf_lanes q4 = sf_lanes_fma_scalars(r, 1.0 / 39916800.0, 1.0 / 3628800.0);
  sf_lanes q5 = sf_lanes_fma_scalars(r, 1.0 / 6227020800.0, 1.0 / 479001600.0);
  sf_lanes s0 = sf_lanes_fma(q1, r2, q0);
  sf_lanes s1 = sf_lanes_fma(q3, r2, q2);
  sf_lanes s2 = sf_lanes_fma(q5, r2, q4);
  sf_lanes P = sf_lanes_fma(r4, sf_lanes_fma(s2, r4, s1), s0);
  sf_lanes p = sf_lanes_add_scalar(sf_lanes_fma(r2, P, r), 1.0);
  /* times 2^n: n (two's complement, |n| <= 1023) is in the low bits of shifted */
  sf_lanes e = sf_lanes_add_exponent(p, shifted);
  return sf_lanes_select(sf_lanes_eq(x, x), e, x);
}

#endif
