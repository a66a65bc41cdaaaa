#include "models/rng.h"

/* splitmix64 (Steele, Lea & Flood 2014): the seeding generator that Vigna
 * recommends for xoshiro; one step also serves as a 64-bit mixing hash. */
static uint64_t splitmix64_next(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

void sf_rng_seed_lane(sf_rng *rng, uint64_t seed, uint64_t key_a, uint64_t key_b, unsigned lane) {
  /* Chain the keys through the mixer so that (seed, a, b) and any
   * permutation of them name different streams. */
  uint64_t h = seed;
  uint64_t mixed = splitmix64_next(&h);
  h = mixed ^ key_a;
  mixed = splitmix64_next(&h);
  h = mixed ^ key_b;
  mixed = splitmix64_next(&h);
  /* Lane l's state is splitmix64's outputs 4l .. 4l + 3 from the mixed
   * keys, as Vigna seeds xoshiro; lane 0 is the first four. */
  uint64_t state = mixed + 4u * (uint64_t)lane * 0x9e3779b97f4a7c15u;
  for (int i = 0; i < 4; ++i) rng->s[i] = splitmix64_next(&state);
  if ((rng->s[0] | rng->s[1] | rng->s[2] | rng->s[3]) == 0) rng->s[0] = 1;
}

void sf_rng_seed(sf_rng *rng, uint64_t seed, uint64_t key_a, uint64_t key_b) {
  sf_rng_seed_lane(rng, seed, key_a, key_b, 0);
}
