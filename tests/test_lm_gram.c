/* The polish's block Gram matrix (fit/lm_gram.h), two ways:
 *  - bit for bit against its documented order of operations, written out
 *    here one entry at a time with libm's fma (correctly rounded), for every
 *    build this CPU can run (baseline, AVX2+FMA, AVX-512F) and the one it
 *    picks;
 *  - against J^T J summed in long double from the Jacobian rows written
 *    out explicitly, one per sample and output (entry (u, j) = g_k[u]
 *    a_l[j]), which checks the Kronecker folding and where each entry goes
 *    (biases after their layer's weights, the upper triangle only).
 * Shapes of one to three layers, widths below, at and around the tiles'
 * multiples, one to nine outputs; full blocks, partial ones and a single
 * sample; a sum already in A, below the diagonal untouched. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/lm_gram.h"
#include "models/rng.h"
#include "tests/check.h"

#define BLOCK SF_LM_GRAM_BLOCK

static int parameter(const sf_mlp_shape *s, int l, int i, int j) {
  return j < s->sizes[l] ? sf_mlp_weight_offset(s, l) + i * s->sizes[l] + j : sf_mlp_bias_offset(s, l) + i;
}

/* The documented order (fit/lm_gram.h), entry by entry. */
static void documented_gram(const sf_mlp_shape *s, const double *g, const double *a, int n, double *A) {
  int L = s->n_layers, K = s->sizes[L], P = sf_mlp_param_count(s), padded = (n + 7) / 8 * 8;
  for (int l = 0; l < L; ++l)
    for (int i = 0; i < s->sizes[l + 1]; ++i)
      for (int m = l; m < L; ++m)
        for (int ii = m == l ? i : 0; ii < s->sizes[m + 1]; ++ii) {
          const double *gu = g + (long)sf_lm_gram_unit(s, l, i) * K * BLOCK;
          const double *gv = g + (long)sf_lm_gram_unit(s, m, ii) * K * BLOCK;
          for (int j = 0; j <= s->sizes[l]; ++j)
            for (int jj = m == l && ii == i ? j : 0; jj <= s->sizes[m]; ++jj) {
              const double *al = a + (long)sf_lm_gram_input_row(s, l, j) * BLOCK;
              const double *am = a + (long)sf_lm_gram_input_row(s, m, jj) * BLOCK;
              double lane[8];
              for (int smp = 0; smp < padded; ++smp) {
                double G = gu[smp] * gv[smp];
                for (int k = 1; k < K; ++k) G = fma(gu[k * BLOCK + smp], gv[k * BLOCK + smp], G);
                double T = G * al[smp];
                lane[smp % 8] = smp < 8 ? T * am[smp] : fma(T, am[smp], lane[smp % 8]);
              }
              double sum = ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
              int p = parameter(s, l, i, j), q = parameter(s, m, ii, jj);
              A[p < q ? (long)p * P + q : (long)q * P + p] += sum;
            }
        }
}

/* sum over samples and outputs of row row^T, the rows written out. */
static void explicit_gram(const sf_mlp_shape *s, const double *g, const double *a, int n, long double *exact,
                          long double *scale) {
  int L = s->n_layers, K = s->sizes[L], P = sf_mlp_param_count(s);
  double *row = calloc((size_t)P, sizeof(double));
  for (int smp = 0; smp < n; ++smp)
    for (int k = 0; k < K; ++k) {
      for (int l = 0; l < L; ++l)
        for (int i = 0; i < s->sizes[l + 1]; ++i)
          for (int j = 0; j <= s->sizes[l]; ++j)
            row[parameter(s, l, i, j)] = g[((long)sf_lm_gram_unit(s, l, i) * K + k) * BLOCK + smp] *
                                         a[(long)sf_lm_gram_input_row(s, l, j) * BLOCK + smp];
      for (int p = 0; p < P; ++p)
        for (int q = p; q < P; ++q) {
          long double prod = (long double)row[p] * row[q];
          exact[(long)p * P + q] += prod;
          scale[(long)p * P + q] += fabsl(prod);
        }
    }
  free(row);
}

int main(void) {
  static const sf_mlp_shape shapes[] = {
      {1, {5, 2}, SF_ACT_SIGMOID, SF_ACT_LINEAR},       {2, {2, 4, 3}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG},
      {2, {3, 5, 1}, SF_ACT_TANH, SF_ACT_LINEAR},        {3, {2, 16, 16, 3}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG_EXP},
      {3, {4, 8, 8, 9}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG}, {3, {2, 7, 9, 2}, SF_ACT_SIGMOID, SF_ACT_SIGMOID},
  };
  static const int counts[] = {BLOCK, BLOCK - 3, 13, 1};
  static const sf_mlp_isa isas[] = {SF_MLP_ISA_BASELINE, SF_MLP_ISA_AVX2_FMA, SF_MLP_ISA_AVX512};
  enum { N_SHAPES = sizeof shapes / sizeof shapes[0], N_COUNTS = sizeof counts / sizeof counts[0], N_ISAS = 3 };
  char ran[96] = "";
  for (int b = 0; b < N_ISAS; ++b)
    if (sf_mlp_isa_available(isas[b]))
      snprintf(ran + strlen(ran), sizeof ran - strlen(ran), "%s%s", ran[0] ? ", " : "", sf_mlp_isa_name(isas[b]));
  sf_rng rng;
  sf_rng_seed(&rng, 3, 0x6772616dull, 0);   /* "gram" */
  int all_same = 1, below_kept = 1;
  double worst_rel = 0.0;
  for (int sh = 0; sh < N_SHAPES; ++sh)
    for (int c = 0; c < N_COUNTS; ++c) {
      const sf_mlp_shape *s = &shapes[sh];
      int n = counts[c], K = s->sizes[s->n_layers], P = sf_mlp_param_count(s);
      long g_rows = (long)sf_lm_gram_units(s) * K, a_rows = sf_lm_gram_input_rows(s);
      double *g = malloc(sizeof(double) * g_rows * BLOCK), *a = malloc(sizeof(double) * a_rows * BLOCK);
      double *scratch = malloc(sizeof(double) * sf_lm_gram_scratch_size(s));
      size_t bytes = sizeof(double) * (size_t)P * P;
      double *start = malloc(bytes), *want = malloc(bytes), *got = malloc(bytes);
      long double *exact = calloc((size_t)P * P, sizeof(long double)), *scale = calloc((size_t)P * P, sizeof(long double));
      /* g over orders of magnitude and signs, zero past the n samples (to
       * the next multiple of 8); a finite everywhere, 1 on the bias rows */
      for (long r = 0; r < g_rows; ++r)
        for (int smp = 0; smp < BLOCK; ++smp)
          g[r * BLOCK + smp] = smp < n ? (2.0 * sf_rng_uniform(&rng) - 1.0) * exp(6.0 * sf_rng_uniform(&rng) - 3.0) : 0.0;
      for (long r = 0; r < a_rows; ++r)
        for (int smp = 0; smp < BLOCK; ++smp) a[r * BLOCK + smp] = 2.0 * sf_rng_uniform(&rng) - 1.0;
      for (int l = 0; l < s->n_layers; ++l)
        for (int smp = 0; smp < n; ++smp) a[(long)sf_lm_gram_input_row(s, l, s->sizes[l]) * BLOCK + smp] = 1.0;
      for (int k = 0; k < P * P; ++k) start[k] = sf_rng_uniform(&rng) - 0.5;
      memcpy(want, start, bytes);
      documented_gram(s, g, a, n, want);
      memcpy(got, start, bytes);
      sf_lm_add_block_gram(s, g, a, n, scratch, got);
      int same = memcmp(got, want, bytes) == 0;
      for (int b = 0; b < N_ISAS; ++b) {
        if (!sf_mlp_isa_available(isas[b])) continue;
        double *by_isa = malloc(bytes);
        memcpy(by_isa, start, bytes);
        sf_lm_add_block_gram_isa(isas[b], s, g, a, n, scratch, by_isa);
        if (memcmp(by_isa, want, bytes))
          printf("  %s: shape %d, %d samples differs from the documented order\n", sf_mlp_isa_name(isas[b]), sh, n);
        same &= memcmp(by_isa, want, bytes) == 0;
        free(by_isa);
      }
      all_same &= same;
      explicit_gram(s, g, a, n, exact, scale);
      for (int p = 0; p < P; ++p)
        for (int q = 0; q < P; ++q) {
          long k = (long)p * P + q;
          if (q < p) {
            below_kept &= got[k] == start[k];
            continue;
          }
          long double added = (long double)got[k] - (long double)start[k];
          double rel = (double)(fabsl(added - exact[k]) / (scale[k] + fabs(start[k])));
          if (rel > worst_rel) worst_rel = rel;
        }
      free(g); free(a); free(scratch); free(start); free(want); free(got); free(exact); free(scale);
    }
  printf("block Gram, %d shapes x %d sample counts, builds %s and the one picked: bit for bit the documented order: "
         "%s; worst error against the explicit rows' long double sum %.3g (of the sum of |products| and |the sum before|); below the "
         "diagonal untouched: %s\n",
         (int)N_SHAPES, (int)N_COUNTS, ran, all_same ? "yes" : "no", worst_rel, below_kept ? "yes" : "no");
  CHECK(all_same);
  CHECK(below_kept);
  CHECK(worst_rel < 1e-13);
  return check_summary();
}
