#include "models/rng_lanes.h"

#include "models/rng.h"

void sf_rng_lanes_seed(sf_rng_lanes *lanes, uint64_t seed, uint64_t key_a, uint64_t key_b) {
  for (int l = 0; l < SF_RNG_LANES; ++l) {
    sf_rng one;
    sf_rng_seed_lane(&one, seed, key_a, key_b, (unsigned)l);
    for (int w = 0; w < 4; ++w) lanes->s[w][l] = one.s[w];
  }
}

/* Draw k's integer: floor(u * (bound + 1)) capped at bound (u * (bound + 1)
 * can round up to bound + 1 when u is within an ulp of 1). */
static long below_or_at(double u, long bound) {
  long j = (long)(u * (double)(bound + 1));
  return j > bound ? bound : j;
}

/* The eight lanes of sf_rng_next and sf_rng_uniform, one lane at a time. */
static void partners_scalar(sf_rng_lanes *lanes, long top, long *partner, long groups) {
  for (int l = 0; l < SF_RNG_LANES; ++l) {
    sf_rng one = {{lanes->s[0][l], lanes->s[1][l], lanes->s[2][l], lanes->s[3][l]}};
    for (long g = 0; g < groups; ++g) {
      long k = g * SF_RNG_LANES + l;
      partner[k] = below_or_at(sf_rng_uniform(&one), top - k);
    }
    for (int w = 0; w < 4; ++w) lanes->s[w][l] = one.s[w];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

/* The same steps on eight 64-bit lanes of a 512-bit register; the
 * multiplications by 5 and 9 as shifts and adds, the conversions between
 * 64-bit integers and doubles exact (AVX-512DQ; bounds below 2^53), so
 * every bit equals partners_scalar's. */
__attribute__((target("avx512f,avx512dq"))) static void partners_avx512(sf_rng_lanes *lanes, long top,
                                                                         long *partner, long groups) {
  __m512i s0 = _mm512_loadu_si512(lanes->s[0]), s1 = _mm512_loadu_si512(lanes->s[1]);
  __m512i s2 = _mm512_loadu_si512(lanes->s[2]), s3 = _mm512_loadu_si512(lanes->s[3]);
  const __m512d scale = _mm512_set1_pd(0x1.0p-53);
  const __m512i lane_step = _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0);
  for (long g = 0; g < groups; ++g) {
    __m512i times5 = _mm512_add_epi64(_mm512_slli_epi64(s1, 2), s1);
    __m512i rotated = _mm512_rol_epi64(times5, 7);
    __m512i result = _mm512_add_epi64(_mm512_slli_epi64(rotated, 3), rotated);
    __m512i t = _mm512_slli_epi64(s1, 17);
    s2 = _mm512_xor_si512(s2, s0);
    s3 = _mm512_xor_si512(s3, s1);
    s1 = _mm512_xor_si512(s1, s2);
    s0 = _mm512_xor_si512(s0, s3);
    s2 = _mm512_xor_si512(s2, t);
    s3 = _mm512_rol_epi64(s3, 45);
    __m512d u = _mm512_mul_pd(_mm512_cvtepu64_pd(_mm512_srli_epi64(result, 11)), scale);
    __m512i bound = _mm512_sub_epi64(_mm512_set1_epi64(top - g * SF_RNG_LANES), lane_step);
    __m512d count = _mm512_cvtepi64_pd(_mm512_add_epi64(bound, _mm512_set1_epi64(1)));
    __m512i j = _mm512_min_epi64(_mm512_cvttpd_epi64(_mm512_mul_pd(u, count)), bound);
    _mm512_storeu_si512(partner + g * SF_RNG_LANES, j);
  }
  _mm512_storeu_si512(lanes->s[0], s0);
  _mm512_storeu_si512(lanes->s[1], s1);
  _mm512_storeu_si512(lanes->s[2], s2);
  _mm512_storeu_si512(lanes->s[3], s3);
}

/* The same on two 4-lane halves of 256-bit registers. AVX2 has no 64-bit
 * integer to double conversion: the 53 random bits go as two exact 32-bit
 * halves (each or-ed into the mantissa of 2^52 and 2^52 subtracted), and the
 * partners, below 2^31, as 32-bit integers; every operation on doubles is
 * the scalar path's, so are the bits. */
__attribute__((target("avx2"))) static __m256i rotl_avx2(__m256i x, int k) {
  return _mm256_or_si256(_mm256_slli_epi64(x, k), _mm256_srli_epi64(x, 64 - k));
}

__attribute__((target("avx2"))) static __m256d exact_double_avx2(__m256i bits53) {
  const __m256i exponent_2p52 = _mm256_set1_epi64x(0x4330000000000000);
  const __m256d two_p52 = _mm256_set1_pd(0x1.0p52);
  __m256i low = _mm256_and_si256(bits53, _mm256_set1_epi64x(0xffffffff));
  __m256i high = _mm256_srli_epi64(bits53, 32);
  __m256d low_d = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(low, exponent_2p52)), two_p52);
  __m256d high_d = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(high, exponent_2p52)), two_p52);
  return _mm256_add_pd(_mm256_mul_pd(high_d, _mm256_set1_pd(0x1.0p32)), low_d);
}

__attribute__((target("avx2"))) static void partners_avx2(sf_rng_lanes *lanes, long top, long *partner,
                                                          long groups) {
  __m256i s[4][2];
  for (int w = 0; w < 4; ++w)
    for (int h = 0; h < 2; ++h) s[w][h] = _mm256_loadu_si256((const __m256i *)(lanes->s[w] + 4 * h));
  const __m256d scale = _mm256_set1_pd(0x1.0p-53);
  for (long g = 0; g < groups; ++g)
    for (int h = 0; h < 2; ++h) {
      __m256i s0 = s[0][h], s1 = s[1][h], s2 = s[2][h], s3 = s[3][h];
      __m256i times5 = _mm256_add_epi64(_mm256_slli_epi64(s1, 2), s1);
      __m256i rotated = rotl_avx2(times5, 7);
      __m256i result = _mm256_add_epi64(_mm256_slli_epi64(rotated, 3), rotated);
      __m256i t = _mm256_slli_epi64(s1, 17);
      s2 = _mm256_xor_si256(s2, s0);
      s3 = _mm256_xor_si256(s3, s1);
      s1 = _mm256_xor_si256(s1, s2);
      s0 = _mm256_xor_si256(s0, s3);
      s2 = _mm256_xor_si256(s2, t);
      s3 = rotl_avx2(s3, 45);
      s[0][h] = s0, s[1][h] = s1, s[2][h] = s2, s[3][h] = s3;
      __m256d u = _mm256_mul_pd(exact_double_avx2(_mm256_srli_epi64(result, 11)), scale);
      int first = (int)(top - g * SF_RNG_LANES) - 4 * h;
      __m128i bound = _mm_sub_epi32(_mm_set1_epi32(first), _mm_set_epi32(3, 2, 1, 0));
      __m256d count = _mm256_cvtepi32_pd(_mm_add_epi32(bound, _mm_set1_epi32(1)));
      __m128i j = _mm_min_epi32(_mm256_cvttpd_epi32(_mm256_mul_pd(u, count)), bound);
      _mm256_storeu_si256((__m256i *)(partner + g * SF_RNG_LANES + 4 * h), _mm256_cvtepi32_epi64(j));
    }
  for (int w = 0; w < 4; ++w)
    for (int h = 0; h < 2; ++h) _mm256_storeu_si256((__m256i *)(lanes->s[w] + 4 * h), s[w][h]);
}
#endif

int sf_rng_lanes_isa_available(sf_rng_lanes_isa isa) {
  switch (isa) {
    case SF_RNG_LANES_SCALAR: return 1;
#if defined(__x86_64__) && defined(__GNUC__)
    case SF_RNG_LANES_AVX2: return __builtin_cpu_supports("avx2");
    case SF_RNG_LANES_AVX512: return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
#endif
    default: return 0;
  }
}

void sf_rng_lanes_partners_isa(sf_rng_lanes_isa isa, sf_rng_lanes *lanes, long top, long *partner, long groups) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa == SF_RNG_LANES_AVX512) {
    partners_avx512(lanes, top, partner, groups);
    return;
  }
  if (isa == SF_RNG_LANES_AVX2) {
    partners_avx2(lanes, top, partner, groups);
    return;
  }
#endif
  (void)isa;
  partners_scalar(lanes, top, partner, groups);
}

void sf_rng_lanes_partners(sf_rng_lanes *lanes, long top, long *partner, long groups) {
  sf_rng_lanes_isa isa = SF_RNG_LANES_SCALAR;
  if (sf_rng_lanes_isa_available(SF_RNG_LANES_AVX512)) isa = SF_RNG_LANES_AVX512;
  else if (top < 0x7fffffffL && sf_rng_lanes_isa_available(SF_RNG_LANES_AVX2)) isa = SF_RNG_LANES_AVX2;
  sf_rng_lanes_partners_isa(isa, lanes, top, partner, groups);
}
