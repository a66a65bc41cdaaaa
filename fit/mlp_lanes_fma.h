/* a * b + c rounded once (IEEE fused multiply-add) on 8 lanes, for x86
 * CPUs without a multiply-add instruction: the training kernel's baseline
 * build (fit/mlp_kernel_baseline.c), which CPUs without AVX2 and FMA run:
 * Sandy and Ivy Bridge, the Atom-derived Celerons and Pentiums, a virtual
 * machine's default CPU model.
 *
 * Why: there libm's fma is glibc's generic one, which switches the
 * rounding mode and tests the exception flags on every call: 247 ns per
 * call on an Emerald Rapids Xeon with its FMA hidden from glibc
 * (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA), and the baseline kernel
 * took 27 us per sample for the 2-4-3 and 172 us for the 4-8-8-9 (about 3
 * minutes per epoch of the scattering set; a build trains 60). With this:
 * 0.60 and 3.1 us (build/bench_mlp_kernel 4096, the baseline row). Where
 * libm's fma is the instruction (an AMD CPU with FMA but not AVX2) the
 * calls were faster: 0.34 and 1.9 us on that Xeon.
 *
 * How (Boldo & Melquiond, "Emulation of FMA and correctly rounded sums:
 * proved algorithms using rounding to odd", IEEE TC 57(4), 2008, the
 * algorithm glibc's generic fma uses), in round to nearest, in SSE2:
 *   p + pe = a b exactly (Dekker's product, Veltkamp's split);
 *   s + se = p + c exactly (Knuth's TwoSum);
 *   u = RO(se + pe), rounded to odd: the sum rounded toward zero, its last
 *       bit set when inexact (from its TwoSum error, on the bits);
 *   result = RN(s + u), the correctly rounded a b + c.
 * Valid while nothing overflows or underflows: |a|, |b| in [2^-450,
 * 2^500], |c| <= 2^1000, the result normal (|r| >= 2^-1021). a or b zero
 * (and the others finite) is exact as p + c. Other lanes (infinities, NaN,
 * extreme exponents, results that are zero or subnormal: none in training)
 * take libm's fma. The bits are libm's correctly rounded fma's
 * (tests/test_mlp_lanes_fma.c: 14 million triples against it, with
 * cancellations, half-way cases and their neighbours; 400 million more
 * while writing it).
 *
 * Compile without implicit contraction (the kernel turns it off; without
 * an FMA instruction there is none anyway). */
#ifndef SKYFIT_FIT_MLP_LANES_FMA_H
#define SKYFIT_FIT_MLP_LANES_FMA_H

#include <emmintrin.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

typedef double sf_fma_lanes __attribute__((vector_size(64)));

/* Inlined, except under AddressSanitizer (its instrumentation of the
 * baseline kernel with every multiply-add inlined took GCC 110 s to
 * compile, 23 s with libm calls) and where the includer asks for calls
 * (SF_FMA_LANES_CALLED: tests/test_mlp_lanes.c, whose unrolled loops took
 * 330 s at -O3 inlined): a call costs only speed there. */
#if defined(__SANITIZE_ADDRESS__) || defined(SF_FMA_LANES_CALLED)
#define SF_FMA_INLINE static __attribute__((noinline, unused))
#else
#define SF_FMA_INLINE static inline __attribute__((always_inline))
#endif

/* Two lanes of sf_fma_lanes_emulated, in SSE2 instructions (GCC's generic
 * 8-lane vectors turned each comparison into scalar compares and
 * branches). *other gets the movemask of the lanes left to libm. */
SF_FMA_INLINE __m128d sf_fma_2lanes(__m128d a, __m128d b, __m128d c, int *other) {
  const __m128d split = _mm_set1_pd(134217729.0);   /* 2^27 + 1 */
  const __m128d zero = _mm_setzero_pd();
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(INT64_MAX));
  /* Dekker: a b = p + pe, each half of a and b 26 bits at most, so every
   * partial product is exact */
  __m128d p = _mm_mul_pd(a, b);
  __m128d ta = _mm_mul_pd(a, split), tb = _mm_mul_pd(b, split);
  __m128d ah = _mm_sub_pd(ta, _mm_sub_pd(ta, a)), bh = _mm_sub_pd(tb, _mm_sub_pd(tb, b));
  __m128d al = _mm_sub_pd(a, ah), bl = _mm_sub_pd(b, bh);
  __m128d pe = _mm_sub_pd(
      _mm_mul_pd(al, bl),
      _mm_sub_pd(_mm_sub_pd(_mm_sub_pd(p, _mm_mul_pd(ah, bh)), _mm_mul_pd(al, bh)), _mm_mul_pd(ah, bl)));
  /* TwoSum: p + c = s + se */
  __m128d s = _mm_add_pd(p, c);
  __m128d sb = _mm_sub_pd(s, p);
  __m128d se = _mm_add_pd(_mm_sub_pd(p, _mm_sub_pd(s, sb)), _mm_sub_pd(c, sb));
  /* se + pe rounded to odd: w = RN(se + pe), we its error. Inexact (we !=
   * 0): toward zero is w itself when we has w's sign, else the next
   * double toward zero (bits - 1, the same for either sign); then the
   * last bit set. */
  __m128d w = _mm_add_pd(se, pe);
  __m128d wb = _mm_sub_pd(w, se);
  __m128d we = _mm_add_pd(_mm_sub_pd(se, _mm_sub_pd(w, wb)), _mm_sub_pd(pe, wb));
  __m128i inexact = _mm_castpd_si128(_mm_cmpneq_pd(we, zero));
  __m128i toward_zero = _mm_castpd_si128(_mm_xor_pd(_mm_cmplt_pd(we, zero), _mm_cmplt_pd(w, zero)));
  __m128i u = _mm_add_epi64(_mm_castpd_si128(w), _mm_and_si128(inexact, toward_zero));
  u = _mm_or_si128(u, _mm_and_si128(inexact, _mm_set1_epi64x(1)));
  __m128d r = _mm_add_pd(s, _mm_castsi128_pd(u));
  /* a or b zero, the others finite: a b is exactly p (a signed zero) */
  const __m128d largest = _mm_set1_pd(0x1.fffffffffffffp+1023);
  __m128d aa = _mm_and_pd(a, magnitude), ab = _mm_and_pd(b, magnitude), ac = _mm_and_pd(c, magnitude);
  __m128d finite = _mm_and_pd(_mm_and_pd(_mm_cmple_pd(aa, largest), _mm_cmple_pd(ab, largest)),
                              _mm_cmple_pd(ac, largest));
  __m128d zero_product = _mm_and_pd(finite, _mm_or_pd(_mm_cmpeq_pd(aa, zero), _mm_cmpeq_pd(ab, zero)));
  r = _mm_or_pd(_mm_and_pd(zero_product, _mm_add_pd(p, c)), _mm_andnot_pd(zero_product, r));
  /* where the algorithm holds (comparisons are false for NaN) */
  const __m128d tiny = _mm_set1_pd(0x1p-450), huge = _mm_set1_pd(0x1p+500);
  __m128d valid = _mm_and_pd(_mm_and_pd(_mm_cmpge_pd(aa, tiny), _mm_cmple_pd(aa, huge)),
                             _mm_and_pd(_mm_cmpge_pd(ab, tiny), _mm_cmple_pd(ab, huge)));
  valid = _mm_and_pd(valid, _mm_cmple_pd(ac, _mm_set1_pd(0x1p+1000)));
  valid = _mm_and_pd(valid, _mm_cmpge_pd(_mm_and_pd(r, magnitude), _mm_set1_pd(0x1p-1021)));
  *other = 3 & ~_mm_movemask_pd(_mm_or_pd(valid, zero_product));
  return r;
}

SF_FMA_INLINE sf_fma_lanes sf_fma_lanes_emulated(sf_fma_lanes a, sf_fma_lanes b, sf_fma_lanes c) {
  __m128d qa[4], qb[4], qc[4], qr[4];
  memcpy(qa, &a, sizeof a);
  memcpy(qb, &b, sizeof b);
  memcpy(qc, &c, sizeof c);
  int other[4], any = 0;
  for (int q = 0; q < 4; ++q) {
    qr[q] = sf_fma_2lanes(qa[q], qb[q], qc[q], &other[q]);
    any |= other[q];
  }
  sf_fma_lanes r;
  memcpy(&r, qr, sizeof r);
  if (any)
    for (int k = 0; k < 8; ++k)
      if (other[k / 2] >> (k % 2) & 1) r[k] = fma(a[k], b[k], c[k]);
  return r;
}

#endif
