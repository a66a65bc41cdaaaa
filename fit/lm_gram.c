/* No contraction into fused multiply-adds: the tiled paths then do the
 * same operations per lane as the plain one (as fit/fit_sky_config.c). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#endif
#include "fit/lm_gram.h"

#include <string.h>

/* The plain loop below, on any CPU; with GCC on x86-64, the tiled ones,
 * picked at run time (the binary is built without -march). AVX2 and
 * AVX-512F without FMA: the same operations per lane, hence the same bits.
 * Measured per entry of a block of 64 rows (one core of a 2-core Xeon with
 * AVX-512, a scratch benchmark; one run each): 193 parameters, plain 7.2
 * ns, AVX2 4.2 ns, AVX-512 3.3 ns; 371 parameters (2-16-16-3), AVX2 5.2
 * ns, AVX-512 3.5 ns. The AVX2 tile compiled for AVX-512 ran no faster
 * (3.9 ns at 193); tiled on SSE2 alone was slower than plain. */
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

static void gram_plain(int P, const double *block, int padded, double *A) {
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

/* Four entries' sums from their half sums h[k] = (l0 + l4, l1 + l5, l2 +
 * l6, l3 + l7), added to A's four at Aij: the additions of entry_sum, by
 * pairwise shuffles. */
__attribute__((always_inline)) static inline void add_four_sums(const lanes4 h[TILE], double *Aij) {
  /* (l0 + l4) + (l2 + l6), (l1 + l5) + (l3 + l7) of entries 0, 1, then 2, 3 */
  lanes4 t0 = SHUFFLE(h[0], h[1], 0, 1, 4, 5) + SHUFFLE(h[0], h[1], 2, 3, 6, 7);
  lanes4 t1 = SHUFFLE(h[2], h[3], 0, 1, 4, 5) + SHUFFLE(h[2], h[3], 2, 3, 6, 7);
  lanes4 sums = SHUFFLE(t0, t1, 0, 2, 4, 6) + SHUFFLE(t0, t1, 1, 3, 5, 7);
  lanes4 row = load4(Aij) + sums;
  memcpy(Aij, &row, sizeof row);
}

/* The entries of a column tile below its diagonal row j0 (rows j0+1..j0+3,
 * i <= j), entry by entry. */
static inline void tile_triangle(int P, const double *block, int padded, int j0, double *A) {
  for (int i = j0 + 1; i < j0 + TILE; ++i)
    for (int j = i; j < j0 + TILE; ++j) add_entry(P, block, padded, i, j, A);
}

/* Columns j_end..P-1, past the last whole tile, entry by entry. */
static inline void columns_past_tiles(int P, const double *block, int padded, int j_end, double *A) {
  for (int i = 0; i < P; ++i)
    for (int j = i > j_end ? i : j_end; j < P; ++j) add_entry(P, block, padded, i, j, A);
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
      add_four_sums(h, A + (size_t)i * P + j0);
    }
    tile_triangle(P, block, padded, j0, A);
  }
  columns_past_tiles(P, block, padded, j0, A);
}

typedef double lanes8 __attribute__((vector_size(64)));

__attribute__((always_inline)) static inline lanes8 load8(const double *p) {
  lanes8 v;
  memcpy(&v, p, sizeof v);
  return v;
}

/* Half sums (l0 + l4, ..., l3 + l7) of an entry's 8 lanes. */
__attribute__((always_inline)) static inline lanes4 halves_added(lanes8 l) {
  lanes4 lo, hi;
  memcpy(&lo, &l, sizeof lo);
  memcpy(&hi, (const double *)&l + 4, sizeof hi);
  return lo + hi;
}

/* AVX-512: an entry's 8 lanes are one register, so a tile is 4 x 4
 * entries, rows i0..i0+3 against columns j0..j0+3 (16 accumulators; 8
 * loads per 8 rows for 16 entries, where the AVX2 tile loads 10 for 4);
 * the rows of a column tile past its last whole 4 x 4 one at a time
 * against its 4 columns; the rest as gram_tiled. */
__attribute__((target("avx512f"))) static void gram_tiled_avx512(int P, const double *block, int padded, double *A) {
  int j0 = 0;
  for (; j0 + TILE <= P; j0 += TILE) {
    const double *bj = block + (size_t)j0 * SF_LM_GRAM_BLOCK;
    int i0 = 0;
    for (; i0 + TILE <= j0 + 1; i0 += TILE) {
      const double *bi = block + (size_t)i0 * SF_LM_GRAM_BLOCK;
      lanes8 acc[TILE][TILE];
      for (int a = 0; a < TILE; ++a)
        for (int k = 0; k < TILE; ++k) acc[a][k] = (lanes8){0};
      for (int r = 0; r < padded; r += 8) {
        lanes8 x[TILE];
        for (int a = 0; a < TILE; ++a) x[a] = load8(bi + a * SF_LM_GRAM_BLOCK + r);
        for (int k = 0; k < TILE; ++k) {
          lanes8 y = load8(bj + k * SF_LM_GRAM_BLOCK + r);
          for (int a = 0; a < TILE; ++a) acc[a][k] += x[a] * y;
        }
      }
      for (int a = 0; a < TILE; ++a) {
        lanes4 h[TILE];
        for (int k = 0; k < TILE; ++k) h[k] = halves_added(acc[a][k]);
        add_four_sums(h, A + (size_t)(i0 + a) * P + j0);
      }
    }
    for (int i = i0; i <= j0; ++i) {
      const double *bi = block + (size_t)i * SF_LM_GRAM_BLOCK;
      lanes8 acc[TILE];
      for (int k = 0; k < TILE; ++k) acc[k] = (lanes8){0};
      for (int r = 0; r < padded; r += 8) {
        lanes8 x = load8(bi + r);
        for (int k = 0; k < TILE; ++k) acc[k] += x * load8(bj + k * SF_LM_GRAM_BLOCK + r);
      }
      lanes4 h[TILE];
      for (int k = 0; k < TILE; ++k) h[k] = halves_added(acc[k]);
      add_four_sums(h, A + (size_t)i * P + j0);
    }
    tile_triangle(P, block, padded, j0, A);
  }
  columns_past_tiles(P, block, padded, j0, A);
}
#endif

int sf_lm_gram_path_available(sf_lm_gram_path p) {
  switch (p) {
    case SF_LM_GRAM_PLAIN: return 1;
#if defined(GRAM_TILED)
    case SF_LM_GRAM_AVX2: return __builtin_cpu_supports("avx2");
    case SF_LM_GRAM_AVX512: return __builtin_cpu_supports("avx512f");
#endif
    default: return 0;
  }
}

void sf_lm_add_block_gram_path(sf_lm_gram_path p, int P, const double *block, int padded, double *A) {
  switch (p) {
#if defined(GRAM_TILED)
    case SF_LM_GRAM_AVX2: gram_tiled(P, block, padded, A); return;
    case SF_LM_GRAM_AVX512: gram_tiled_avx512(P, block, padded, A); return;
#endif
    default: gram_plain(P, block, padded, A); return;
  }
}

void sf_lm_add_block_gram(int P, const double *block, int padded, double *A) {
  sf_lm_gram_path p = sf_lm_gram_path_available(SF_LM_GRAM_AVX512) ? SF_LM_GRAM_AVX512
                      : sf_lm_gram_path_available(SF_LM_GRAM_AVX2) ? SF_LM_GRAM_AVX2
                                                                    : SF_LM_GRAM_PLAIN;
  sf_lm_add_block_gram_path(p, P, block, padded, A);
}
