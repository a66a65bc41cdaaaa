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
#endif

void sf_rng_lanes_partners(sf_rng_lanes *lanes, long top, long *partner, long groups) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq")) {
    partners_avx512(lanes, top, partner, groups);
    return;
  }
#endif
  partners_scalar(lanes, top, partner, groups);
}
