#include "fit/mlp_backward.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/exp_lanes.h"

/* Sums over samples end in LANES lanes added in a fixed tree
 * (fit/mlp_backward.h); blocks hold a power of two >= LANES samples. */
#define LANES 8
/* A block's arrays are sized to stay within about 96 KiB (L1/L2). */
#define BLOCK_BUDGET_DOUBLES 12288
#define BLOCK_MAX 256
/* Samples ahead whose rows are prefetched when gathering shuffled rows. */
#define PREFETCH_AHEAD 24

/* The hot function is compiled for three instruction sets and chosen at run
 * time (no -march=native: the binary must run on any x86-64). Every helper
 * below is forced inline so that it is compiled inside each clone. The
 * operations per lane are the same in all three (no contraction into fused
 * multiply-adds), hence the same results. */
#if defined(__GNUC__) && !defined(__clang__)
/* the same even if this file is built in GNU mode, where GCC contracts */
#pragma GCC optimize("fp-contract=off")
#endif
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HOT_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define HOT_CLONES
#endif

#if defined(__GNUC__)
#define FORCE_INLINE __attribute__((always_inline)) inline
#else
#define FORCE_INLINE inline
#endif

static const char *const loss_names[] = {"mse", "rel", "log"};

const char *sf_mlp_loss_name(sf_mlp_loss_kind k) { return (unsigned)k < 3u ? loss_names[k] : "?"; }

int sf_mlp_loss_parse(const char *name, sf_mlp_loss_kind *out) {
  for (int k = 0; k < 3; ++k)
    if (strcmp(name, loss_names[k]) == 0) {
      *out = (sf_mlp_loss_kind)k;
      return 0;
    }
  return -1;
}

/* Residual e and de/dpred of one output (fit/mlp_backward.h). */
static FORCE_INLINE double residual(sf_mlp_loss_kind kind, double delta, double pred, double target, double *de) {
  switch (kind) {
    case SF_LOSS_REL: {
      double w = 1.0 / (fabs(target) + delta);
      *de = w;
      return (pred - target) * w;
    }
    case SF_LOSS_LOG: {
      double p = pred + delta;
      /* A non-positive p (possible only with an output that can go
       * negative) is held at a tiny value: the loss stays finite and
       * large, and pushes p up. */
      if (p < 1e-300) p = 1e-300;
      *de = 1.0 / p;
      return log(p) - log(target + delta);
    }
    default:
      *de = 1.0;
      return pred - target;
  }
}

double sf_mlp_sample_loss(const sf_mlp_loss *loss, int n_out, const double *pred, const double *target,
                          double *dloss_dpred) {
  double sum = 0.0, inv_n = 1.0 / n_out;
  for (int k = 0; k < n_out; ++k) {
    double de, e = residual(loss->kind, loss->delta ? loss->delta[k] : 0.0, pred[k], target[k], &de);
    sum += e * e;
    if (dloss_dpred) dloss_dpred[k] = 2.0 * e * de * inv_n;
  }
  return sum * inv_n;
}

/* f(z) in the vectorisable form (sf_mlp_activate's formulas). */
static FORCE_INLINE double activate(sf_mlp_activation f, double z) {
  switch (f) {
    case SF_ACT_SIGMOID: return 1.0 / (1.0 + sf_exp_lanes(-z));
    case SF_ACT_TANH: return tanh(z);
    case SF_ACT_RELU: return z > 0.0 ? z : 0.0;
    case SF_ACT_LINEAR: return z;
    case SF_ACT_EXP_NEG: return sf_exp_lanes(-z);
    case SF_ACT_EXP_NEG_EXP: return sf_exp_lanes(-sf_exp_lanes(-z));
  }
  return z;
}

/* f'(z) from a = f(z). */
static FORCE_INLINE double slope(sf_mlp_activation f, double a) {
  switch (f) {
    case SF_ACT_SIGMOID: return a * (1.0 - a);
    case SF_ACT_TANH: return 1.0 - a * a;
    case SF_ACT_RELU: return a > 0.0 ? 1.0 : 0.0;
    case SF_ACT_LINEAR: return 1.0;
    case SF_ACT_EXP_NEG: return -a;
    /* d/dz exp(-exp(-z)) = a exp(-z) = -a log a */
    case SF_ACT_EXP_NEG_EXP: return a > 0.0 ? -a * log(a) : 0.0;
  }
  return 1.0;
}

/* Fixed-order sum of the lanes. */
static FORCE_INLINE double lane_sum(const double *acc) {
  return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
}

/* Block arrays: act[l] ((sizes[l] + 1) x B, the last row all ones: the
 * bias's input) for l = 0..L, two delta arrays (widest layer x B), targets
 * (n_out x B), per-sample loss (B), a scratch row (B); then the gradient
 * lanes (n_params x LANES). */
static long block_doubles_per_sample(const sf_mlp_shape *s) {
  long units = 0;
  int widest = 1;
  for (int l = 0; l <= s->n_layers; ++l) units += s->sizes[l] + 1;
  for (int l = 1; l <= s->n_layers; ++l) widest = s->sizes[l] > widest ? s->sizes[l] : widest;
  return units + 2L * widest + s->sizes[s->n_layers] + 2;
}

int sf_mlp_workspace_init(sf_mlp_workspace *ws, const sf_mlp_shape *shape) {
  long per_sample = block_doubles_per_sample(shape);
  long block = LANES;
  while (block < BLOCK_MAX && 2 * block * per_sample <= BLOCK_BUDGET_DOUBLES) block *= 2;
  ws->shape = *shape;
  ws->block = (int)block;
  ws->mem = malloc((size_t)(per_sample * block + (long)sf_mlp_param_count(shape) * LANES) * sizeof(double));
  if (!ws->mem) return -1;
  double *row = ws->mem;
  for (int l = 0; l <= shape->n_layers; ++l) {
    row += (long)shape->sizes[l] * block;
    for (long s = 0; s < block; ++s) row[s] = 1.0;
    row += block;
  }
  return 0;
}

void sf_mlp_workspace_free(sf_mlp_workspace *ws) {
  free(ws->mem);
  ws->mem = NULL;
}

/* z = f(W a + b) for nb samples, rows stride B. Each statement is a loop
 * over the samples of a row: contiguous, no dependence between samples. */
static FORCE_INLINE void forward_layer_f(sf_mlp_activation f, const double *W, const double *b, int ni, int no,
                                         const double *a, long as, double *z, int nb, int B) {
  for (int r = 0; r < no; ++r) {
    const double *w = W + (long)r * ni;
    double *restrict zr = z + (long)r * B;
    const double br = b[r];
    for (int s = 0; s < nb; ++s) zr[s] = br;
    for (int j = 0; j < ni; ++j) {
      const double wj = w[j];
      const double *restrict aj = a + j * as;
      for (int s = 0; s < nb; ++s) zr[s] += wj * aj[s];
    }
    for (int s = 0; s < nb; ++s) zr[s] = activate(f, zr[s]);
  }
}

static FORCE_INLINE void forward_layer(sf_mlp_activation f, const double *W, const double *b, int ni, int no,
                                       const double *a, long as, double *z, int nb, int B) {
  switch (f) {
    case SF_ACT_SIGMOID: forward_layer_f(SF_ACT_SIGMOID, W, b, ni, no, a, as, z, nb, B); break;
    case SF_ACT_TANH: forward_layer_f(SF_ACT_TANH, W, b, ni, no, a, as, z, nb, B); break;
    case SF_ACT_RELU: forward_layer_f(SF_ACT_RELU, W, b, ni, no, a, as, z, nb, B); break;
    case SF_ACT_LINEAR: forward_layer_f(SF_ACT_LINEAR, W, b, ni, no, a, as, z, nb, B); break;
    case SF_ACT_EXP_NEG: forward_layer_f(SF_ACT_EXP_NEG, W, b, ni, no, a, as, z, nb, B); break;
    case SF_ACT_EXP_NEG_EXP: forward_layer_f(SF_ACT_EXP_NEG_EXP, W, b, ni, no, a, as, z, nb, B); break;
  }
}

/* Per-sample squared residuals summed over the outputs (sample_sq), and
 * d = dLoss/dz of the output layer. */
static FORCE_INLINE void output_delta_f(sf_mlp_activation f, sf_mlp_loss_kind kind, const sf_mlp_loss *loss,
                                        int n_out, const double *pred, const double *target, long ts, double *sample_sq,
                                        double *d, int nb, int B) {
  const double inv_n = 1.0 / n_out;
  double *restrict sq = sample_sq;
  for (int s = 0; s < nb; ++s) sq[s] = 0.0;
  for (int r = 0; r < n_out; ++r) {
    const double delta = kind == SF_LOSS_MSE ? 0.0 : loss->delta[r];
    const double *restrict p = pred + (long)r * B, *restrict t = target + r * ts;
    double *restrict dr = d + (long)r * B;
    for (int s = 0; s < nb; ++s) {
      double de, e = residual(kind, delta, p[s], t[s], &de);
      sq[s] += e * e;
      dr[s] = 2.0 * e * de * inv_n * slope(f, p[s]);
    }
  }
}

static FORCE_INLINE void output_delta_loss(sf_mlp_activation f, const sf_mlp_loss *loss, int n_out,
                                           const double *pred, const double *target, long ts, double *sample_sq,
                                           double *d, int nb, int B) {
  switch (loss->kind) {
    case SF_LOSS_REL: output_delta_f(f, SF_LOSS_REL, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_LOSS_LOG: output_delta_f(f, SF_LOSS_LOG, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    default: output_delta_f(f, SF_LOSS_MSE, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
  }
}

static FORCE_INLINE void output_delta(sf_mlp_activation f, const sf_mlp_loss *loss, int n_out, const double *pred,
                                      const double *target, long ts, double *sample_sq, double *d, int nb, int B) {
  switch (f) {
    case SF_ACT_SIGMOID: output_delta_loss(SF_ACT_SIGMOID, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_ACT_TANH: output_delta_loss(SF_ACT_TANH, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_ACT_RELU: output_delta_loss(SF_ACT_RELU, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_ACT_LINEAR: output_delta_loss(SF_ACT_LINEAR, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_ACT_EXP_NEG: output_delta_loss(SF_ACT_EXP_NEG, loss, n_out, pred, target, ts, sample_sq, d, nb, B); break;
    case SF_ACT_EXP_NEG_EXP:
      output_delta_loss(SF_ACT_EXP_NEG_EXP, loss, n_out, pred, target, ts, sample_sq, d, nb, B);
      break;
  }
}

/* Sum of v[0..nb-1] (nb a power of two >= LANES, v overwritten) by halving:
 * v[s] += v[s + half] until LANES values remain, then lane_sum. A fixed
 * order that vectorises (each halving is a loop over contiguous samples). */
static FORCE_INLINE double fold_sum(double *restrict v, int nb) {
  for (int half = nb / 2; half >= LANES; half /= 2) {
    const double *restrict hi = v + half;
    for (int s = 0; s < half; ++s) v[s] += hi[s];
  }
  return lane_sum(v);
}

/* Gradient lanes of a layer: G[(r (ni+1) + j) LANES + k] += the block's
 * sum of d_r[s] a_j[s] folded to LANES values by halving (fold_to_lanes),
 * where a_ni is the row of ones (the bias). Every step is a loop over
 * contiguous samples that the compiler vectorises at any width with the
 * same per-element arithmetic. */
static FORCE_INLINE void weight_gradient(const double *d, const double *a, long as, int ni, int no, double *G,
                                         double *scratch, int nb, int B) {
  double *restrict prod = scratch;
  for (int r = 0; r < no; ++r) {
    const double *restrict dr = d + (long)r * B;
    for (int j = 0; j <= ni; ++j) {
      const double *restrict aj = a + j * as;
      for (int s = 0; s < nb; ++s) prod[s] = dr[s] * aj[s];
      for (int half = nb / 2; half >= LANES; half /= 2) {
        const double *restrict hi = prod + half;
        for (int s = 0; s < half; ++s) prod[s] += hi[s];
      }
      double *restrict g = G + ((long)r * (ni + 1) + j) * LANES;
      for (int k = 0; k < LANES; ++k) g[k] += prod[k];
    }
  }
}

/* dn_j = f'(z_j) sum_r W[r][j] d_r: dLoss/dz of the layer below. */
static FORCE_INLINE void propagate_f(sf_mlp_activation f, const double *W, const double *d, const double *a, int ni,
                                     int no, double *dn, int nb, int B) {
  for (int j = 0; j < ni; ++j) {
    const double *restrict aj = a + (long)j * B;
    double *restrict dj = dn + (long)j * B;
    for (int s = 0; s < nb; ++s) dj[s] = 0.0;
    for (int r = 0; r < no; ++r) {
      const double w = W[(long)r * ni + j];
      const double *restrict dr = d + (long)r * B;
      for (int s = 0; s < nb; ++s) dj[s] += w * dr[s];
    }
    for (int s = 0; s < nb; ++s) dj[s] *= slope(f, aj[s]);
  }
}

static FORCE_INLINE void propagate(sf_mlp_activation f, const double *W, const double *d, const double *a, int ni,
                                   int no, double *dn, int nb, int B) {
  switch (f) {
    case SF_ACT_SIGMOID: propagate_f(SF_ACT_SIGMOID, W, d, a, ni, no, dn, nb, B); break;
    case SF_ACT_TANH: propagate_f(SF_ACT_TANH, W, d, a, ni, no, dn, nb, B); break;
    case SF_ACT_RELU: propagate_f(SF_ACT_RELU, W, d, a, ni, no, dn, nb, B); break;
    case SF_ACT_LINEAR: propagate_f(SF_ACT_LINEAR, W, d, a, ni, no, dn, nb, B); break;
    case SF_ACT_EXP_NEG: propagate_f(SF_ACT_EXP_NEG, W, d, a, ni, no, dn, nb, B); break;
    case SF_ACT_EXP_NEG_EXP: propagate_f(SF_ACT_EXP_NEG_EXP, W, d, a, ni, no, dn, nb, B); break;
  }
}

/* Rows of the samples into the unit-major block; padding samples (nv..nb-1)
 * get zero inputs and targets, and zero weight below. */
static FORCE_INLINE void gather(const double *x, const double *y, const int *index, long first, int nv, int nb,
                                int n_in, int n_out, double *a0, double *t, int B) {
  for (int s = 0; s < nv; ++s) {
    long i = index ? index[first + s] : first + s;
#if defined(__GNUC__)
    /* Shuffled rows of a large set are cache misses: ask for them early. */
    if (index && s + PREFETCH_AHEAD < nv) {
      long ahead = index[first + s + PREFETCH_AHEAD];
      const double *xa = x + ahead * n_in, *ya = y + ahead * n_out;
      __builtin_prefetch(xa);
      __builtin_prefetch(xa + n_in - 1);
      __builtin_prefetch(ya);
      __builtin_prefetch(ya + n_out - 1);
    }
#endif
    const double *xr = x + i * n_in, *yr = y + i * n_out;
    for (int j = 0; j < n_in; ++j) a0[(long)j * B + s] = xr[j];
    for (int k = 0; k < n_out; ++k) t[(long)k * B + s] = yr[k];
  }
  for (int s = nv; s < nb; ++s) {
    for (int j = 0; j < n_in; ++j) a0[(long)j * B + s] = 0.0;
    for (int k = 0; k < n_out; ++k) t[(long)k * B + s] = 0.0;
  }
}

HOT_CLONES
static double loss_blocks(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss, const double *x,
                          const double *y, const int *index, const sf_mlp_columns *columns, long begin, long end,
                          double *grad, sf_mlp_workspace *ws) {
  const int L = s->n_layers, n_in = s->sizes[0], n_out = s->sizes[L], B = ws->block;
  double *act[SF_MLP_MAX_LAYERS + 1];
  int widest = 1;
  double *p = ws->mem;
  for (int l = 0; l <= L; ++l) {
    act[l] = p;
    p += (long)(s->sizes[l] + 1) * B;
    if (l > 0 && s->sizes[l] > widest) widest = s->sizes[l];
  }
  double *delta[2] = {p, p + (long)widest * B};
  double *target = p + 2L * widest * B;
  double *sample_sq = target + (long)n_out * B;
  double *scratch = sample_sq + B;
  double *lanes = scratch + B;
  const int np = sf_mlp_param_count(s);
  if (grad) memset(lanes, 0, (size_t)np * LANES * sizeof(double));
  int w_off[SF_MLP_MAX_LAYERS], b_off[SF_MLP_MAX_LAYERS];
  for (int l = 0; l < L; ++l) {
    w_off[l] = sf_mlp_weight_offset(s, l);
    b_off[l] = sf_mlp_bias_offset(s, l);
  }
  const double inv_n = 1.0 / n_out;
  double total = 0.0;
  for (long first = begin; first < end; first += B) {
    int nv = end - first < B ? (int)(end - first) : B;
    int nb = LANES;
    while (nb < nv) nb *= 2;
    /* The inputs (with their row of ones) and targets of the block. */
    const double *a0 = act[0], *t = target;
    long a0_stride = B, t_stride = B;
    if (columns) {
      a0 = columns->x + first;
      t = columns->y + first;
      a0_stride = t_stride = columns->stride;
    } else {
      gather(x, y, index, first, nv, nb, n_in, n_out, act[0], target, B);
    }
    for (int l = 0; l < L; ++l)
      forward_layer(l + 1 == L ? s->output : s->hidden, params + w_off[l], params + b_off[l], s->sizes[l],
                    s->sizes[l + 1], l == 0 ? a0 : act[l], l == 0 ? a0_stride : B, act[l + 1], nb, B);
    double *d = delta[0];
    output_delta(s->output, loss, n_out, act[L], t, t_stride, sample_sq, d, nb, B);
    /* Padding samples weigh nothing: zero loss and zero delta (which stays
     * zero through the layers below). */
    for (int k = nv; k < nb; ++k) {
      sample_sq[k] = 0.0;
      for (int r = 0; r < n_out; ++r) d[(long)r * B + k] = 0.0;
    }
    for (int k = 0; k < nb; ++k) sample_sq[k] *= inv_n;
    total += fold_sum(sample_sq, nb);
    if (!grad) continue;
    for (int l = L - 1; l >= 0; --l) {
      int ni = s->sizes[l], no = s->sizes[l + 1];
      weight_gradient(d, l == 0 ? a0 : act[l], l == 0 ? a0_stride : B, ni, no, lanes + (long)w_off[l] * LANES,
                      scratch, nb, B);
      if (l == 0) break;
      double *dn = d == delta[0] ? delta[1] : delta[0];
      propagate(s->hidden, params + w_off[l], d, act[l], ni, no, dn, nb, B);
      d = dn;
    }
  }
  if (grad)
    for (int l = 0; l < L; ++l) {
      int ni = s->sizes[l], no = s->sizes[l + 1];
      const double *G = lanes + (long)w_off[l] * LANES;
      for (int r = 0; r < no; ++r) {
        for (int j = 0; j < ni; ++j) grad[w_off[l] + r * ni + j] += lane_sum(G + ((long)r * (ni + 1) + j) * LANES);
        grad[b_off[l] + r] += lane_sum(G + ((long)r * (ni + 1) + ni) * LANES);
      }
    }
  return total;
}

double sf_mlp_loss_range_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                            const double *x, const double *y, const int *index, long begin, long end,
                            double *grad, sf_mlp_workspace *ws) {
  return loss_blocks(s, params, loss, x, y, index, NULL, begin, end, grad, ws);
}

int sf_mlp_columns_make(sf_mlp_columns *c, const double *x, const double *y, long n, int n_in, int n_out) {
  /* Blocks may read up to a block (<= BLOCK_MAX) past the last sample. */
  c->n = n;
  c->stride = (n + BLOCK_MAX - 1) / BLOCK_MAX * BLOCK_MAX + BLOCK_MAX;
  c->n_in = n_in;
  c->n_out = n_out;
  c->x = calloc((size_t)((n_in + 1) * c->stride), sizeof(double));
  c->y = calloc((size_t)(n_out * c->stride), sizeof(double));
  if (!c->x || !c->y) {
    sf_mlp_columns_free(c);
    return -1;
  }
  for (long i = 0; i < n; ++i) {
    for (int j = 0; j < n_in; ++j) c->x[j * c->stride + i] = x[i * n_in + j];
    for (int k = 0; k < n_out; ++k) c->y[k * c->stride + i] = y[i * n_out + k];
  }
  for (long i = 0; i < c->stride; ++i) c->x[n_in * c->stride + i] = 1.0;
  return 0;
}

void sf_mlp_columns_free(sf_mlp_columns *c) {
  free(c->x);
  free(c->y);
  c->x = c->y = NULL;
}

double sf_mlp_loss_columns_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                              const sf_mlp_columns *c, long begin, long end, double *grad, sf_mlp_workspace *ws) {
  return loss_blocks(s, params, loss, NULL, NULL, NULL, c, begin, end, grad, ws);
}

double sf_mlp_loss_range(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                         const double *x, const double *y, const int *index, long begin, long end,
                         double *grad) {
  sf_mlp_workspace ws;
  if (sf_mlp_workspace_init(&ws, s)) return NAN;
  double total = loss_blocks(s, params, loss, x, y, index, NULL, begin, end, grad, &ws);
  sf_mlp_workspace_free(&ws);
  return total;
}
