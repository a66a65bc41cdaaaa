/* The polish's block Gram matrix (fit/lm_gram.h): included once by each of
 * fit/lm_gram_{avx512,avx2,baseline}.c, which name it (SF_LM_GRAM_NAME)
 * and are compiled with their instruction set's flags, as the training
 * kernel is (fit/mlp_kernel.h). The operations per lane are the same in
 * all three (fit/mlp_lanes.h), so are the bits; only the tile shape, which
 * changes which entries are computed side by side, follows the registers
 * (SF_LM_GRAM_TILE_ROWS x SF_LM_GRAM_TILE_COLS). */
#ifndef SF_LM_GRAM_NAME
#error "define SF_LM_GRAM_NAME before including fit/lm_gram_body.h"
#endif

#include "fit/lanes_body_prelude.h"

#include "fit/lm_gram.h"
#include "fit/mlp_lanes.h"

#ifndef SF_LM_GRAM_TILE_ROWS
#define SF_LM_GRAM_TILE_ROWS 4
#endif
#ifndef SF_LM_GRAM_TILE_COLS
#define SF_LM_GRAM_TILE_COLS 4
#endif
#define BLOCK SF_LM_GRAM_BLOCK
_Static_assert(BLOCK % SF_LANES == 0, "a block is whole vectors of samples");

/* ((L_0 + L_1) + (L_2 + L_3)) + ((L_4 + L_5) + (L_6 + L_7)) */
static FORCE_INLINE double lanes_total(sf_lanes l) {
  double v[SF_LANES];
  sf_lanes_store(v, l);
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
}

/* One pair of units (u, u'): the rows T_j = G a_l[j] of u's side against
 * the rows a_m[j'] of u''s, and where their entries go in A. Row j of a
 * side of n rows is the parameter weight0 + j, its last row the bias. */
typedef struct unit_pair {
  const double *T, *Y;
  int n_t, n_y;
  int t_weight0, t_bias, y_weight0, y_bias;
  int same_unit;   /* u = u': the entries j <= j' only */
  int vecs;        /* vectors of samples in the block */
  int P;
  double *A;
} unit_pair;

static FORCE_INLINE int parameter(int weight0, int bias, int n, int j) { return j < n - 1 ? weight0 + j : bias; }

/* Entries of rows r0..r0+R-1 of T against rows c0..c0+C-1 of Y: R x C
 * accumulators whose dependency chains run side by side. */
static FORCE_INLINE void tile(const unit_pair *up, int r0, int R, int c0, int C) {
  sf_lanes acc[SF_LM_GRAM_TILE_ROWS][SF_LM_GRAM_TILE_COLS];
  SF_LANES_UNROLL
  for (int r = 0; r < R; ++r) {
    sf_lanes t = sf_lanes_load(up->T + (long)(r0 + r) * BLOCK);
    SF_LANES_UNROLL
    for (int c = 0; c < C; ++c) acc[r][c] = sf_lanes_mul(t, sf_lanes_load(up->Y + (long)(c0 + c) * BLOCK));
  }
  for (int v = 1; v < up->vecs; ++v) {
    sf_lanes y[SF_LM_GRAM_TILE_COLS];
    SF_LANES_UNROLL
    for (int c = 0; c < C; ++c) y[c] = sf_lanes_load(up->Y + (long)(c0 + c) * BLOCK + v * SF_LANES);
    SF_LANES_UNROLL
    for (int r = 0; r < R; ++r) {
      sf_lanes t = sf_lanes_load(up->T + (long)(r0 + r) * BLOCK + v * SF_LANES);
      SF_LANES_UNROLL
      for (int c = 0; c < C; ++c) acc[r][c] = sf_lanes_fma(t, y[c], acc[r][c]);
    }
  }
  SF_LANES_UNROLL
  for (int r = 0; r < R; ++r)
    SF_LANES_UNROLL
    for (int c = 0; c < C; ++c) {
      int j = r0 + r, jj = c0 + c;
      if (up->same_unit && jj < j) continue;
      int p = parameter(up->t_weight0, up->t_bias, up->n_t, j), q = parameter(up->y_weight0, up->y_bias, up->n_y, jj);
      double *entry = p < q ? &up->A[(long)p * up->P + q] : &up->A[(long)q * up->P + p];
      *entry += lanes_total(acc[r][c]);
    }
}

/* Rows r0..r0+R-1 of T against every row of Y (from the diagonal's tile
 * on, for u = u'), the columns left past the whole tiles in one tile of
 * fewer columns: a row of 4 x 1 tiles kept 4 dependency chains in flight,
 * half of what the two multiply-add units need (2-16-16-3: 17 columns). */
static FORCE_INLINE void row_strip(const unit_pair *up, int r0, int R) {
  int c0 = 0;
  for (; c0 + SF_LM_GRAM_TILE_COLS <= up->n_y; c0 += SF_LM_GRAM_TILE_COLS)
    if (!up->same_unit || c0 + SF_LM_GRAM_TILE_COLS > r0) tile(up, r0, R, c0, SF_LM_GRAM_TILE_COLS);
  int rest = up->n_y - c0;
  if (rest == 0 || (up->same_unit && up->n_y <= r0)) return;
  if (SF_LM_GRAM_TILE_COLS > 3 && rest == 3) tile(up, r0, R, c0, 3);
  else if (SF_LM_GRAM_TILE_COLS > 2 && rest == 2) tile(up, r0, R, c0, 2);
  else
    for (; c0 < up->n_y; ++c0) tile(up, r0, R, c0, 1);
}

/* Every entry of a pair: strips of whole tiles' rows, then one strip of
 * the rows left (the first layer's 3 rows of the sky's networks). */
static void pair_entries(const unit_pair *up) {
  int r0 = 0;
  for (; r0 + SF_LM_GRAM_TILE_ROWS <= up->n_t; r0 += SF_LM_GRAM_TILE_ROWS) row_strip(up, r0, SF_LM_GRAM_TILE_ROWS);
  int rest = up->n_t - r0;
  if (SF_LM_GRAM_TILE_ROWS > 3 && rest == 3) row_strip(up, r0, 3);
  else if (SF_LM_GRAM_TILE_ROWS > 2 && rest == 2) row_strip(up, r0, 2);
  else
    for (; r0 < up->n_t; ++r0) row_strip(up, r0, 1);
}

void SF_LM_GRAM_NAME(const sf_mlp_shape *s, const double *g, const double *a, int vecs, double *scratch, double *A) {
  int L = s->n_layers, K = s->sizes[L], P = sf_mlp_param_count(s);
  for (int l = 0; l < L; ++l)
    for (int i = 0; i < s->sizes[l + 1]; ++i) {
      const double *gu = g + (long)sf_lm_gram_unit(s, l, i) * K * BLOCK;
      const double *al = a + (long)sf_lm_gram_input_row(s, l, 0) * BLOCK;
      int n_t = s->sizes[l] + 1;
      for (int m = l; m < L; ++m)
        for (int ii = m == l ? i : 0; ii < s->sizes[m + 1]; ++ii) {
          const double *gv = g + (long)sf_lm_gram_unit(s, m, ii) * K * BLOCK;
          /* T_j = G a_l[j], G = sum_k g_k[u] g_k[u'] */
          for (int v = 0; v < vecs; ++v) {
            sf_lanes G = sf_lanes_mul(sf_lanes_load(gu + v * SF_LANES), sf_lanes_load(gv + v * SF_LANES));
            for (int k = 1; k < K; ++k)
              G = sf_lanes_fma(sf_lanes_load(gu + (long)k * BLOCK + v * SF_LANES),
                               sf_lanes_load(gv + (long)k * BLOCK + v * SF_LANES), G);
            for (int j = 0; j < n_t; ++j)
              sf_lanes_store(scratch + (long)j * BLOCK + v * SF_LANES,
                             sf_lanes_mul(G, sf_lanes_load(al + (long)j * BLOCK + v * SF_LANES)));
          }
          int n_y = s->sizes[m] + 1;
          unit_pair up = {scratch,
                          a + (long)sf_lm_gram_input_row(s, m, 0) * BLOCK,
                          n_t,
                          n_y,
                          sf_mlp_weight_offset(s, l) + i * s->sizes[l],
                          sf_mlp_bias_offset(s, l) + i,
                          sf_mlp_weight_offset(s, m) + ii * s->sizes[m],
                          sf_mlp_bias_offset(s, m) + ii,
                          m == l && ii == i,
                          vecs,
                          P,
                          A};
          pair_entries(&up);
        }
    }
}
