/* Eight xoshiro256** streams (models/rng.h) advanced side by side, for the
 * one place where drawing is the bottleneck: the per-epoch shuffle of an
 * MLP's training set (fit/dataset.c). One stream's state update is a serial
 * chain of about five operations per draw; eight independent lanes fill a
 * vector register each step, and a draw then costs a fraction of one.
 *
 * Draw k of a sequence comes from lane k % 8, its (k / 8)-th value;
 * lane l is the scalar stream sf_rng_seed_lane(seed, key_a, key_b, l), so
 * lane 0 is sf_rng_seed's stream and any draw can be checked against
 * models/rng.h alone. */
#ifndef SKYFIT_MODELS_RNG_LANES_H
#define SKYFIT_MODELS_RNG_LANES_H

#include <stdint.h>

#define SF_RNG_LANES 8

typedef struct sf_rng_lanes {
  uint64_t s[4][SF_RNG_LANES]; /* state word w of lane l at s[w][l] */
} sf_rng_lanes;

/* Lane l starts as sf_rng_seed_lane(seed, key_a, key_b, l). */
void sf_rng_lanes_seed(sf_rng_lanes *lanes, uint64_t seed, uint64_t key_a, uint64_t key_b);

/* Fisher-Yates swap partners for i = top, top - 1, ...: writes `groups` *
 * SF_RNG_LANES integers, partner[k] uniform in 0 .. top - k, as
 *   j = (long)(u * (double)(top - k + 1)), capped at top - k,
 * with u = sf_rng_uniform from draw k (lane k % 8, its (k / 8)-th value).
 * Entries past i = 0 (top - k < 0) are to be ignored. top < 2^53. */
void sf_rng_lanes_partners(sf_rng_lanes *lanes, long top, long *partner, long groups);

#endif
