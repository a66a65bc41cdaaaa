/* The training kernel (fit/mlp_kernel.h): included once by each of
 * fit/mlp_kernel_{avx512,avx512_newton,avx2,baseline}.c, which name it
 * (SF_MLP_KERNEL_NAME) and are compiled with their instruction set's flags.
 * The operations per lane are the same in all four (the Newton build's
 * reciprocals round as the division does): multiply-adds fused where the
 * code says so (sf_lanes_fma: an instruction with AVX-512F or FMA; on the
 * x86-64 baseline exact arithmetic with the correctly rounded result,
 * fit/mlp_lanes_fma.h) and nowhere else, hence the same results. */
#ifndef SF_MLP_KERNEL_NAME
#error "define SF_MLP_KERNEL_NAME before including fit/mlp_kernel_body.h"
#endif

#include "fit/lanes_body_prelude.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fit/mlp_kernel.h"
#include "fit/mlp_lanes.h"
#if defined(SF_MLP_SIGMOID_NEWTON)
#include "fit/mlp_lanes_reciprocal.h"
#endif

/* The sigmoid's e^-z is capped at e^700: any z < -700 gives 1 / (1 +
 * e^700) = 9.9e-305 (the exponential's own cap, e^709, gave down to
 * 1.2e-308, a subnormal 1/d). Its denominators stay in
 * sf_lanes_reciprocal_n's domain; the same cap on every build. */
#define SIGMOID_EXP_CAP 700.0

/* d[k] = 1 / d[k] for the n vectors of a pass (1 <= d <= 1 + e^700). With
 * SF_MLP_SIGMOID_NEWTON (fit/mlp_kernel_avx512_newton.c) the even vectors
 * by multiply-adds (fit/mlp_lanes_reciprocal.h), the odd ones by the
 * divider, which works beside the multiply-add ports: the same bits as
 * dividing all. */
static FORCE_INLINE void reciprocals_n(sf_lanes *d, int n) {
  const sf_lanes one = sf_lanes_set1(1.0);
#if defined(SF_MLP_SIGMOID_NEWTON)
  sf_lanes even[SF_LANES_EXP_MAX];
  SF_LANES_UNROLL
  for (int k = 0; 2 * k < n; ++k) even[k] = d[2 * k];
  sf_lanes_reciprocal_n(even, (n + 1) / 2);
  SF_LANES_UNROLL
  for (int k = 0; 2 * k < n; ++k) d[2 * k] = even[k];
  SF_LANES_UNROLL
  for (int k = 1; k < n; k += 2) d[k] = sf_lanes_div(one, d[k]);
#else
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) d[k] = sf_lanes_div(one, d[k]);
#endif
}

/* Whether f starts with e^-z (the sigmoid, exp(-z), exp(-exp(-z))):
 * forward_rows_f hands it -z. */
static FORCE_INLINE int takes_negated(sf_mlp_activation f) {
  return f == SF_ACT_SIGMOID || f == SF_ACT_EXP_NEG || f == SF_ACT_EXP_NEG_EXP;
}

/* z[k] = f(z[k]) on the lanes of the n vectors of a pass (sf_mlp_activate's
 * formulas; tanh through libm), their exponentials side by side
 * (sf_lanes_exp_n); where takes_negated(f), z[k] holds -z. n a constant
 * where it is called. */
static FORCE_INLINE void activate_n(sf_mlp_activation f, sf_lanes *z, int n) {
  const sf_lanes zero = sf_lanes_set1(0.0), one = sf_lanes_set1(1.0);
  SF_LANES_UNROLL
  for (int k = 0; k < n; ++k) {
    if (f == SF_ACT_TANH) {
      double v[LANES];
      sf_lanes_store(v, z[k]);
      for (int i = 0; i < LANES; ++i) v[i] = tanh(v[i]);
      z[k] = sf_lanes_load(v);
    }
    if (f == SF_ACT_RELU) z[k] = sf_lanes_select(sf_lanes_gt(z[k], zero), z[k], zero);
  }
  if (f == SF_ACT_SIGMOID) sf_lanes_exp_n_capped(z, n, SIGMOID_EXP_CAP);
  if (f == SF_ACT_EXP_NEG || f == SF_ACT_EXP_NEG_EXP) sf_lanes_exp_n(z, n);
  if (f == SF_ACT_EXP_NEG_EXP) {
    SF_LANES_UNROLL
    for (int k = 0; k < n; ++k) z[k] = sf_lanes_neg(z[k]);
    sf_lanes_exp_n(z, n);
  }
  if (f == SF_ACT_SIGMOID) {
    SF_LANES_UNROLL
    for (int k = 0; k < n; ++k) z[k] = sf_lanes_add(one, z[k]);
    reciprocals_n(z, n);
  }
}

/* f'(z) from a = f(z), on the lanes. */
static FORCE_INLINE sf_lanes slope(sf_mlp_activation f, sf_lanes a) {
  const sf_lanes zero = sf_lanes_set1(0.0), one = sf_lanes_set1(1.0);
  switch (f) {
    case SF_ACT_SIGMOID: return sf_lanes_mul(a, sf_lanes_sub(one, a));
    case SF_ACT_TANH: return sf_lanes_sub(one, sf_lanes_mul(a, a));
    case SF_ACT_RELU: return sf_lanes_select(sf_lanes_gt(a, zero), one, zero);
    case SF_ACT_LINEAR: return one;
    case SF_ACT_EXP_NEG: return sf_lanes_neg(a);
    /* d/dz exp(-exp(-z)) = a exp(-z) = -a log a */
    case SF_ACT_EXP_NEG_EXP: {
      double v[LANES];
      sf_lanes_store(v, a);
      for (int k = 0; k < LANES; ++k) v[k] = v[k] > 0.0 ? -v[k] * log(v[k]) : 0.0;
      return sf_lanes_load(v);
    }
  }
  return one;
}

/* Fixed-order sum of the lanes. */
static FORCE_INLINE double lane_sum(const double *acc) {
  return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
}

_Static_assert(ROWS * VECS <= SF_LANES_EXP_MAX, "forward_rows_f takes the exponentials of ROWS VECS vectors at once");

/* out_r = f(W_r . a + b_r) for rows r = r0..r0+nr-1 of a layer (nr <= ROWS)
 * and the GROUP samples of a group (a: row j at a + j as), the nr VECS
 * accumulators in registers across the inputs j. (The unrolled loops over
 * q and v keep arrays indexed by them in registers.) */
static FORCE_INLINE void forward_rows_f(sf_mlp_activation f, const double *W, const double *b, int ni, int r0,
                                        int nr, const double *a, long as, double *restrict out) {
  sf_lanes z[ROWS * VECS];   /* row r0 + q, vector v at z[q VECS + v] */
  /* z = b + w_0 a_0 + w_1 a_1 + ..., added in this order, each term fused.
   * Where takes_negated(f), -z instead: -b - w_0 a_0 - w_1 a_1 - ..., each
   * step the negation of z's (round to nearest is symmetric; at most a
   * zero's sign differs, and e^0 = e^-0), in negated multiply-adds: the
   * negation costs no instruction. */
  const int negated = takes_negated(f);
  SF_LANES_UNROLL
  for (int q = 0; q < nr; ++q)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) {
      sf_lanes a0 = sf_lanes_load(a + v * LANES);
      double w = W[(long)(r0 + q) * ni], bias = b[r0 + q];
      z[q * VECS + v] = negated ? sf_lanes_fnma_scalars(a0, w, -bias) : sf_lanes_fma_scalars(a0, w, bias);
    }
  for (int j = 1; j < ni; ++j)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) {
      sf_lanes aj = sf_lanes_load(a + j * as + v * LANES);
      SF_LANES_UNROLL
      for (int q = 0; q < nr; ++q) {
        double w = W[(long)(r0 + q) * ni + j];
        sf_lanes *zq = &z[q * VECS + v];
        *zq = negated ? sf_lanes_fnma_scalar(aj, w, *zq) : sf_lanes_fma_scalar(aj, w, *zq);
      }
    }
  activate_n(f, z, nr * VECS);
  SF_LANES_UNROLL
  for (int q = 0; q < nr; ++q)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) sf_lanes_store(out + (r0 + q) * GROUP + v * LANES, z[q * VECS + v]);
}

static FORCE_INLINE void forward_layer_f(sf_mlp_activation f, const double *W, const double *b, int ni, int no,
                                         const double *a, long as, double *restrict out) {
  int r = 0;
  for (; r + ROWS <= no; r += ROWS) forward_rows_f(f, W, b, ni, r, ROWS, a, as, out);
  for (; r < no; ++r) forward_rows_f(f, W, b, ni, r, 1, a, as, out);
}

static FORCE_INLINE void forward_layer(sf_mlp_activation f, const double *W, const double *b, int ni, int no,
                                       const double *a, long as, double *out) {
  switch (f) {
    case SF_ACT_SIGMOID: forward_layer_f(SF_ACT_SIGMOID, W, b, ni, no, a, as, out); break;
    case SF_ACT_TANH: forward_layer_f(SF_ACT_TANH, W, b, ni, no, a, as, out); break;
    case SF_ACT_RELU: forward_layer_f(SF_ACT_RELU, W, b, ni, no, a, as, out); break;
    case SF_ACT_LINEAR: forward_layer_f(SF_ACT_LINEAR, W, b, ni, no, a, as, out); break;
    case SF_ACT_EXP_NEG: forward_layer_f(SF_ACT_EXP_NEG, W, b, ni, no, a, as, out); break;
    case SF_ACT_EXP_NEG_EXP: forward_layer_f(SF_ACT_EXP_NEG_EXP, W, b, ni, no, a, as, out); break;
  }
}

/* Residual e and de/dpred of one output on the lanes (residual above). */
static FORCE_INLINE sf_lanes residual_lanes(sf_mlp_loss_kind kind, double delta, sf_lanes pred, sf_lanes target,
                                            sf_lanes *de) {
  switch (kind) {
    case SF_LOSS_REL: {
      sf_lanes w = sf_lanes_div(sf_lanes_set1(1.0), sf_lanes_add_scalar(sf_lanes_abs(target), delta));
      *de = w;
      return sf_lanes_mul(sf_lanes_sub(pred, target), w);
    }
    case SF_LOSS_LOG: {
      double p[LANES], t[LANES], e[LANES], d[LANES];
      sf_lanes_store(p, pred);
      sf_lanes_store(t, target);
      for (int k = 0; k < LANES; ++k) e[k] = residual(SF_LOSS_LOG, delta, p[k], t[k], &d[k]);
      *de = sf_lanes_load(d);
      return sf_lanes_load(e);
    }
    default:
      *de = sf_lanes_set1(1.0);
      return sf_lanes_sub(pred, target);
  }
}

/* Per-sample squared residuals summed over the outputs (sq[v]), and d =
 * dLoss/dz of the output layer, for the GROUP samples of a group. */
static FORCE_INLINE void output_delta_f(sf_mlp_activation f, sf_mlp_loss_kind kind, const sf_mlp_loss *loss,
                                        int n_out, const double *pred, const double *target, long ts, sf_lanes *sq,
                                        double *restrict d) {
  const double two_inv_n = 2.0 * (1.0 / n_out);
  /* summed in registers (summed in *sq, they were a chain of stores and
   * reloads across the outputs) */
  sf_lanes sums[VECS];
  SF_LANES_UNROLL
  for (int v = 0; v < VECS; ++v) sums[v] = sf_lanes_set1(0.0);
  for (int r = 0; r < n_out; ++r) {
    const double delta = kind == SF_LOSS_MSE ? 0.0 : loss->delta[r];
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) {
      sf_lanes p = sf_lanes_load(pred + r * GROUP + v * LANES), de;
      sf_lanes e = residual_lanes(kind, delta, p, sf_lanes_load(target + r * ts + v * LANES), &de);
      sums[v] = sf_lanes_add(sums[v], sf_lanes_mul(e, e));   /* 0 + e^2 is e^2 exactly */
      sf_lanes_store(d + r * GROUP + v * LANES, sf_lanes_mul(sf_lanes_mul(sf_lanes_scale(e, two_inv_n), de), slope(f, p)));
    }
  }
  SF_LANES_UNROLL
  for (int v = 0; v < VECS; ++v) sq[v] = sums[v];
}

static FORCE_INLINE void output_delta_loss(sf_mlp_activation f, const sf_mlp_loss *loss, int n_out,
                                           const double *pred, const double *target, long ts, sf_lanes *sq,
                                           double *d) {
  switch (loss->kind) {
    case SF_LOSS_REL: output_delta_f(f, SF_LOSS_REL, loss, n_out, pred, target, ts, sq, d); break;
    case SF_LOSS_LOG: output_delta_f(f, SF_LOSS_LOG, loss, n_out, pred, target, ts, sq, d); break;
    default: output_delta_f(f, SF_LOSS_MSE, loss, n_out, pred, target, ts, sq, d); break;
  }
}

static FORCE_INLINE void output_delta(sf_mlp_activation f, const sf_mlp_loss *loss, int n_out, const double *pred,
                                      const double *target, long ts, sf_lanes *sq, double *d) {
  switch (f) {
    case SF_ACT_SIGMOID: output_delta_loss(SF_ACT_SIGMOID, loss, n_out, pred, target, ts, sq, d); break;
    case SF_ACT_TANH: output_delta_loss(SF_ACT_TANH, loss, n_out, pred, target, ts, sq, d); break;
    case SF_ACT_RELU: output_delta_loss(SF_ACT_RELU, loss, n_out, pred, target, ts, sq, d); break;
    case SF_ACT_LINEAR: output_delta_loss(SF_ACT_LINEAR, loss, n_out, pred, target, ts, sq, d); break;
    case SF_ACT_EXP_NEG: output_delta_loss(SF_ACT_EXP_NEG, loss, n_out, pred, target, ts, sq, d); break;
    case SF_ACT_EXP_NEG_EXP: output_delta_loss(SF_ACT_EXP_NEG_EXP, loss, n_out, pred, target, ts, sq, d); break;
  }
}

/* Gradient lanes of a layer: G_W[r][j] += d_r a_j (fused) and G_b[r] +=
 * d_r, lane by lane: each lane adds its own samples' products, in sample order,
 * straight into its accumulator (no per-group fold), loaded and stored once
 * per group. Rows r0..r0+nr-1 together: each a_j loaded once for them. */
static FORCE_INLINE void weight_gradient_rows(const double *d, const double *a, long as, int ni, int r0, int nr,
                                              double *restrict GW, double *restrict Gb) {
  sf_lanes dr[ROWS][VECS];
  SF_LANES_UNROLL
  for (int q = 0; q < nr; ++q)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) dr[q][v] = sf_lanes_load(d + (r0 + q) * GROUP + v * LANES);
  for (int j = 0; j < ni; ++j) {
    sf_lanes aj[VECS], acc[ROWS];
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) aj[v] = sf_lanes_load(a + j * as + v * LANES);
    SF_LANES_UNROLL
    for (int q = 0; q < nr; ++q) acc[q] = sf_lanes_load(GW + ((long)(r0 + q) * ni + j) * LANES);
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v)
      SF_LANES_UNROLL
      for (int q = 0; q < nr; ++q) acc[q] = sf_lanes_fma(dr[q][v], aj[v], acc[q]);
    SF_LANES_UNROLL
    for (int q = 0; q < nr; ++q) sf_lanes_store(GW + ((long)(r0 + q) * ni + j) * LANES, acc[q]);
  }
  SF_LANES_UNROLL
  for (int q = 0; q < nr; ++q) {
    sf_lanes acc = sf_lanes_load(Gb + (r0 + q) * LANES);
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) acc = sf_lanes_add(acc, dr[q][v]);
    sf_lanes_store(Gb + (r0 + q) * LANES, acc);
  }
}

static FORCE_INLINE void weight_gradient(const double *d, const double *a, long as, int ni, int no,
                                         double *restrict GW, double *restrict Gb) {
  int r = 0;
  for (; r + ROWS <= no; r += ROWS) weight_gradient_rows(d, a, as, ni, r, ROWS, GW, Gb);
  for (; r < no; ++r) weight_gradient_rows(d, a, as, ni, r, 1, GW, Gb);
}

/* dn_j = f'(z_j) sum_r W[r][j] d_r: dLoss/dz of the layer below, the sums
 * in registers across r; units j0..j0+nj-1 together, each d_r loaded once
 * for them. */
static FORCE_INLINE void propagate_units_f(sf_mlp_activation f, const double *W, const double *d, const double *a,
                                           int ni, int no, int j0, int nj, double *restrict dn) {
  sf_lanes acc[ROWS][VECS];
  SF_LANES_UNROLL
  for (int v = 0; v < VECS; ++v) {
    sf_lanes d0 = sf_lanes_load(d + v * LANES);
    SF_LANES_UNROLL
    for (int q = 0; q < nj; ++q) acc[q][v] = sf_lanes_scale(d0, W[j0 + q]);
  }
  for (int r = 1; r < no; ++r)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v) {
      sf_lanes dr = sf_lanes_load(d + r * GROUP + v * LANES);
      SF_LANES_UNROLL
      for (int q = 0; q < nj; ++q) acc[q][v] = sf_lanes_fma_scalar(dr, W[(long)r * ni + j0 + q], acc[q][v]);
    }
  SF_LANES_UNROLL
  for (int q = 0; q < nj; ++q)
    SF_LANES_UNROLL
    for (int v = 0; v < VECS; ++v)
      sf_lanes_store(dn + (j0 + q) * GROUP + v * LANES,
                     sf_lanes_mul(acc[q][v], slope(f, sf_lanes_load(a + (j0 + q) * GROUP + v * LANES))));
}

static FORCE_INLINE void propagate_f(sf_mlp_activation f, const double *W, const double *d, const double *a, int ni,
                                     int no, double *restrict dn) {
  int j = 0;
  for (; j + ROWS <= ni; j += ROWS) propagate_units_f(f, W, d, a, ni, no, j, ROWS, dn);
  for (; j < ni; ++j) propagate_units_f(f, W, d, a, ni, no, j, 1, dn);
}

static FORCE_INLINE void propagate(sf_mlp_activation f, const double *W, const double *d, const double *a, int ni,
                                   int no, double *dn) {
  switch (f) {
    case SF_ACT_SIGMOID: propagate_f(SF_ACT_SIGMOID, W, d, a, ni, no, dn); break;
    case SF_ACT_TANH: propagate_f(SF_ACT_TANH, W, d, a, ni, no, dn); break;
    case SF_ACT_RELU: propagate_f(SF_ACT_RELU, W, d, a, ni, no, dn); break;
    case SF_ACT_LINEAR: propagate_f(SF_ACT_LINEAR, W, d, a, ni, no, dn); break;
    case SF_ACT_EXP_NEG: propagate_f(SF_ACT_EXP_NEG, W, d, a, ni, no, dn); break;
    case SF_ACT_EXP_NEG_EXP: propagate_f(SF_ACT_EXP_NEG_EXP, W, d, a, ni, no, dn); break;
  }
}

/* Row of sample i's inputs and targets, asked for early (shuffled rows of a
 * large set are cache misses): the first and last of x's row and of y's,
 * or with packed (packed rows, rows_packed, each starting a 64-byte line)
 * one request per line of the row. For the 4,8,8,9's 13 fields that is 2
 * requests instead of 4, and its shuffled rows took 42.3 -> 40.7 ns per
 * sample (build/bench_mlp_kernel, an Emerald Rapids Xeon). */
static FORCE_INLINE void prefetch_row(const double *x, long xs, const double *y, long ys, long i, int n_in,
                                      int n_out, int packed) {
#if defined(__GNUC__)
  const double *xa = x + i * xs, *ya = y + i * ys;
  if (packed) {
    for (int f = 0; f < n_in + n_out; f += LANES) __builtin_prefetch(xa + f);
    return;
  }
  __builtin_prefetch(xa);
  __builtin_prefetch(xa + n_in - 1);
  __builtin_prefetch(ya);
  __builtin_prefetch(ya + n_out - 1);
#else
  (void)x, (void)xs, (void)y, (void)ys, (void)i, (void)n_in, (void)n_out, (void)packed;
#endif
}

/* Whether shuffled samples are packed rows (sf_mlp_rows: inputs then
 * targets, a stride of whole vectors), which gather_packed gathers. */
static FORCE_INLINE int rows_packed(const double *x, long xs, const double *y, long ys, const int *index,
                                    int n_in) {
  return index && xs == ys && y == x + n_in && xs % LANES == 0;
}

/* Shuffled rows of the group PREFETCH_GROUPS ahead, asked for a few at a
 * time while this group computes: asked all at once (64 lines for 32
 * rows), they exceed the misses a core keeps in flight, and the prefetch
 * instructions themselves stalled (perf: a third of the kernel's time in a
 * shuffled epoch). */
typedef struct prefetch_cursor {
  long next, stop;   /* samples next..stop-1 are still to be asked for */
} prefetch_cursor;

static FORCE_INLINE void prefetch_some(prefetch_cursor *pc, const double *x, long xs, const double *y, long ys,
                                       const int *index, long count, int n_in, int n_out, int packed) {
  long stop = pc->next + count < pc->stop ? pc->next + count : pc->stop;
  for (; pc->next < stop; ++pc->next) prefetch_row(x, xs, y, ys, index[pc->next], n_in, n_out, packed);
}

/* Rows of samples first..first+nv-1 (through index when given; sample i's
 * inputs at x + i xs, its targets at y + i ys) into the group arrays;
 * samples nv..GROUP-1 get zero inputs and targets (and zero weight in the
 * caller). */
static FORCE_INLINE void gather(const double *x, long xs, const double *y, long ys, const int *index, long first,
                                int nv, int n_in, int n_out, double *restrict a0, double *restrict t) {
  for (int s = 0; s < nv; ++s) {
    long i = index ? index[first + s] : first + s;
    const double *xr = x + i * xs, *yr = y + i * ys;
    for (int j = 0; j < n_in; ++j) a0[j * GROUP + s] = xr[j];
    for (int k = 0; k < n_out; ++k) t[k * GROUP + s] = yr[k];
  }
  for (int s = nv; s < GROUP; ++s) {
    for (int j = 0; j < n_in; ++j) a0[j * GROUP + s] = 0.0;
    for (int k = 0; k < n_out; ++k) t[k * GROUP + s] = 0.0;
  }
}

/* gather for packed rows (sf_mlp_rows: inputs then targets, stride a
 * multiple of LANES): 8 samples at a time, each LANES-wide piece of their
 * rows loaded as a vector and transposed into the group's columns. The same
 * values as gather. */
static FORCE_INLINE void gather_packed(const double *rows, long stride, const int *index, long first, int nv,
                                       int n_in, int n_out, double *restrict a0, double *restrict t) {
  const int fields = n_in + n_out;
  int s0 = 0;
  for (; s0 + LANES <= nv; s0 += LANES) {
    const double *row[LANES];
    for (int k = 0; k < LANES; ++k) row[k] = rows + (long)index[first + s0 + k] * stride;
    for (int piece = 0; piece * LANES < fields; ++piece) {
      sf_lanes v[LANES];
      for (int k = 0; k < LANES; ++k) v[k] = sf_lanes_load(row[k] + piece * LANES);
      sf_lanes_transpose8(v);
      for (int f = piece * LANES; f < fields && f < piece * LANES + LANES; ++f)
        sf_lanes_store(f < n_in ? a0 + f * GROUP + s0 : t + (f - n_in) * GROUP + s0, v[f - piece * LANES]);
    }
  }
  for (int s = s0; s < GROUP; ++s) {
    const double *r = s < nv ? rows + (long)index[first + s] * stride : NULL;
    for (int j = 0; j < n_in; ++j) a0[j * GROUP + s] = r ? r[j] : 0.0;
    for (int k = 0; k < n_out; ++k) t[k * GROUP + s] = r ? r[n_in + k] : 0.0;
  }
}

double SF_MLP_KERNEL_NAME(const sf_mlp_kernel_args *args) {
  const sf_mlp_shape *s = args->shape;
  const double *params = args->params, *x = args->x, *y = args->y;
  const sf_mlp_loss *loss = args->loss;
  const long xs = args->xs, ys = args->ys, begin = args->begin, end = args->end;
  const int *index = args->index;
  const sf_mlp_columns *columns = args->columns;
  double *grad = args->grad;
  const int L = s->n_layers, n_in = s->sizes[0], n_out = s->sizes[L];
  group_arrays g;
  group_layout(s, args->ws->mem, &g);
  const int np = sf_mlp_param_count(s);
  if (grad) memset(g.grad, 0, (size_t)np * LANES * sizeof(double));
  int w_off[SF_MLP_MAX_LAYERS], b_off[SF_MLP_MAX_LAYERS];
  for (int l = 0; l < L; ++l) {
    w_off[l] = sf_mlp_weight_offset(s, l);
    b_off[l] = sf_mlp_bias_offset(s, l);
  }
  const long chunk = args->chunk > 0 ? args->chunk : end - begin;
  const long prefetch_end = args->prefetch_end > end ? args->prefetch_end : end;
  /* the first PREFETCH_GROUPS groups' rows now, then each group the rows of
   * the one PREFETCH_GROUPS ahead, spread over its 2 L steps */
  const long lead = PREFETCH_GROUPS * GROUP;
  prefetch_cursor pc = {begin, begin + lead < end ? begin + lead : end};
  const long per_step = (GROUP + 2 * L - 1) / (2 * L);
  const int packed = rows_packed(x, xs, y, ys, index, n_in);
  /* packed rows that start lines (sf_mlp_rows_make's) are prefetched a
   * line at a time */
  const int packed_lines = packed && (uintptr_t)x % (LANES * sizeof(double)) == 0;
  if (index) prefetch_some(&pc, x, xs, y, ys, index, lead, n_in, n_out, packed_lines);
#define PREFETCH_STEP() \
  if (index) prefetch_some(&pc, x, xs, y, ys, index, per_step, n_in, n_out, packed_lines)
  const double inv_n = 1.0 / n_out;
  sf_lanes loss_lanes = sf_lanes_set1(0.0);
  double total_loss = 0.0;
  long chunk_end = begin + chunk < end ? begin + chunk : end;
  int nv = 0;
  for (long first = begin, k = 0; first < end; first += nv) {
    nv = chunk_end - first < GROUP ? (int)(chunk_end - first) : GROUP;
    if (index) {
      prefetch_some(&pc, x, xs, y, ys, index, GROUP, n_in, n_out, packed_lines);   /* what the last group left */
      pc.stop = first + lead + GROUP < prefetch_end ? first + lead + GROUP : prefetch_end;
    }
    /* The group's inputs and targets: read in place from columns (padded
     * past the last sample), else gathered. */
    const double *a0 = g.act[0], *t = g.target;
    long a0_stride = GROUP, t_stride = GROUP;
    if (columns) {
      a0 = columns->x + first;
      t = columns->y + first;
      a0_stride = t_stride = columns->stride;
    } else if (packed) {
      gather_packed(x, xs, index, first, nv, n_in, n_out, g.act[0], g.target);
    } else {
      gather(x, xs, y, ys, index, first, nv, n_in, n_out, g.act[0], g.target);
    }
    for (int l = 0; l < L; ++l) {
      PREFETCH_STEP();
      forward_layer(l + 1 == L ? s->output : s->hidden, params + w_off[l], params + b_off[l], s->sizes[l],
                    s->sizes[l + 1], l == 0 ? a0 : g.act[l], l == 0 ? a0_stride : GROUP, g.act[l + 1]);
    }
    double *d = g.delta[0];
    sf_lanes sq[VECS] = {0};   /* set by output_delta (GCC cannot tell) */
    output_delta(s->output, loss, n_out, g.act[L], t, t_stride, sq, d);
    /* Padding samples weigh nothing: zero loss and zero delta (which stays
     * zero through the layers below). */
    if (nv < GROUP) {
      double v[GROUP];
      for (int u = 0; u < VECS; ++u) sf_lanes_store(v + u * LANES, sq[u]);
      for (int k = nv; k < GROUP; ++k) {
        v[k] = 0.0;
        for (int r = 0; r < n_out; ++r) d[r * GROUP + k] = 0.0;
      }
      for (int u = 0; u < VECS; ++u) sq[u] = sf_lanes_load(v + u * LANES);
    }
    for (int u = 0; u < VECS; ++u) loss_lanes = sf_lanes_add(loss_lanes, sf_lanes_scale(sq[u], inv_n));
    for (int l = L - 1; grad && l >= 0; --l) {
      int ni = s->sizes[l], no = s->sizes[l + 1];
      PREFETCH_STEP();
      weight_gradient(d, l == 0 ? a0 : g.act[l], l == 0 ? a0_stride : GROUP, ni, no, g.grad + (long)w_off[l] * LANES,
                      g.grad + (long)b_off[l] * LANES);
      if (l == 0) break;
      double *dn = d == g.delta[0] ? g.delta[1] : g.delta[0];
      propagate(s->hidden, params + w_off[l], d, g.act[l], ni, no, dn);
      d = dn;
    }
    if (first + nv < chunk_end) continue;
    /* the chunk's sums out, its lanes back to zero */
    double lanes[LANES];
    sf_lanes_store(lanes, loss_lanes);
    double chunk_sum = lane_sum(lanes);
    loss_lanes = sf_lanes_set1(0.0);
    if (args->chunk > 0) args->chunk_loss[k] = chunk_sum;
    total_loss += chunk_sum;
    if (grad) {
      double *gk = grad + k * np;
      for (int q = 0; q < np; ++q) gk[q] += lane_sum(g.grad + (long)q * LANES);
      memset(g.grad, 0, (size_t)np * LANES * sizeof(double));
    }
    k += 1;
    chunk_end = chunk_end + chunk < end ? chunk_end + chunk : end;
  }
#undef PREFETCH_STEP
  return total_loss;
}

/* e^x[i] -> out[i], i < n, x clamped to [-708, cap], by this build's lanes:
 * the kernel's exponential, for tests/test_mlp_exp_builds.c through
 * sf_mlp_exp_isa. */
#define EXP_NAME_PASTE(kernel) kernel##_exp
#define EXP_NAME(kernel) EXP_NAME_PASTE(kernel)
void EXP_NAME(SF_MLP_KERNEL_NAME)(const double *x, double *out, long n, double cap) {
  sf_lanes_exp_array(x, out, n, cap);
}
#undef EXP_NAME
#undef EXP_NAME_PASTE
