/* Eight xoshiro256** streams (models/rng.h) advanced side by side, for the
 * one place where drawing is the bottleneck: the per-epoch shuffle of an
 * MLP's training set (fit/dataset.c). One stream's state update is a serial
 * chain of about five operations per draw; eight independent lanes fill an
 * AVX-512 register (two AVX2 ones) each step, and a draw then costs a
 * fraction of one.
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

/* The builds of sf_rng_lanes_partners, which picks the fastest the CPU
 * runs; all give the same partners (tests/test_dataset_permutation.c
 * checks each the CPU has). The AVX2 build takes top < 2^31 (an int
 * permutation's), and sf_rng_lanes_partners uses it only then. */
typedef enum sf_rng_lanes_isa { SF_RNG_LANES_SCALAR, SF_RNG_LANES_AVX2, SF_RNG_LANES_AVX512 } sf_rng_lanes_isa;
int sf_rng_lanes_isa_available(sf_rng_lanes_isa isa);
void sf_rng_lanes_partners_isa(sf_rng_lanes_isa isa, sf_rng_lanes *lanes, long top, long *partner, long groups);

#endif
