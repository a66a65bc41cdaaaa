/* fit/dataset.h's seeded permutation (the split and every epoch's shuffle):
 * the same permutation as a plain Fisher-Yates whose swap k draws from
 * models/rng.h's scalar stream of lane k % 8 (so the eight-lane generator
 * of models/rng_lanes.h is checked draw by draw), whatever the length
 * around its blocks of prefetched partners; each build of the lanes'
 * partners the CPU runs (scalar, AVX2, AVX-512) the same partners; every
 * index exactly once; and uniform: the 120 orders of 5 items counted over
 * 120000 streams, and where 16 items land, against the chi-square
 * distribution. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/dataset.h"
#include "models/rng.h"
#include "models/rng_lanes.h"
#include "tests/check.h"

/* Durstenfeld's shuffle as written in Knuth (TAOCP 3.4.2, Algorithm P),
 * the eight lanes taken in turn. */
static void reference_shuffle(int *perm, long n, uint64_t seed, uint64_t key_a, uint64_t key_b) {
  sf_rng lane[8];
  for (unsigned l = 0; l < 8; ++l) sf_rng_seed_lane(&lane[l], seed, key_a, key_b, l);
  for (long i = 0; i < n; ++i) perm[i] = (int)i;
  for (long i = n - 1, k = 0; i > 0; --i, ++k) {
    long j = (long)(sf_rng_uniform(&lane[k % 8]) * (double)(i + 1));
    if (j > i) j = i;
    int t = perm[i];
    perm[i] = perm[j];
    perm[j] = t;
  }
}

/* Index of a permutation of 0..4 among the 120 (Lehmer code). */
static int lehmer_index(const int *p) {
  int index = 0;
  for (int i = 0; i < 5; ++i) {
    int smaller = 0;
    for (int j = i + 1; j < 5; ++j) smaller += p[j] < p[i];
    index = index * (5 - i) + smaller;
  }
  return index;
}

/* Partners for i = top, top - 1, ... (down to 1, or `swaps` of them) in
 * blocks of `groups` groups from one build, against Durstenfeld's j from
 * the scalar streams. */
static int partners_match(sf_rng_lanes_isa isa, long top, long swaps, long groups, uint64_t seed) {
  sf_rng lane[SF_RNG_LANES];
  for (unsigned l = 0; l < SF_RNG_LANES; ++l) sf_rng_seed_lane(&lane[l], seed, 1, 2, l);
  sf_rng_lanes lanes;
  sf_rng_lanes_seed(&lanes, seed, 1, 2);
  long block = groups * SF_RNG_LANES, *got = malloc((size_t)block * sizeof(long));
  int same = got != NULL;
  for (long at = top, k = 0; same && at > 0 && k < swaps; at -= block) {
    sf_rng_lanes_partners_isa(isa, &lanes, at, got, groups);
    for (long b = 0; b < block && at - b > 0 && k < swaps; ++b, ++k) {
      long i = at - b, j = (long)(sf_rng_uniform(&lane[k % SF_RNG_LANES]) * (double)(i + 1));
      if (j > i) j = i;
      same &= got[b] == j;
    }
  }
  free(got);
  return same;
}

int main(void) {
  static const sf_rng_lanes_isa isas[] = {SF_RNG_LANES_SCALAR, SF_RNG_LANES_AVX2, SF_RNG_LANES_AVX512};
  static const char *const isa_names[] = {"scalar", "avx2", "avx512f+dq"};
  for (int q = 0; q < 3; ++q) {
    if (!sf_rng_lanes_isa_available(isas[q])) {
      printf("partners, %s: skip: not on this CPU or build\n", isa_names[q]);
      continue;
    }
    /* a large top (the products u (i + 1) near 2^31), small ones, and
     * blocks of 1 and of 5 groups (state carried across calls) */
    int same = partners_match(isas[q], 2000000000L, 1000000, 5, 3) && partners_match(isas[q], 983039, 983039, 1, 4);
    for (long top = 1; top <= 40; ++top) same &= partners_match(isas[q], top, top, 1, (uint64_t)top);
    printf("partners, %s: the scalar streams' draws: %s\n", isa_names[q], same ? "yes" : "no");
    CHECK(same);
  }

  enum { LARGE = 983040 };
  int *got = malloc(LARGE * sizeof(int)), *want = malloc(LARGE * sizeof(int));
  char *seen = calloc(LARGE, 1);
  if (!got || !want || !seen) return 1;

  int same = 1;
  for (long n = 0; n <= 100; ++n)
    for (uint64_t key = 0; key < 3; ++key) {
      sf_dataset_permutation(got, n, 11, key, n);
      reference_shuffle(want, n, 11, key, n);
      same &= n == 0 || memcmp(got, want, (size_t)n * sizeof(int)) == 0;
    }
  sf_dataset_permutation(got, LARGE, 5, 6, 7);
  reference_shuffle(want, LARGE, 5, 6, 7);
  same &= memcmp(got, want, LARGE * sizeof(int)) == 0;
  printf("the same permutation as plain Fisher-Yates, n = 0..100 and %d: %s\n", LARGE, same ? "yes" : "no");
  CHECK(same);

  int each_once = 1;
  for (long i = 0; i < LARGE; ++i) {
    if (got[i] < 0 || got[i] >= LARGE || seen[got[i]]) each_once = 0;
    else seen[got[i]] = 1;
  }
  CHECK(each_once);

  /* Pearson's chi-square over the 120 orders, 119 degrees of freedom: mean
   * 119, sd 15.4; above 200 has probability 4.8e-6. A biased shuffle
   * (j in 0..i-1, Sattolo's cycles only) scores in the hundreds of
   * thousands. */
  enum { DRAWS = 120000 };
  long counts[120] = {0};
  for (uint64_t s = 0; s < DRAWS; ++s) {
    int p[5];
    sf_dataset_permutation(p, 5, 3, 0x73687566ull, s);
    counts[lehmer_index(p)] += 1;
  }
  double chi2 = 0.0, expected = DRAWS / 120.0;
  for (int k = 0; k < 120; ++k) chi2 += (counts[k] - expected) * (counts[k] - expected) / expected;
  printf("orders of 5 over %d streams: chi-square %.1f (119 degrees of freedom; bound 200)\n", DRAWS, chi2);
  CHECK(chi2 < 200.0);

  /* Sixteen items take all eight lanes (15 swaps): where each item lands,
   * 16 x 16 cells over 64000 streams, every row and column a uniform
   * distribution; chi-square over the 256 cells, 225 degrees of freedom
   * (rows and columns sum to the stream count): mean 225, sd 21.2; above
   * 330 has probability below 1e-5. */
  enum { SPREAD = 64000 };
  long lands[16][16] = {{0}};
  for (uint64_t s = 0; s < SPREAD; ++s) {
    int p[16];
    sf_dataset_permutation(p, 16, 9, 0x6c616e65ull, s);
    for (int at = 0; at < 16; ++at) lands[p[at]][at] += 1;
  }
  double chi2_lanes = 0.0, per_cell = SPREAD / 16.0;
  for (int item = 0; item < 16; ++item)
    for (int at = 0; at < 16; ++at)
      chi2_lanes += (lands[item][at] - per_cell) * (lands[item][at] - per_cell) / per_cell;
  printf("where 16 items land over %d streams: chi-square %.1f (225 degrees of freedom; bound 330)\n", SPREAD,
         chi2_lanes);
  CHECK(chi2_lanes < 330.0);

  free(got);
  free(want);
  free(seen);
  return check_summary();
}
