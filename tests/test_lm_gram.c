/* The polish's block Gram matrix (fit/lm_gram.h) against the sums written
 * out in its documented order, bit for bit, and against a long double sum
 * (loosely: a wrong entry, not rounding), for parameter counts below,
 * at and around multiples of its 4-column tiles and for full and partial
 * blocks of rows; entries below the diagonal untouched. Every path this
 * CPU can run (plain, tiled for AVX2, tiled for AVX-512F), and the one it
 * picks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/lm_gram.h"
#include "models/rng.h"
#include "tests/check.h"

/* A[i][j] += ((l0 + l4) + (l2 + l6)) + ((l1 + l5) + (l3 + l7)), lane l the
 * products of rows l, l + 8, ... in order. */
static void reference_gram(int P, const double *block, int padded, double *A) {
  for (int i = 0; i < P; ++i)
    for (int j = i; j < P; ++j) {
      double l[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (int r = 0; r < padded; r += 8)
        for (int k = 0; k < 8; ++k) l[k] += block[i * SF_LM_GRAM_BLOCK + r + k] * block[j * SF_LM_GRAM_BLOCK + r + k];
      A[i * P + j] += ((l[0] + l[4]) + (l[2] + l[6])) + ((l[1] + l[5]) + (l[3] + l[7]));
    }
}

int main(void) {
  static const int sizes[] = {1, 5, 8, 9, 16, 27, 31, 123, 193, 371};
  static const int rows[] = {8, 40, 64};
  sf_rng rng;
  sf_rng_seed(&rng, 3, 0x6772616dull, 0);   /* "gram" */
  static const sf_lm_gram_path paths[] = {SF_LM_GRAM_PLAIN, SF_LM_GRAM_AVX2, SF_LM_GRAM_AVX512};
  static const char *const path_names[] = {"plain", "AVX2", "AVX-512F"};
  enum { N_SIZES = sizeof sizes / sizeof sizes[0], N_PATHS = sizeof paths / sizeof paths[0] };
  char ran[64] = "";
  for (int p = 0; p < N_PATHS; ++p)
    if (sf_lm_gram_path_available(paths[p]))
      snprintf(ran + strlen(ran), sizeof ran - strlen(ran), "%s%s", ran[0] ? ", " : "", path_names[p]);
  CHECK(sf_lm_gram_path_available(SF_LM_GRAM_PLAIN));
  int all_same = 1;
  double worst_rel = 0.0;
  for (int s = 0; s < N_SIZES; ++s)
    for (int q = 0; q < 3; ++q) {
      int P = sizes[s], padded = rows[q];
      size_t bytes = sizeof(double) * (size_t)P * P;
      double *block = malloc(sizeof(double) * (size_t)P * SF_LM_GRAM_BLOCK);
      double *got = malloc(bytes), *want = malloc(bytes), *start = malloc(bytes), *by_path = malloc(bytes);
      for (int k = 0; k < P * SF_LM_GRAM_BLOCK; ++k) block[k] = (2.0 * sf_rng_uniform(&rng) - 1.0) * exp(8.0 * sf_rng_uniform(&rng) - 4.0);
      /* a sum already there (the previous blocks'), also below the diagonal */
      for (int k = 0; k < P * P; ++k) start[k] = sf_rng_uniform(&rng) - 0.5;
      memcpy(got, start, bytes);
      memcpy(want, start, bytes);
      sf_lm_add_block_gram(P, block, padded, got);
      reference_gram(P, block, padded, want);
      int same = memcmp(got, want, bytes) == 0;
      for (int p = 0; p < N_PATHS; ++p) {
        if (!sf_lm_gram_path_available(paths[p])) continue;
        memcpy(by_path, start, bytes);
        sf_lm_add_block_gram_path(paths[p], P, block, padded, by_path);
        int path_same = memcmp(by_path, want, bytes) == 0;
        if (!path_same) printf("  %s: P %d, %d rows differs from the documented order\n", path_names[p], P, padded);
        same &= path_same;
      }
      /* want's lower triangle is start's: every path left it alone */
      all_same &= same;
      CHECK(same);
      for (int i = 0; i < P; ++i)
        for (int j = i; j < P; ++j) {
          long double exact = 0.0L, scale = 0.0L;
          for (int r = 0; r < padded; ++r) {
            long double p = (long double)block[i * SF_LM_GRAM_BLOCK + r] * block[j * SF_LM_GRAM_BLOCK + r];
            exact += p;
            scale += fabsl(p);
          }
          long double added = (long double)got[i * P + j] - (long double)start[i * P + j];
          double rel = (double)(fabsl(added - exact) / (scale + 1.0L));
          if (rel > worst_rel) worst_rel = rel;
        }
      free(block);
      free(got);
      free(want);
      free(start);
      free(by_path);
    }
  printf("block Gram, %d sizes x 3 row counts, paths %s and the one picked: bit for bit the documented order: %s; worst "
         "error against a long double sum %.3g (of the sum of |products| + 1)\n",
         (int)N_SIZES, ran, all_same ? "yes" : "no", worst_rel);
  CHECK(worst_rel < 1e-13);
  return check_summary();
}
