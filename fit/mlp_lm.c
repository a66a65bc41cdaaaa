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

/* d e_k / d z_u for every unit u of the sample in w (fit/lm_gram.h),
 * scale = d e_k / d out_k, into column pos of the block's rows g. */
static void unit_gradients(const sf_mlp_shape *s, const double *params, int k, double scale, lm_work *w,
                           double *g_block, int pos) {
  int L = s->n_layers, K = s->sizes[L];
  double *g = w->g[0], *g_prev = w->g[1];
  for (int i = 0; i < K; ++i) g[i] = 0.0;
  g[k] = scale * activation_slope(s->output, w->z[L - 1][k], w->a[L][k]);
  for (int l = L - 1; l >= 0; --l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    double *g_rows = g_block + ((long)sf_lm_gram_unit(s, l, 0) * K + k) * SF_LM_GRAM_BLOCK + pos;
    for (int i = 0; i < n_out; ++i) g_rows[(long)i * K * SF_LM_GRAM_BLOCK] = g[i];
    if (l == 0) break;
    const double *W = params + sf_mlp_weight_offset(s, l);
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

/* One thread's buffers for the normal equations of a chunk of samples:
 * a block of samples' unit gradients and layer inputs (fit/lm_gram.h). */
typedef struct lm_worker {
  lm_work w;
  double *g_block, *a_block, *scratch;
  double *JTJ, *JTe;     /* the chunk's sums (J^T J: upper triangle) */
} lm_worker;

static int lm_worker_init(lm_worker *t, const sf_mlp_shape *s) {
  memset(t, 0, sizeof *t);
  int P = sf_mlp_param_count(s), K = s->sizes[s->n_layers];
  size_t PP = (size_t)P * (size_t)P;
  t->g_block = malloc((size_t)sf_lm_gram_units(s) * K * SF_LM_GRAM_BLOCK * sizeof(double));
  t->a_block = malloc((size_t)sf_lm_gram_input_rows(s) * SF_LM_GRAM_BLOCK * sizeof(double));
  t->scratch = malloc((size_t)sf_lm_gram_scratch_size(s) * sizeof(double));
  t->JTJ = malloc(PP * sizeof(double));
  t->JTe = malloc((size_t)P * sizeof(double));
  t->w.P = P;
  return t->g_block && t->a_block && t->scratch && t->JTJ && t->JTe ? 0 : -1;
}

static void lm_worker_free(lm_worker *t) {
  free(t->g_block);
  free(t->a_block);
  free(t->scratch);
  free(t->JTJ);
  free(t->JTe);
}

/* The block's first `filled` samples into t->JTJ; the columns past them,
 * to the next multiple of 8, zeroed (they add nothing). */
static void add_block(const sf_mlp_shape *s, lm_worker *t, int filled) {
  int padded = (filled + 7) & ~7;
  if (filled < padded) {
    long g_rows = (long)sf_lm_gram_units(s) * s->sizes[s->n_layers], a_rows = sf_lm_gram_input_rows(s);
    for (long r = 0; r < g_rows; ++r)
      memset(t->g_block + r * SF_LM_GRAM_BLOCK + filled, 0, (size_t)(padded - filled) * sizeof(double));
    for (long r = 0; r < a_rows; ++r)
      memset(t->a_block + r * SF_LM_GRAM_BLOCK + filled, 0, (size_t)(padded - filled) * sizeof(double));
  }
  sf_lm_add_block_gram(s, t->g_block, t->a_block, filled, t->scratch, t->JTJ);
}

/* J^T J (upper triangle) and J^T e of samples s0..s1-1 into t->JTJ, t->JTe:
 * each sample's unit gradients for every output (one back-propagation per
 * output) and layer inputs, gathered SF_LM_GRAM_BLOCK samples at a time.
 * The sum order is fixed by the samples. */
static void chunk_normal_equations(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                                   const sf_dataset *train, long s0, long s1, lm_worker *t) {
  int P = t->w.P, L = shape->n_layers, n_out = shape->sizes[L];
  memset(t->JTJ, 0, (size_t)P * (size_t)P * sizeof(double));
  memset(t->JTe, 0, (size_t)P * sizeof(double));
  double e[SF_MLP_MAX_WIDTH];
  int filled = 0;
  for (long s = s0; s < s1; ++s) {
    forward_store(shape, params, train->x + s * train->n_in, &t->w);
    for (int k = 0; k < n_out; ++k) {
      double slope;
      e[k] = residual(loss, k, t->w.a[L][k], train->y[s * train->n_out + k], &slope);
      unit_gradients(shape, params, k, slope, &t->w, t->g_block, filled);
    }
    for (int l = 0; l < L; ++l) {
      int n_in = shape->sizes[l];
      double *a_rows = t->a_block + (long)sf_lm_gram_input_row(shape, l, 0) * SF_LM_GRAM_BLOCK + filled;
      for (int j = 0; j < n_in; ++j) a_rows[(long)j * SF_LM_GRAM_BLOCK] = t->w.a[l][j];
      a_rows[(long)n_in * SF_LM_GRAM_BLOCK] = 1.0;
      /* J^T e: the sample's sum_k e_k g_k[u] times the unit's inputs */
      int wo = sf_mlp_weight_offset(shape, l), bo = sf_mlp_bias_offset(shape, l);
      const double *g_layer = t->g_block + (long)sf_lm_gram_unit(shape, l, 0) * n_out * SF_LM_GRAM_BLOCK + filled;
      for (int i = 0; i < shape->sizes[l + 1]; ++i) {
        const double *gu = g_layer + (long)i * n_out * SF_LM_GRAM_BLOCK;
        double c = 0.0;
        for (int k = 0; k < n_out; ++k) c += e[k] * gu[(long)k * SF_LM_GRAM_BLOCK];
        for (int j = 0; j < n_in; ++j) t->JTe[wo + i * n_in + j] += c * t->w.a[l][j];
        t->JTe[bo + i] += c;
      }
    }
    if (++filled == SF_LM_GRAM_BLOCK) {
      add_block(shape, t, filled);
      filled = 0;
    }
  }
  if (filled) add_block(shape, t, filled);
}

size_t sf_mlp_lm_bytes(const sf_mlp_shape *shape, int n_threads) {
  int threads = n_threads > 0 ? n_threads : omp_get_max_threads();
  if (threads > LM_CHUNKS) threads = LM_CHUNKS;
  size_t P = (size_t)sf_mlp_param_count(shape), K = (size_t)shape->sizes[shape->n_layers];
  size_t per_thread = (P * P + P + (size_t)sf_lm_gram_units(shape) * K * SF_LM_GRAM_BLOCK +
                       (size_t)sf_lm_gram_input_rows(shape) * SF_LM_GRAM_BLOCK + (size_t)sf_lm_gram_scratch_size(shape)) *
                      sizeof(double);
  return 3 * P * P * sizeof(double) + 4 * P * sizeof(double) + (size_t)threads * per_thread;
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
  for (int t = 0; ok && t < n_threads; ++t) ok = lm_worker_init(&workers[t], shape) == 0;
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
