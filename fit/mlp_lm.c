#include "fit/mlp_lm.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "fit/lm_gram.h"
#include "fit/train.h"

void sf_mlp_lm_options_default(sf_mlp_lm_options *o) {
  o->iterations = 0;
  o->max_samples = 0;
  o->lambda0 = 1e-3;
  o->n_threads = 0;
  o->interrupt = NULL;
  o->stop_after_steps = 0;
  o->progress = NULL;
  o->progress_ctx = NULL;
}

/* f'(z) from z and a = f(z). */
static double activation_slope(sf_mlp_activation f, double z, double a) {
  switch (f) {
    case SF_ACT_SIGMOID: return a * (1.0 - a);
    case SF_ACT_TANH: return 1.0 - a * a;
    case SF_ACT_RELU: return z > 0.0 ? 1.0 : 0.0;
    case SF_ACT_LINEAR: return 1.0;
    case SF_ACT_EXP_NEG: return -a;
    case SF_ACT_EXP_NEG_EXP: return a * exp(-z);
  }
  return 0.0;
}

/* Residual of one output (fit/mlp_backward.h) and its slope in pred. */
static double residual(const sf_mlp_loss *loss, int k, double pred, double target, double *slope) {
  switch (loss->kind) {
    case SF_LOSS_REL: {
      double w = 1.0 / (fabs(target) + loss->delta[k]);
      *slope = w;
      return (pred - target) * w;
    }
    case SF_LOSS_LOG: {
      double p = pred + loss->delta[k];
      if (p < 1e-300) p = 1e-300;
      *slope = 1.0 / p;
      return log(p) - log(target + loss->delta[k]);
    }
    case SF_LOSS_MSE:
    default:
      *slope = 1.0;
      return pred - target;
  }
}

typedef struct lm_work {
  int P, L;
  double z[SF_MLP_MAX_LAYERS][SF_MLP_MAX_WIDTH], a[SF_MLP_MAX_LAYERS + 1][SF_MLP_MAX_WIDTH];
  double g[2][SF_MLP_MAX_WIDTH];
  double *row;
} lm_work;

static void forward_store(const sf_mlp_shape *s, const double *params, const double *x, lm_work *w) {
  memcpy(w->a[0], x, (size_t)s->sizes[0] * sizeof(double));
  const double *p = params;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    const double *W = p, *b = p + n_out * n_in;
    sf_mlp_activation f = l + 1 == s->n_layers ? s->output : s->hidden;
    for (int i = 0; i < n_out; ++i) {
      double sum = b[i];
      for (int j = 0; j < n_in; ++j) sum += W[i * n_in + j] * w->a[l][j];
      w->z[l][i] = sum;
      w->a[l + 1][i] = sf_mlp_activate(f, sum);
    }
    p += n_out * (n_in + 1);
  }
}

/* w->row = d out_k / d params (flat order of models/mlp.h) * scale. */
static void jacobian_row(const sf_mlp_shape *s, const double *params, int k, double scale, lm_work *w) {
  int L = s->n_layers;
  memset(w->row, 0, (size_t)w->P * sizeof(double));
  double *g = w->g[0], *g_prev = w->g[1];
  int n_last = s->sizes[L];
  for (int i = 0; i < n_last; ++i) g[i] = 0.0;
  g[k] = scale * activation_slope(s->output, w->z[L - 1][k], w->a[L][k]);
  for (int l = L - 1; l >= 0; --l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    int wo = sf_mlp_weight_offset(s, l), bo = sf_mlp_bias_offset(s, l);
    const double *W = params + wo;
    for (int i = 0; i < n_out; ++i) {
      if (g[i] == 0.0) continue;
      for (int j = 0; j < n_in; ++j) w->row[wo + i * n_in + j] = g[i] * w->a[l][j];
      w->row[bo + i] = g[i];
    }
    if (l == 0) break;
    for (int j = 0; j < n_in; ++j) {
      double sum = 0.0;
      for (int i = 0; i < n_out; ++i) sum += W[i * n_in + j] * g[i];
      g_prev[j] = sum * activation_slope(s->hidden, w->z[l - 1][j], w->a[l][j]);
    }
    double *t = g;
    g = g_prev;
    g_prev = t;
  }
}

/* A pass over the samples goes in LM_CHUNKS fixed chunks, chunk c holding
 * samples n c / LM_CHUNKS .. n (c + 1) / LM_CHUNKS - 1, each summed on its
 * own and the chunks' sums added in chunk order: the same bits whatever
 * the number of threads that computed them. */
#define LM_CHUNKS 32

static long chunk_begin(long n, int c) { return n * c / LM_CHUNKS; }

/* Sum of squared residuals over samples s0..s1-1. */
static double chunk_loss(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss, const sf_dataset *d,
                         long s0, long s1) {
  double out[SF_MLP_MAX_WIDTH], sum = 0.0, slope;
  int n_out = s->sizes[s->n_layers];
  for (long i = s0; i < s1; ++i) {
    sf_mlp_forward(s, params, d->x + i * d->n_in, out);
    for (int k = 0; k < n_out; ++k) {
      double e = residual(loss, k, out[k], d->y[i * d->n_out + k], &slope);
      sum += e * e;
    }
  }
  return sum;
}

/* Sum of squared residuals over the first n samples. */
static double total_loss(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss, const sf_dataset *d,
                         long n, int n_threads) {
  double part[LM_CHUNKS], sum = 0.0;
#pragma omp parallel for schedule(static, 1) num_threads(n_threads) if (n_threads > 1)
  for (int c = 0; c < LM_CHUNKS; ++c) part[c] = chunk_loss(s, params, loss, d, chunk_begin(n, c), chunk_begin(n, c + 1));
  for (int c = 0; c < LM_CHUNKS; ++c) sum += part[c];
  return sum;
}

/* Solves A x = b for symmetric positive definite A (P x P, upper triangle
 * used) by Cholesky; -1 when A is not positive definite. */
static int cholesky_solve(int P, const double *A, const double *b, double *Lw, double *x) {
  for (int i = 0; i < P; ++i)
    for (int j = 0; j <= i; ++j) {
      double sum = A[j * P + i];
      for (int k = 0; k < j; ++k) sum -= Lw[i * P + k] * Lw[j * P + k];
      if (i == j) {
        if (!(sum > 0.0)) return -1;
        Lw[i * P + i] = sqrt(sum);
      } else {
        Lw[i * P + j] = sum / Lw[j * P + j];
      }
    }
  for (int i = 0; i < P; ++i) {
    double sum = b[i];
    for (int k = 0; k < i; ++k) sum -= Lw[i * P + k] * x[k];
    x[i] = sum / Lw[i * P + i];
  }
  for (int i = P - 1; i >= 0; --i) {
    double sum = x[i];
    for (int k = i + 1; k < P; ++k) sum -= Lw[k * P + i] * x[k];
    x[i] = sum / Lw[i * P + i];
  }
  return 0;
}

/* Jacobian rows are gathered LM_BLOCK at a time, stored parameter-major
 * (block[i * LM_BLOCK + r] = row r's entry i), and J^T J's upper triangle
 * gets each block's Gram matrix (fit/lm_gram.h): contiguous dot products
 * instead of one pass over the whole P x P matrix per row (which made the
 * polish of a 2-16-16-3 network memory-bound). The sum order is fixed by
 * the samples. */
#define LM_BLOCK SF_LM_GRAM_BLOCK

static void add_block_gram(int P, double *block, int filled, double *JTJ) {
  int padded = (filled + 7) & ~7;
  for (int i = 0; i < P; ++i)
    for (int r = filled; r < padded; ++r) block[(size_t)i * LM_BLOCK + r] = 0.0;
  sf_lm_add_block_gram(P, block, padded, JTJ);
}

/* Rows are staged row-major LM_STAGE at a time and then written into the
 * parameter-major block a 64-byte line per parameter: written one by one,
 * each row touched P lines of a block larger than L1. */
#define LM_STAGE 8   /* divides LM_BLOCK */
_Static_assert(LM_BLOCK % LM_STAGE == 0, "LM_STAGE must divide LM_BLOCK");

/* One thread's buffers for the normal equations of a chunk of samples. */
typedef struct lm_worker {
  lm_work w;
  double *row, *block;   /* LM_STAGE Jacobian rows, row-major; LM_BLOCK rows, parameter-major */
  double *JTJ, *JTe;     /* the chunk's sums (J^T J: upper triangle) */
} lm_worker;

static int lm_worker_init(lm_worker *t, int P) {
  memset(t, 0, sizeof *t);
  size_t PP = (size_t)P * (size_t)P;
  t->row = malloc((size_t)P * LM_STAGE * sizeof(double));
  t->block = malloc((size_t)P * LM_BLOCK * sizeof(double));
  t->JTJ = malloc(PP * sizeof(double));
  t->JTe = malloc((size_t)P * sizeof(double));
  t->w.P = P;
  t->w.row = t->row;
  return t->row && t->block && t->JTJ && t->JTe ? 0 : -1;
}

/* Staged rows 0..count-1 into block rows first..first+count-1. */
static void unstage_rows(const lm_worker *t, int count, int first) {
  int P = t->w.P;
  for (int i = 0; i < P; ++i) {
    double *b = t->block + (size_t)i * LM_BLOCK + first;
    for (int r = 0; r < count; ++r) b[r] = t->row[(size_t)r * P + i];
  }
}

static void lm_worker_free(lm_worker *t) {
  free(t->row);
  free(t->block);
  free(t->JTJ);
  free(t->JTe);
}

/* J^T J (upper triangle) and J^T e of samples s0..s1-1 into t->JTJ, t->JTe:
 * each residual's Jacobian row, gathered LM_BLOCK rows at a time. */
static void chunk_normal_equations(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                                   const sf_dataset *train, long s0, long s1, lm_worker *t) {
  int P = t->w.P, n_out = shape->sizes[shape->n_layers];
  memset(t->JTJ, 0, (size_t)P * (size_t)P * sizeof(double));
  memset(t->JTe, 0, (size_t)P * sizeof(double));
  double out[SF_MLP_MAX_WIDTH];
  int filled = 0;
  for (long s = s0; s < s1; ++s) {
    forward_store(shape, params, train->x + s * train->n_in, &t->w);
    memcpy(out, t->w.a[shape->n_layers], (size_t)n_out * sizeof(double));
    for (int k = 0; k < n_out; ++k) {
      double slope, e = residual(loss, k, out[k], train->y[s * train->n_out + k], &slope);
      int staged = filled % LM_STAGE;
      t->w.row = t->row + (size_t)staged * P;
      jacobian_row(shape, params, k, slope, &t->w);
      for (int i = 0; i < P; ++i) t->JTe[i] += t->w.row[i] * e;
      ++filled;
      if (staged + 1 == LM_STAGE) unstage_rows(t, LM_STAGE, filled - LM_STAGE);
      if (filled == LM_BLOCK) {
        add_block_gram(P, t->block, filled, t->JTJ);
        filled = 0;
      }
    }
  }
  if (filled % LM_STAGE) unstage_rows(t, filled % LM_STAGE, filled - filled % LM_STAGE);
  if (filled) add_block_gram(P, t->block, filled, t->JTJ);
}

int sf_mlp_lm_polish(const sf_mlp_shape *shape, double *params, const sf_mlp_loss *loss, const sf_dataset *train,
                     const sf_dataset *validation, const sf_mlp_lm_options *o, sf_mlp_lm_result *result,
                     sf_error *err) {
  memset(result, 0, sizeof *result);
  int P = sf_mlp_param_count(shape);
  long n = o->max_samples > 0 && o->max_samples < train->n ? o->max_samples : train->n;
  int n_out = shape->sizes[shape->n_layers];
  int has_val = validation && validation->n > 0;
  size_t PP = (size_t)P * (size_t)P;
  double *JTJ = malloc(PP * sizeof(double)), *Lw = malloc(PP * sizeof(double));
  double *JTe = malloc((size_t)P * sizeof(double)), *step = malloc((size_t)P * sizeof(double));
  double *trial = malloc((size_t)P * sizeof(double)), *best = malloc((size_t)P * sizeof(double));
  double *A = malloc(PP * sizeof(double));
  int n_threads = o->n_threads > 0 ? o->n_threads : omp_get_max_threads();
  if (n_threads > LM_CHUNKS) n_threads = LM_CHUNKS;
  lm_worker *workers = calloc((size_t)n_threads, sizeof *workers);
  int ok = JTJ && Lw && JTe && step && trial && best && A && workers;
  for (int t = 0; ok && t < n_threads; ++t) ok = lm_worker_init(&workers[t], P) == 0;
  if (!ok) {
    for (int t = 0; workers && t < n_threads; ++t) lm_worker_free(&workers[t]);
    free(JTJ); free(Lw); free(JTe); free(step); free(trial); free(best); free(A); free(workers);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  double cost = total_loss(shape, params, loss, train, n, n_threads);
  double norm = (double)n * n_out;
  result->initial_loss = result->final_loss = cost / norm;
  double best_val = has_val ? sf_mlp_dataset_loss(shape, params, loss, validation, n_threads) : NAN;
  result->initial_validation = result->final_validation = best_val;
  memcpy(best, params, (size_t)P * sizeof(double));
  double lambda = o->lambda0;
  int need_jacobian = 1;
  for (int it = 0; it < o->iterations; ++it) {
    if ((o->interrupt && *o->interrupt) || (o->stop_after_steps > 0 && it >= o->stop_after_steps)) {
      result->interrupted = 1;
      break;
    }
    if (need_jacobian) {
      memset(JTJ, 0, PP * sizeof(double));
      memset(JTe, 0, (size_t)P * sizeof(double));
#pragma omp parallel for ordered schedule(static, 1) num_threads(n_threads) if (n_threads > 1)
      for (int c = 0; c < LM_CHUNKS; ++c) {
        lm_worker *t = &workers[omp_get_thread_num()];
        chunk_normal_equations(shape, params, loss, train, chunk_begin(n, c), chunk_begin(n, c + 1), t);
#pragma omp ordered
        for (int i = 0; i < P; ++i) {
          JTe[i] += t->JTe[i];
          for (int j = i; j < P; ++j) JTJ[(size_t)i * P + j] += t->JTJ[(size_t)i * P + j];
        }
      }
      need_jacobian = 0;
    }
    /* damped normal equations; the floor keeps parameters no sample sees solvable */
    memcpy(A, JTJ, PP * sizeof(double));
    double max_diag = 0.0;
    for (int i = 0; i < P; ++i) max_diag = fmax(max_diag, JTJ[(size_t)i * P + i]);
    for (int i = 0; i < P; ++i) A[(size_t)i * P + i] += lambda * JTJ[(size_t)i * P + i] + 1e-12 * max_diag + 1e-300;
    for (int i = 0; i < P; ++i) JTe[i] = -JTe[i];
    int bad = cholesky_solve(P, A, JTe, Lw, step);
    for (int i = 0; i < P; ++i) JTe[i] = -JTe[i];
    result->iterations = it + 1;
    double trial_cost = INFINITY;
    if (!bad) {
      for (int i = 0; i < P; ++i) trial[i] = params[i] + step[i];
      trial_cost = total_loss(shape, trial, loss, train, n, n_threads);
    }
    if (!bad && trial_cost < cost) {
      memcpy(params, trial, (size_t)P * sizeof(double));
      cost = trial_cost;
      lambda = fmax(lambda / 3.0, 1e-12);
      result->accepted += 1;
      need_jacobian = 1;
      if (has_val) {
        double v = sf_mlp_dataset_loss(shape, params, loss, validation, n_threads);
        if (v < best_val) {
          best_val = v;
          memcpy(best, params, (size_t)P * sizeof(double));
        }
      }
    } else {
      lambda *= 4.0;
    }
    if (o->progress) o->progress(o->progress_ctx, it + 1, o->iterations, cost / norm, best_val);
    if (lambda > 1e12) break;
  }
  if (has_val) memcpy(params, best, (size_t)P * sizeof(double));
  result->final_loss = total_loss(shape, params, loss, train, n, n_threads) / norm;
  result->final_validation = best_val;
  for (int t = 0; t < n_threads; ++t) lm_worker_free(&workers[t]);
  free(JTJ); free(Lw); free(JTe); free(step); free(trial); free(best); free(A); free(workers);
  return SF_OK;
}
