#include "fit/spectral4_fit.h"

#include <math.h>
#include <nlopt.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "models/color_space.h"
#include "util/clock.h"

int sf_spectral4_kernel_init(sf_spectral4_kernel *k, int n, const double *lambda_nm, const sf_cmf *cmf,
                             sf_error *err) {
  memset(k, 0, sizeof *k);
  if (n < 2 || n > SF_MAX_CHANNELS) return sf_fail(err, SF_ERR_INPUT, "spectral kernel: %d channels", n);
  k->K = calloc((size_t)n * n, sizeof *k->K);
  if (!k->K) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  k->n = n;
  memcpy(k->lambda_nm, lambda_nm, (size_t)n * sizeof *lambda_nm);
  k->cmf = cmf;
  return 0;
}

void sf_spectral4_kernel_free(sf_spectral4_kernel *k) {
  free(k->K);
  k->K = NULL;
}

void sf_spectral4_kernel_add(sf_spectral4_kernel *k, const double *L, const double y[3], double w) {
  int n = k->n;
  for (int a = 0; a < n; ++a) {
    double wa = w * L[a];
    if (wa == 0.0) continue;
    double *row = k->K + (size_t)a * n;
    for (int b = 0; b < n; ++b) row[b] += wa * L[b];
    for (int c = 0; c < 3; ++c) k->P[a][c] += wa * y[c];
  }
  k->yy += w * (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
  k->weight_sum += w;
  k->n_samples++;
}

void sf_spectral4_rgb_of_wavelength(const sf_cmf *cmf, double lambda_nm, double c[3]) {
  double bar[3];
  sf_cmf_at(cmf, lambda_nm, bar);
  sf_xyz_to_linear_srgb(bar, c);
}

/* Linear interpolation weights of lambda on the kernel's even grid. */
static void interp(const sf_spectral4_kernel *k, double lambda, int *i0, double *t) {
  double step = (k->lambda_nm[k->n - 1] - k->lambda_nm[0]) / (k->n - 1);
  double pos = (lambda - k->lambda_nm[0]) / step;
  if (pos <= 0.0) pos = 0.0;
  if (pos >= k->n - 1) pos = k->n - 1;
  int i = (int)pos;
  if (i >= k->n - 1) i = k->n - 2;
  *i0 = i;
  *t = pos - i;
}

static double kernel_at(const sf_spectral4_kernel *k, int i, double ti, int j, double tj) {
  const double *K = k->K;
  int n = k->n;
  double a = K[(size_t)i * n + j], b = K[(size_t)i * n + j + 1];
  double c = K[(size_t)(i + 1) * n + j], d = K[(size_t)(i + 1) * n + j + 1];
  return (1 - ti) * ((1 - tj) * a + tj * b) + ti * ((1 - tj) * c + tj * d);
}

/* The loss's quadratic form for m wavelengths with colour vectors col:
 * A = (col_i . col_j) K(l_i, l_j), b_i = col_i . P(l_i). */
static void quadratic_form(const sf_spectral4_kernel *k, int m, const double *lambda, double col[][3],
                           double A[4][4], double b[4]) {
  int idx[4];
  double t[4];
  for (int i = 0; i < m; ++i) interp(k, lambda[i], &idx[i], &t[i]);
  for (int i = 0; i < m; ++i) {
    b[i] = 0.0;
    for (int c = 0; c < 3; ++c)
      b[i] += col[i][c] * ((1 - t[i]) * k->P[idx[i]][c] + t[i] * k->P[idx[i] + 1][c]);
    for (int j = 0; j < m; ++j)
      A[i][j] = (col[i][0] * col[j][0] + col[i][1] * col[j][1] + col[i][2] * col[j][2]) *
                kernel_at(k, idx[i], t[i], idx[j], t[j]);
  }
}

/* The loss from the quadratic form; INFINITY where its terms cancel to
 * below 1e-9 of their magnitudes: the weights then cancel one another
 * (near-equal wavelengths, weights of +-1e5), the value is rounding (it
 * came out -307 for 710, 715, 720 nm) and such weights' colours would be
 * rounding in a float32 shader too. A fit's loss is ~1e-6 of yy. */
static double loss_of(const sf_spectral4_kernel *k, int m, double A[4][4], const double b[4], const double *w) {
  double q = k->yy, magnitude = k->yy;
  for (int i = 0; i < m; ++i) {
    q -= 2.0 * w[i] * b[i];
    magnitude += 2.0 * fabs(w[i] * b[i]);
    for (int j = 0; j < m; ++j) {
      q += w[i] * w[j] * A[i][j];
      magnitude += fabs(w[i] * w[j] * A[i][j]);
    }
  }
  if (!(q >= 1e-9 * magnitude)) return INFINITY;
  return q / (3.0 * k->weight_sum);
}

double sf_spectral4_loss(const sf_spectral4_kernel *k, const sf_spectral4_params *p) {
  double col[4][3], A[4][4], b[4];
  for (int i = 0; i < 4; ++i) sf_spectral4_rgb_of_wavelength(k->cmf, p->lambda_nm[i], col[i]);
  quadratic_form(k, 4, p->lambda_nm, col, A, b);
  return loss_of(k, 4, A, b, p->weight_nm);
}

/* Solves A w = b (m x m, symmetric positive semi-definite) by Gaussian
 * elimination with partial pivoting; returns 0 if singular. */
static int solve(int m, double A_in[4][4], const double b_in[4], double *w) {
  double A[4][5];
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) A[i][j] = A_in[i][j];
    A[i][m] = b_in[i];
  }
  for (int c = 0; c < m; ++c) {
    int p = c;
    for (int r = c + 1; r < m; ++r)
      if (fabs(A[r][c]) > fabs(A[p][c])) p = r;
    if (!(fabs(A[p][c]) > 1e-300)) return 0;
    if (p != c)
      for (int j = 0; j <= m; ++j) {
        double tmp = A[c][j];
        A[c][j] = A[p][j];
        A[p][j] = tmp;
      }
    for (int r = c + 1; r < m; ++r) {
      double f = A[r][c] / A[c][c];
      for (int j = c; j <= m; ++j) A[r][j] -= f * A[c][j];
    }
  }
  for (int i = m - 1; i >= 0; --i) {
    double s = A[i][m];
    for (int j = i + 1; j < m; ++j) s -= A[i][j] * w[j];
    w[i] = s / A[i][i];
  }
  return 1;
}

double sf_spectral4_optimal_weights(const sf_spectral4_kernel *k, sf_spectral4_params *p) {
  double col[4][3], A[4][4], b[4];
  for (int i = 0; i < 4; ++i) sf_spectral4_rgb_of_wavelength(k->cmf, p->lambda_nm[i], col[i]);
  quadratic_form(k, 4, p->lambda_nm, col, A, b);
  double w[4];
  if (!solve(4, A, b, w)) return INFINITY;
  memcpy(p->weight_nm, w, sizeof w);
  return loss_of(k, 4, A, b, w);
}

double sf_spectral4_rgb_baseline(const sf_spectral4_kernel *k, const double lambda_rgb_nm[3], double *scale) {
  /* channel c of the estimate is scale * L(lambda_c): colour vector e_c */
  double col[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, A[4][4], b[4];
  quadratic_form(k, 3, lambda_rgb_nm, col, A, b);
  double num = b[0] + b[1] + b[2], den = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) den += A[i][j];
  *scale = num / den;
  double w[3] = {*scale, *scale, *scale};
  return loss_of(k, 3, A, b, w);
}

void sf_spectral4_fit_options_default(sf_spectral4_fit_options *o) {
  o->grid_min_nm = 380.0;
  o->grid_max_nm = 780.0;
  o->grid_step_nm = 10.0;
  o->max_evaluations = 20000;
  o->ftol_rel = 1e-10;
  o->xtol_rel = 1e-7;
  o->initial_step_nm = 5.0;
  o->initial_step_fraction = 0.1;
  o->restarts = 4;
  o->starts = 8;
  o->shortlist = 1024;
}

typedef struct nm_ctx {
  const sf_spectral4_kernel *k;
  int evaluations;
} nm_ctx;

static double nm_objective(unsigned n, const double *x, double *grad, void *data) {
  (void)n;
  (void)grad;
  nm_ctx *c = data;
  c->evaluations++;
  sf_spectral4_params p;
  memcpy(p.lambda_nm, x, 4 * sizeof *x);
  memcpy(p.weight_nm, x + 4, 4 * sizeof *x);
  return sf_spectral4_loss(c->k, &p);
}

static void sort_by_wavelength(sf_spectral4_params *p) {
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && p->lambda_nm[j] < p->lambda_nm[j - 1]; --j) {
      double l = p->lambda_nm[j], w = p->weight_nm[j];
      p->lambda_nm[j] = p->lambda_nm[j - 1];
      p->weight_nm[j] = p->weight_nm[j - 1];
      p->lambda_nm[j - 1] = l;
      p->weight_nm[j - 1] = w;
    }
}

static int nelder_mead_once(const sf_spectral4_kernel *k, const sf_spectral4_params *start,
                            const sf_spectral4_fit_options *o, sf_spectral4_params *best, double *loss,
                            int *evaluations, int *status, sf_error *err) {
  nlopt_opt opt = nlopt_create(NLOPT_LN_NELDERMEAD, 8);
  if (!opt) return sf_fail(err, SF_ERR_INTERNAL, "nlopt_create failed");
  double x[8], lo[8], hi[8], step[8];
  for (int i = 0; i < 4; ++i) {
    x[i] = start->lambda_nm[i];
    x[4 + i] = start->weight_nm[i];
    lo[i] = k->lambda_nm[0];
    hi[i] = k->lambda_nm[k->n - 1];
    lo[4 + i] = -HUGE_VAL;
    hi[4 + i] = HUGE_VAL;
    step[i] = o->initial_step_nm;
    step[4 + i] = o->initial_step_fraction * fabs(start->weight_nm[i]) + 1e-3;
  }
  nm_ctx ctx = {k, 0};
  nlopt_set_min_objective(opt, nm_objective, &ctx);
  nlopt_set_lower_bounds(opt, lo);
  nlopt_set_upper_bounds(opt, hi);
  nlopt_set_initial_step(opt, step);
  nlopt_set_ftol_rel(opt, o->ftol_rel);
  nlopt_set_xtol_rel(opt, o->xtol_rel);
  nlopt_set_maxeval(opt, o->max_evaluations);
  double f = 0.0;
  nlopt_result res = nlopt_optimize(opt, x, &f);
  nlopt_destroy(opt);
  *status = (int)res;
  *evaluations = ctx.evaluations;
  if (res < 0) return sf_fail(err, SF_ERR_INTERNAL, "NLopt Nelder-Mead failed (status %d)", (int)res);
  memcpy(best->lambda_nm, x, 4 * sizeof *x);
  memcpy(best->weight_nm, x + 4, 4 * sizeof *x);
  *loss = f;
  return 0;
}

int sf_spectral4_nelder_mead(const sf_spectral4_kernel *k, const sf_spectral4_params *start,
                             const sf_spectral4_fit_options *o, sf_spectral4_params *best, double *loss,
                             int *evaluations, int *status, sf_error *err) {
  int total = 0, n_eval = 0;
  int rc = nelder_mead_once(k, start, o, best, loss, &n_eval, status, err);
  total += n_eval;
  for (int r = 0; rc == 0 && r < o->restarts; ++r) {
    sf_spectral4_params again;
    double f = 0.0;
    int st = 0;
    rc = nelder_mead_once(k, best, o, &again, &f, &n_eval, &st, err);
    total += n_eval;
    if (rc || !(f < *loss)) break;
    *best = again;
    *loss = f;
    *status = st;
  }
  sort_by_wavelength(best);
  *evaluations = total;
  return rc;
}

/* A grid quadruple: wavelength indices a < b < c < d and its loss. */
typedef struct grid_point {
  int index[4];
  double loss;
} grid_point;

static sf_spectral4_params grid_params(const sf_spectral4_fit_options *o, const int index[4]) {
  sf_spectral4_params p;
  for (int i = 0; i < 4; ++i) {
    p.lambda_nm[i] = o->grid_min_nm + index[i] * o->grid_step_nm;
    p.weight_nm[i] = 0.0;
  }
  return p;
}

/* Whether no grid neighbour of g (each index moved by -1, 0 or +1, still
 * increasing and on the grid) has a lower loss. */
static int grid_local_minimum(const sf_spectral4_kernel *k, const sf_spectral4_fit_options *o, int m,
                              const grid_point *g) {
  for (int code = 0; code < 81; ++code) {
    if (code == 40) continue;   /* (0, 0, 0, 0): g itself */
    int n[4], rest = code, valid = 1;
    for (int i = 0; i < 4; ++i, rest /= 3) n[i] = g->index[i] + rest % 3 - 1;
    for (int i = 0; i < 4; ++i)
      if (n[i] < 0 || n[i] >= m || (i > 0 && n[i] <= n[i - 1])) valid = 0;
    if (!valid) continue;
    sf_spectral4_params p = grid_params(o, n);
    if (sf_spectral4_optimal_weights(k, &p) < g->loss) return 0;
  }
  return 1;
}

int sf_spectral4_fit(const sf_spectral4_kernel *k, const sf_spectral4_fit_options *o, sf_spectral4_fit_result *r,
                     sf_error *err) {
  memset(r, 0, sizeof *r);
  double t0 = sf_wall_seconds();
  int m = (int)floor((o->grid_max_nm - o->grid_min_nm) / o->grid_step_nm + 1e-9) + 1;
  if (m < 4) return sf_fail(err, SF_ERR_INPUT, "spectral4 grid: fewer than 4 wavelengths");
  if (o->starts < 1 || o->shortlist < o->starts)
    return sf_fail(err, SF_ERR_INPUT, "spectral4: %d starts from a shortlist of %d", o->starts, o->shortlist);
  /* The shortlist: the best quadruples, by loss (ties: the earlier first). */
  grid_point *best = malloc((size_t)o->shortlist * sizeof *best);
  if (!best) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int n_best = 0;
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c)
        for (int d = c + 1; d < m; ++d) {
          grid_point g = {{a, b, c, d}, 0.0};
          sf_spectral4_params p = grid_params(o, g.index);
          g.loss = sf_spectral4_optimal_weights(k, &p);
          r->grid_candidates++;
          if (!isfinite(g.loss) || (n_best == o->shortlist && !(g.loss < best[n_best - 1].loss))) continue;
          int j = n_best < o->shortlist ? n_best++ : n_best - 1;
          for (; j > 0 && g.loss < best[j - 1].loss; --j) best[j] = best[j - 1];
          best[j] = g;
        }
  r->grid_seconds = sf_wall_seconds() - t0;
  if (n_best == 0) {
    free(best);
    /* every quadruple has a wavelength the sky is black at (a sun or a
     * scatterer confined to a band narrower than the 4 wavelengths'
     * spread): the weights are singular there */
    return sf_fail(err, SF_ERR_INPUT,
                   "spectral4: no 4 wavelengths of the grid all see light in the sky (a sun_irradiance or a "
                   "scattering confined to a narrow band): the 4 weights are undetermined");
  }
  r->grid_best = grid_params(o, best[0].index);
  r->grid_loss = sf_spectral4_optimal_weights(k, &r->grid_best);
  /* Nelder-Mead from each of the best few grid local minima: one start
   * from the best grid point stays in its basin, and the basins of a
   * scene's loss are not ranked on a 10 nm grid as they are at their
   * floors (examples/scenes/spectral4.json: from the best grid point 6.6e-7,
   * the best of 8 starts 3.3e-7). */
  double t1 = sf_wall_seconds();
  int rc = 0;
  r->loss = INFINITY;
  for (int i = 0; i < n_best && r->starts < o->starts && rc == 0; ++i) {
    if (!grid_local_minimum(k, o, m, &best[i])) continue;
    sf_spectral4_params start = grid_params(o, best[i].index), found;
    sf_spectral4_optimal_weights(k, &start);
    double loss = 0.0;
    int evaluations = 0, status = 0;
    rc = sf_spectral4_nelder_mead(k, &start, o, &found, &loss, &evaluations, &status, err);
    r->evaluations += evaluations;
    r->starts++;
    if (rc == 0 && loss < r->loss) {
      r->best = found;
      r->loss = loss;
      r->nlopt_status = status;
    }
  }
  free(best);   /* its first entry, the grid's best, is always a local minimum */
  r->nelder_mead_seconds = sf_wall_seconds() - t1;
  return rc;
}
