/* No contraction into fused multiply-adds: the AVX2 path then does the
 * same operations per lane as the plain one (as fit/fit_sky_config.c). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#endif
#include "fit/lm_gram.h"

#include <string.h>

/* The plain loop below, on any CPU; with AVX2 (and GCC on x86-64), the
 * tiled one, picked at run time (the binary is built without -march).
 * AVX2 without FMA: the same operations per lane, hence the same bits.
 * Measured per entry of a 193-parameter block of 64 rows, on a 2-core
 * Xeon (AVX-512): plain 7.2 ns, tiled 3.8 ns (the same code for AVX-512
 * ran no faster: 3.9 ns); tiled on SSE2 alone was slower than plain. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GRAM_TILED 1
#endif

/* Entry (i, j) of a block's Gram matrix: ((l0 + l4) + (l2 + l6)) + ((l1 +
 * l5) + (l3 + l7)), lane k the products of rows k, k + 8, ... in order (GCC
 * vectorises the lanes). */
static inline double entry_sum(const double *bi, const double *bj, int padded) {
  double l[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (int r = 0; r < padded; r += 8)
    for (int k = 0; k < 8; ++k) l[k] += bi[r + k] * bj[r + k];
  return ((l[0] + l[4]) + (l[2] + l[6])) + ((l[1] + l[5]) + (l[3] + l[7]));
}

static inline void add_entry(int P, const double *block, int padded, int i, int j, double *A) {
  A[(size_t)i * P + j] += entry_sum(block + (size_t)i * SF_LM_GRAM_BLOCK, block + (size_t)j * SF_LM_GRAM_BLOCK, padded);
}

void sf_lm_add_block_gram_plain(int P, const double *block, int padded, double *A) {
  for (int i = 0; i < P; ++i)
    for (int j = i; j < P; ++j) add_entry(P, block, padded, i, j, A);
}

#if defined(GRAM_TILED)
/* The 8 lanes of an entry's sum as two halves of 4 (lanes 0-3, 4-7), an
 * AVX2 register each (GCC's 8-lane generic vectors, wider than an AVX2
 * register, spilled there: 3x slower than the plain loop). The helpers are
 * always inlined into the AVX2 function, so the vector-argument ABI GCC
 * warns about (-Wpsabi) never applies. */
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double lanes4 __attribute__((vector_size(32)));
typedef long long lanes4_index __attribute__((vector_size(32)));
#define SHUFFLE(a, b, ...) __builtin_shuffle(a, b, (lanes4_index){__VA_ARGS__})
#define TILE 4

__attribute__((always_inline)) static inline lanes4 load4(const double *p) {
  lanes4 v;
  memcpy(&v, p, sizeof v);
  return v;
}

/* Columns j0..j0+3 together, down rows 0..j0: their 4 rows of B (2 KiB)
 * stay in L1 while B[i] streams past (the whole block, P x 64 doubles, is
 * an L2 load per entry otherwise); their sums are independent dependency
 * chains, and the four entries' lanes are added together, the same
 * additions as entry_sum by pairwise shuffles. The rest of the triangle,
 * and columns past the last tile, entry by entry. */
__attribute__((target("avx2"))) static void gram_tiled(int P, const double *block, int padded, double *A) {
  int j0 = 0;
  for (; j0 + TILE <= P; j0 += TILE) {
    const double *bj = block + (size_t)j0 * SF_LM_GRAM_BLOCK;
    for (int i = 0; i <= j0; ++i) {
      const double *bi = block + (size_t)i * SF_LM_GRAM_BLOCK;
      lanes4 lo[TILE], hi[TILE];
      for (int k = 0; k < TILE; ++k) lo[k] = hi[k] = (lanes4){0};
      for (int r = 0; r < padded; r += 8) {
        lanes4 x_lo = load4(bi + r), x_hi = load4(bi + r + 4);
        for (int k = 0; k < TILE; ++k) {
          lo[k] += x_lo * load4(bj + k * SF_LM_GRAM_BLOCK + r);
          hi[k] += x_hi * load4(bj + k * SF_LM_GRAM_BLOCK + r + 4);
        }
      }
      lanes4 h[TILE];   /* l0 + l4, l1 + l5, l2 + l6, l3 + l7 per entry */
      for (int k = 0; k < TILE; ++k) h[k] = lo[k] + hi[k];
      /* (l0 + l4) + (l2 + l6), (l1 + l5) + (l3 + l7) of entries 0, 1, then 2, 3 */
      lanes4 t0 = SHUFFLE(h[0], h[1], 0, 1, 4, 5) + SHUFFLE(h[0], h[1], 2, 3, 6, 7);
      lanes4 t1 = SHUFFLE(h[2], h[3], 0, 1, 4, 5) + SHUFFLE(h[2], h[3], 2, 3, 6, 7);
      lanes4 sums = SHUFFLE(t0, t1, 0, 2, 4, 6) + SHUFFLE(t0, t1, 1, 3, 5, 7);
      double *Aij = A + (size_t)i * P + j0;
      lanes4 row = load4(Aij) + sums;
      memcpy(Aij, &row, sizeof row);
    }
    for (int i = j0 + 1; i < j0 + TILE; ++i)
      for (int j = i; j < j0 + TILE; ++j) add_entry(P, block, padded, i, j, A);
  }
  for (int i = 0; i < P; ++i)
    for (int j = i > j0 ? i : j0; j < P; ++j) add_entry(P, block, padded, i, j, A);
}
#endif

void sf_lm_add_block_gram(int P, const double *block, int padded, double *A) {
#if defined(GRAM_TILED)
  if (__builtin_cpu_supports("avx2")) {
    gram_tiled(P, block, padded, A);
    return;
  }
#endif
  sf_lm_add_block_gram_plain(P, block, padded, A);
}
