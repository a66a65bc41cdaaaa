/* A small seeded random number generator for Monte Carlo: xoshiro256**
 * (Blackman & Vigna 2018), one independent stream per (seed, stream key)
 * pair so that sample i of a Monte Carlo estimate draws the same numbers
 * whichever thread computes it. The state is a plain value; nothing global. */
#ifndef SKYFIT_MODELS_RNG_H
#define SKYFIT_MODELS_RNG_H

#include <stdint.h>

typedef struct sf_rng {
  uint64_t s[4];
} sf_rng;

/* Starts the stream named by (seed, key_a, key_b): the three are hashed
 * together by splitmix64, which also fills the 256-bit state (never all
 * zero). Different keys give statistically independent streams. */
void sf_rng_seed(sf_rng *rng, uint64_t seed, uint64_t key_a, uint64_t key_b);

/* Stream `lane` of the (seed, key_a, key_b) family: lane 0 is sf_rng_seed's
 * stream, lane l > 0 is seeded from splitmix64's next four outputs after
 * lane l - 1's (models/rng_lanes.h draws eight lanes at once). */
void sf_rng_seed_lane(sf_rng *rng, uint64_t seed, uint64_t key_a, uint64_t key_b, unsigned lane);

static inline uint64_t sf_rng_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

/* Next 64 random bits (xoshiro256**). */
static inline uint64_t sf_rng_next(sf_rng *rng) {
  uint64_t *s = rng->s;
  uint64_t result = sf_rng_rotl(s[1] * 5u, 7) * 9u;
  uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = sf_rng_rotl(s[3], 45);
  return result;
}

/* Uniform double in [0, 1) with 53 random bits: 1 - u is never 0, so
 * -log(1 - u) is always finite. */
static inline double sf_rng_uniform(sf_rng *rng) {
  return (double)(sf_rng_next(rng) >> 11) * 0x1.0p-53;
}

#endif
