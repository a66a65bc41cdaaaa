/* Eight doubles operated on together: the lanes of the training kernel
 * (fit/mlp_kernel_body.h), which takes 8 samples through the network at
 * once.
 *
 * The representation follows the flags the including file is compiled
 * with (fit/mlp_kernel.h compiles the kernel once per instruction set):
 * with AVX2 and FMA (and not AVX-512), two 4-lane registers through
 * intrinsics; otherwise, with GCC or Clang, a generic vector (vector_size
 * 64: one AVX-512 register, or SSE2 registers on the baseline), so an
 * accumulator stays in registers across a loop with a run-time trip count
 * (what plain 8-element arrays did not reliably get); elsewhere a struct of
 * 8 doubles with the same per-lane operations. Every operation is lane-wise
 * IEEE arithmetic, and a multiply-add is fused exactly where written
 * (sf_lanes_fma; the including file turns implicit contraction off), so
 * results are bit for bit the same in every representation.
 *
 * sf_lanes_exp (below) is the kernel's exponential: table-driven, within 1
 * ulp of libm, the same bits in every representation
 * (tests/test_mlp_exp_builds.c). */
#ifndef SKYFIT_FIT_MLP_LANES_H
#define SKYFIT_FIT_MLP_LANES_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#define SF_LANES 8

#if defined(__GNUC__) && !defined(SF_LANES_PORTABLE) && defined(__AVX2__) && defined(__FMA__) && \
    !defined(__AVX512F__)
/* Compiled with AVX2 and FMA (fit/mlp_kernel_avx2.c): two 4-lane registers,
 * lanes 0-3 and 4-7, through intrinsics. GCC's generic 8-lane vectors,
 * wider than any AVX2 register, compiled to scalar compares, inserts and
 * stack spills there (7x slower than AVX-512 per sample). */
#include <immintrin.h>

#define SF_LANES_INLINE __attribute__((always_inline)) static inline
typedef struct sf_lanes {
  __m256d lo, hi;
} sf_lanes;
typedef sf_lanes sf_lanes_mask;   /* all ones or all zeros per lane */

#define SF_LANES_HALVES(name, expr_lo, expr_hi) \
  do {                                           \
    (name).lo = (expr_lo);                       \
    (name).hi = (expr_hi);                       \
  } while (0)

SF_LANES_INLINE sf_lanes sf_lanes_load(const double *p) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_loadu_pd(p), _mm256_loadu_pd(p + 4));
  return r;
}
SF_LANES_INLINE void sf_lanes_store(double *p, sf_lanes v) {
  _mm256_storeu_pd(p, v.lo);
  _mm256_storeu_pd(p + 4, v.hi);
}
SF_LANES_INLINE sf_lanes sf_lanes_set1(double x) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_set1_pd(x), _mm256_set1_pd(x));
  return r;
}
#define SF_LANES_BINARY(name, intrinsic)                              \
  SF_LANES_INLINE sf_lanes name(sf_lanes a, sf_lanes b) {            \
    sf_lanes r;                                                       \
    SF_LANES_HALVES(r, intrinsic(a.lo, b.lo), intrinsic(a.hi, b.hi)); \
    return r;                                                         \
  }
SF_LANES_BINARY(sf_lanes_add, _mm256_add_pd)
SF_LANES_BINARY(sf_lanes_sub, _mm256_sub_pd)
SF_LANES_BINARY(sf_lanes_mul, _mm256_mul_pd)
SF_LANES_BINARY(sf_lanes_div, _mm256_div_pd)
#undef SF_LANES_BINARY
SF_LANES_INLINE sf_lanes sf_lanes_scale(sf_lanes a, double w) { return sf_lanes_mul(a, sf_lanes_set1(w)); }
SF_LANES_INLINE sf_lanes sf_lanes_add_scalar(sf_lanes a, double w) { return sf_lanes_add(a, sf_lanes_set1(w)); }
/* the sign bit flipped, as the generic vectors' -a */
SF_LANES_INLINE sf_lanes sf_lanes_neg(sf_lanes a) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_xor_pd(a.lo, sign), _mm256_xor_pd(a.hi, sign));
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_fmadd_pd(a.lo, b.lo, c.lo), _mm256_fmadd_pd(a.hi, b.hi, c.hi));
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalar(sf_lanes a, double w, sf_lanes c) {
  return sf_lanes_fma(a, sf_lanes_set1(w), c);
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalars(sf_lanes a, double w, double u) {
  return sf_lanes_fma(a, sf_lanes_set1(w), sf_lanes_set1(u));
}
/* c - a * w and u - a * w rounded once, w and u on every lane */
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalar(sf_lanes a, double w, sf_lanes c) {
  const __m256d wv = _mm256_set1_pd(w);
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_fnmadd_pd(a.lo, wv, c.lo), _mm256_fnmadd_pd(a.hi, wv, c.hi));
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalars(sf_lanes a, double w, double u) {
  return sf_lanes_fnma_scalar(a, w, sf_lanes_set1(u));
}
/* ordered, non-signalling: false where either side is NaN, as a < b */
#define SF_LANES_COMPARE(name, predicate)                                                     \
  SF_LANES_INLINE sf_lanes_mask name(sf_lanes a, sf_lanes b) {                               \
    sf_lanes_mask r;                                                                          \
    SF_LANES_HALVES(r, _mm256_cmp_pd(a.lo, b.lo, predicate), _mm256_cmp_pd(a.hi, b.hi, predicate)); \
    return r;                                                                                 \
  }
SF_LANES_COMPARE(sf_lanes_lt, _CMP_LT_OQ)
SF_LANES_COMPARE(sf_lanes_gt, _CMP_GT_OQ)
SF_LANES_COMPARE(sf_lanes_eq, _CMP_EQ_OQ)
#undef SF_LANES_COMPARE
/* m ? a : b, lane by lane */
SF_LANES_INLINE sf_lanes sf_lanes_select(sf_lanes_mask m, sf_lanes a, sf_lanes b) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_blendv_pd(b.lo, a.lo, m.lo), _mm256_blendv_pd(b.hi, a.hi, m.hi));
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_abs(sf_lanes a) {
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(INT64_MAX));
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_and_pd(a.lo, magnitude), _mm256_and_pd(a.hi, magnitude));
  return r;
}
/* a > b ? a : b and a < b ? a : b, lane by lane (b where either is NaN) */
SF_LANES_INLINE sf_lanes sf_lanes_max(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_max_pd(a.lo, b.lo), _mm256_max_pd(a.hi, b.hi));
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_min(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  SF_LANES_HALVES(r, _mm256_min_pd(a.lo, b.lo), _mm256_min_pd(a.hi, b.hi));
  return r;
}
/* The lanes whose bits are table[i & 15], i the bits of idx, lane by lane
 * (four-lane gathers) */
SF_LANES_INLINE sf_lanes sf_lanes_lookup16_bits(const uint64_t table[16], sf_lanes idx) {
  const __m256i low4 = _mm256_set1_epi64x(15);
  const long long *t = (const long long *)table;
  sf_lanes r;
  SF_LANES_HALVES(r,
                  _mm256_castsi256_pd(_mm256_i64gather_epi64(t, _mm256_and_si256(_mm256_castpd_si256(idx.lo), low4), 8)),
                  _mm256_castsi256_pd(_mm256_i64gather_epi64(t, _mm256_and_si256(_mm256_castpd_si256(idx.hi), low4), 8)));
  return r;
}
/* The double whose bits are bits(a) + (bits(b) << 48), mod 2^64, lane by
 * lane. */
SF_LANES_INLINE __m256d sf_lanes_bits_add_shl48_4(__m256d a, __m256d b) {
  return _mm256_castsi256_pd(
      _mm256_add_epi64(_mm256_castpd_si256(a), _mm256_slli_epi64(_mm256_castpd_si256(b), 48)));
}
SF_LANES_INLINE sf_lanes sf_lanes_bits_add_shl48(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  SF_LANES_HALVES(r, sf_lanes_bits_add_shl48_4(a.lo, b.lo), sf_lanes_bits_add_shl48_4(a.hi, b.hi));
  return r;
}
SF_LANES_INLINE double sf_lanes_get(sf_lanes a, int k) {
  double v[SF_LANES];
  sf_lanes_store(v, a);
  return v[k];
}
/* A 4 x 4 block transposed in place (pairs of lanes, then halves). */
SF_LANES_INLINE void sf_lanes_transpose4(__m256d *r0, __m256d *r1, __m256d *r2, __m256d *r3) {
  __m256d t0 = _mm256_unpacklo_pd(*r0, *r1), t1 = _mm256_unpackhi_pd(*r0, *r1);
  __m256d t2 = _mm256_unpacklo_pd(*r2, *r3), t3 = _mm256_unpackhi_pd(*r2, *r3);
  *r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  *r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  *r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  *r3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}
/* v[r][c] becomes v[c][r]: the four 4 x 4 blocks transposed, the two off
 * the diagonal swapped. */
SF_LANES_INLINE void sf_lanes_transpose8(sf_lanes v[8]) {
  sf_lanes_transpose4(&v[0].lo, &v[1].lo, &v[2].lo, &v[3].lo);
  sf_lanes_transpose4(&v[0].hi, &v[1].hi, &v[2].hi, &v[3].hi);
  sf_lanes_transpose4(&v[4].lo, &v[5].lo, &v[6].lo, &v[7].lo);
  sf_lanes_transpose4(&v[4].hi, &v[5].hi, &v[6].hi, &v[7].hi);
  for (int k = 0; k < 4; ++k) {
    __m256d t = v[k].hi;
    v[k].hi = v[k + 4].lo;
    v[k + 4].lo = t;
  }
}
#undef SF_LANES_HALVES
#elif defined(__GNUC__) && !defined(SF_LANES_PORTABLE)
/* Every function taking or returning lanes is inlined (never called), so
 * the vector-argument ABI GCC warns about (-Wpsabi) never applies. */
#pragma GCC diagnostic ignored "-Wpsabi"
#define SF_LANES_INLINE __attribute__((always_inline)) static inline
#if defined(__AVX512F__)
#include <immintrin.h>
#endif
/* x86 (SSE2, as every x86-64) without a multiply-add instruction: exact
 * arithmetic instead of libm's fma (sf_lanes_fma below). */
#if defined(__SSE2__) && !defined(__FMA__) && !defined(__AVX512F__)
#define SF_LANES_FMA_EMULATED 1
#include "fit/mlp_lanes_fma.h"
#endif
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
 * instruction in a function compiled for AVX-512F or FMA (and on CPUs
 * whose base instruction set has it, e.g. AArch64); on the x86-64 baseline
 * by exact arithmetic (fit/mlp_lanes_fma.h), not libm's fma, whose generic
 * version costs 247 ns a call: the same bits either way. The scalar forms
 * below: w (and u) on every lane; fnma: c - a * w and u - a * w rounded
 * once (-a is exact: one negated multiply-add instruction). */
#if defined(SF_LANES_FMA_EMULATED)
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) { return sf_fma_lanes_emulated(a, b, c); }
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalar(sf_lanes a, double w, sf_lanes c) {
  return sf_fma_lanes_emulated(a, sf_lanes_set1(w), c);
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalars(sf_lanes a, double w, double u) {
  return sf_fma_lanes_emulated(a, sf_lanes_set1(w), sf_lanes_set1(u));
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalar(sf_lanes a, double w, sf_lanes c) {
  return sf_fma_lanes_emulated(-a, sf_lanes_set1(w), c);
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalars(sf_lanes a, double w, double u) {
  return sf_fma_lanes_emulated(-a, sf_lanes_set1(w), sf_lanes_set1(u));
}
#else
#if defined(__AVX512F__)
/* The instruction itself: GCC's vectorisation of the lane loop below
 * failed where many accumulators are live (fit/lm_gram_body.h's tiles,
 * built lane by lane with scalar multiply-adds). */
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) {
  return (sf_lanes)_mm512_fmadd_pd((__m512d)a, (__m512d)b, (__m512d)c);
}
#else
SF_LANES_INLINE sf_lanes sf_lanes_fma(sf_lanes a, sf_lanes b, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], b[k], c[k]);
  return r;
}
#endif
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalar(sf_lanes a, double w, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], w, c[k]);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fma_scalars(sf_lanes a, double w, double u) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(a[k], w, u);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalar(sf_lanes a, double w, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(-a[k], w, c[k]);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalars(sf_lanes a, double w, double u) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = __builtin_fma(-a[k], w, u);
  return r;
}
#endif
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
/* a > b ? a : b and a < b ? a : b, lane by lane (b where either is NaN:
 * the x86 instructions' rule, which AVX-512 uses directly) */
SF_LANES_INLINE sf_lanes sf_lanes_max(sf_lanes a, sf_lanes b) {
#if defined(__AVX512F__)
  return (sf_lanes)_mm512_max_pd((__m512d)a, (__m512d)b);
#else
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = a[k] > b[k] ? a[k] : b[k];
  return r;
#endif
}
SF_LANES_INLINE sf_lanes sf_lanes_min(sf_lanes a, sf_lanes b) {
#if defined(__AVX512F__)
  return (sf_lanes)_mm512_min_pd((__m512d)a, (__m512d)b);
#else
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = a[k] < b[k] ? a[k] : b[k];
  return r;
#endif
}
/* The lanes whose bits are table[i & 15], i the bits of idx, lane by lane
 * (AVX-512: one two-register permute, the table in registers) */
SF_LANES_INLINE sf_lanes sf_lanes_lookup16_bits(const uint64_t table[16], sf_lanes idx) {
#if defined(__AVX512F__)
  return (sf_lanes)_mm512_permutex2var_epi64(_mm512_loadu_si512(table), (__m512i)idx, _mm512_loadu_si512(table + 8));
#else
  sf_lanes_bits r;
  for (int k = 0; k < SF_LANES; ++k) r[k] = table[((sf_lanes_bits)idx)[k] & 15];
  return (sf_lanes)r;
#endif
}
/* The double whose bits are bits(a) + (bits(b) << 48), mod 2^64, lane by
 * lane. */
SF_LANES_INLINE sf_lanes sf_lanes_bits_add_shl48(sf_lanes a, sf_lanes b) {
  return (sf_lanes)((sf_lanes_bits)a + ((sf_lanes_bits)b << 48));
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
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalar(sf_lanes a, double w, sf_lanes c) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = fma(-a.v[k], w, c.v[k]);
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_fnma_scalars(sf_lanes a, double w, double u) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = fma(-a.v[k], w, u);
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
SF_LANES_INLINE sf_lanes sf_lanes_max(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] > b.v[k] ? a.v[k] : b.v[k];
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_min(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) r.v[k] = a.v[k] < b.v[k] ? a.v[k] : b.v[k];
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_lookup16_bits(const uint64_t table[16], sf_lanes idx) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) {
    uint64_t u;
    memcpy(&u, &idx.v[k], sizeof u);
    memcpy(&r.v[k], &table[u & 15], sizeof u);
  }
  return r;
}
SF_LANES_INLINE sf_lanes sf_lanes_bits_add_shl48(sf_lanes a, sf_lanes b) {
  sf_lanes r;
  for (int k = 0; k < SF_LANES; ++k) {
    uint64_t u, v;
    memcpy(&u, &a.v[k], sizeof u);
    memcpy(&v, &b.v[k], sizeof v);
    u += v << 48;
    memcpy(&r.v[k], &u, sizeof u);
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

/* The exponential's table: entry j holds the bits of 2^(j/16) (correctly
 * rounded) less j << 48 and 1023 << 52, mod 2^64. Adding to it the low 16
 * bits of 16 (m + 1023) + j, shifted up by 48 (sf_lanes_bits_add_shl48),
 * gives the bits of 2^(j/16) with m added to its exponent: 2^m 2^(j/16)
 * in two integer operations, the table lookup's index being those same
 * bits. (As doubles the entries are meaningless: NaNs and negatives.) */
static const uint64_t sf_lanes_exp2_sixteenths_bits[16] = {
    0x0000000000000000u, 0xffffb5586cf9890fu, 0xffff72b83c7d517bu, 0xffff387a6e756238u,
    0xffff06fe0a31b715u, 0xfffedea64c123422u, 0xfffebfdad5362a27u, 0xfffeab07dd485429u,
    0xfffea09e667f3bcdu, 0xfffea11473eb0187u, 0xfffeace5422aa0dbu, 0xfffec49182a3f090u,
    0xfffee89f995ad3adu, 0xffff199bdd85529cu, 0xffff5818dcfba487u, 0xffffa4afa2a490dau};

#if defined(__clang__)
#define SF_LANES_UNROLL _Pragma("clang loop unroll(full)")
#elif defined(__GNUC__)
#define SF_LANES_UNROLL _Pragma("GCC unroll 16")
#else
#define SF_LANES_UNROLL
#endif

/* e^x on every lane of the n vectors x[0..n-1] (n <= SF_LANES_EXP_MAX, a
 * constant where it is called: the loops unroll and the arrays stay in
 * registers), in place, by a table of 16 (Tang's method): x clamped to
 * [-708, 709] (NaN passes through), x = (16 m + j) ln2/16 + r with |r| <=
 * ln2/32 (Cody & Waite: ln 2 split so that n ln2_hi/16 is exact), then
 *   e^x = 2^m 2^(j/16) (1 + (r + r^2 P(r))),  P(r) = sum_{k=2}^{7} r^(k-2)/k!
 * P by Estrin's scheme (a dependency chain of 3 multiply-adds), 2^m
 * 2^(j/16) by an integer addition to an entry of the table (AVX-512: one
 * permute of two registers; the others a gather or a load per lane). The
 * truncated term r^8/8! is below 1.2e-18; the whole within 1 ulp of libm's
 * exp (tests/test_mlp_lanes.c). About 18 instructions where the degree-13
 * polynomial of a table-free reduction (|r| <= ln2/2) took 31: the kernel
 * is bound by its exponentials. Every multiply-add is fused where written,
 * so the bits are the same in every representation above, and for any n.
 *
 * Each step is taken on all n vectors before the next: their independent
 * dependency chains lie side by side in the instruction stream, and the
 * processor overlaps them without looking far ahead (GCC does not
 * interleave separately inlined exponentials on x86). Measured on a Zen 5,
 * training kernel with 8 at a time against one by one: 2,4,3 full batch
 * 5.2-5.5 -> 4.1-4.4 ns per sample, 2,16,16,3 shuffled 44 -> 35-39.
 *
 * sf_lanes_exp_n_capped clamps x to [-708, cap] instead (cap <= 709, a
 * constant where it is called): the sigmoid's e^-z stays below 2^1010
 * there (fit/mlp_lanes_reciprocal.h). */
#define SF_LANES_EXP_MAX 8
SF_LANES_INLINE void sf_lanes_exp_n_capped(sf_lanes *x, int n, double cap) {
  /* 1.5 * 2^52 rounds to the nearest integer; 1023 * 16 biases m. */
  const double shift = 6755399441055744.0 + 1023.0 * 16.0;
  sf_lanes shifted[SF_LANES_EXP_MAX], r[SF_LANES_EXP_MAX], r2[SF_LANES_EXP_MAX], P[SF_LANES_EXP_MAX];
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) {
    /* max then min: a NaN x is kept by both (the second operand's rule) */
    sf_lanes c = sf_lanes_min(sf_lanes_set1(cap), sf_lanes_max(sf_lanes_set1(-708.0), x[k]));
    /* n = 16 m + j = round(16 c / ln 2); n + 1023 * 16 (>= 25 after the
     * clamps) in the low bits of shifted: j in bits 0..3, m + 1023 above */
    shifted[k] = sf_lanes_fma_scalars(c, 16.0 * 1.4426950408889634074, shift);
    sf_lanes nk = sf_lanes_add_scalar(shifted[k], -shift);
    /* ln 2 = 6.93147180369123816490e-01 (32 significant bits: n times it
     * over 16 is exact) + 1.90821492927058770002e-10 */
    sf_lanes r_hi = sf_lanes_fma_scalar(nk, -6.93147180369123816490e-01 / 16.0, c);
    r[k] = sf_lanes_fma_scalar(nk, -1.90821492927058770002e-10 / 16.0, r_hi);
  }
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) {
    r2[k] = sf_lanes_mul(r[k], r[k]);
    sf_lanes r4 = sf_lanes_mul(r2[k], r2[k]);
    sf_lanes q0 = sf_lanes_fma_scalars(r[k], 1.0 / 6.0, 1.0 / 2.0);
    sf_lanes q1 = sf_lanes_fma_scalars(r[k], 1.0 / 120.0, 1.0 / 24.0);
    sf_lanes q2 = sf_lanes_fma_scalars(r[k], 1.0 / 5040.0, 1.0 / 720.0);
    P[k] = sf_lanes_fma(q2, r4, sf_lanes_fma(q1, r2[k], q0));
  }
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) {
    sf_lanes em1 = sf_lanes_fma(r2[k], P[k], r[k]);   /* e^r - 1 */
    /* t = 2^m 2^(j/16), exact: the clamps keep m in -1022..1022, so its
     * exponent 1023 + m in 1..2045. t (1 + em1) = 2^m 2^(j/16 + r/ln2),
     * 2^(j/16 + r/ln2) in [0.978, 1.96), below 1 only for j = 0, and j >= 9
     * at m = -1022: a normal number, so rounding it once is 2^m times the
     * rounding of 2^(j/16) (1 + em1) (the same bits as scaling after the
     * multiply-add, one operation fewer). A NaN x makes em1 NaN, hence
     * x[k], whatever t its payload made. */
    sf_lanes entry = sf_lanes_lookup16_bits(sf_lanes_exp2_sixteenths_bits, shifted[k]);
    sf_lanes t = sf_lanes_bits_add_shl48(entry, shifted[k]);
    x[k] = sf_lanes_fma(t, em1, t);
  }
}

SF_LANES_INLINE void sf_lanes_exp_n(sf_lanes *x, int n) { sf_lanes_exp_n_capped(x, n, 709.0); }

/* e^x on every lane (sf_lanes_exp_n of one vector). */
SF_LANES_INLINE sf_lanes sf_lanes_exp(sf_lanes x) {
  sf_lanes_exp_n(&x, 1);
  return x;
}

/* out[i] = e^x[i], i < n, x clamped to [-708, cap] (sf_lanes_exp_n_capped),
 * a vector at a time: the exponential of whichever representation the
 * caller is compiled for (tests/test_mlp_exp_builds.c compares them). */
SF_LANES_INLINE void sf_lanes_exp_array(const double *x, double *out, long n, double cap) {
  for (long i = 0; i < n; i += SF_LANES) {
    double v[SF_LANES];
    for (int k = 0; k < SF_LANES; ++k) v[k] = i + k < n ? x[i + k] : 0.0;
    sf_lanes e = sf_lanes_load(v);
    sf_lanes_exp_n_capped(&e, 1, cap);
    sf_lanes_store(v, e);
    for (int k = 0; k < SF_LANES && i + k < n; ++k) out[i + k] = v[k];
  }
}

#endif
