/* Tall residual blocks given to Ceres through their Gram matrix
 * (fit/ceres_shim.h, sf_lsq_add_gram_residuals):
 * - a nonlinear fit (a e^{b x} + c + d x, 1000 noisy points, two parameter
 *   blocks) solved from rows and from the Gram matrix reaches the same
 *   parameters (1e-8) and cost (1e-12), the cost agreeing with a direct sum;
 *   the same with one block held constant;
 * - a rank-deficient fit ((a + b) x + c: two equal columns) through the
 *   Gram matrix reaches the closed-form linear least-squares minimum;
 * - the sky fits' Gram kernels (fit/fit_sky_config.h, sf_sky_fit_gram) agree
 *   with [J r]^T [J r] summed here from sf_sky_form_f's gradient, entry by
 *   entry to 1e-12 of sqrt(G_aa G_bb), for Hosek and Perez; the cost-only
 *   sum is bit-identical to the Gram matrix's last entry;
 * - the global sky fit's Gram matrix over 7 elevations' Bezier control
 *   points (fit/sky_bezier_gram.h) agrees in the same way with [J r]^T
 *   [J r] summed here from each sample's row (Bernstein weights times the
 *   one-sky gradient), for Hosek and Perez; the prepared one-sky Gram gives
 *   sf_sky_fit_gram's bits. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "fit/ceres_shim.h"
#include "fit/fit_sky_config.h"
#include "fit/sky_bezier_gram.h"
#include "fit/sky_radiance_samples.h"
#include "models/hosek_dataset.h"
#include "util/constants.h"

/* ---- the exponential fit ---- */
enum { N_POINTS = 1000 };
typedef struct curve {
  double x[N_POINTS], y[N_POINTS];
} curve;

static double model(const double *ab, const double *cd, double x) {
  return ab[0] * exp(ab[1] * x) + cd[0] + cd[1] * x;
}

static void make_curve(curve *c) {
  uint64_t state = 12345;
  for (int i = 0; i < N_POINTS; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    double noise = ((double)(state >> 11) / 9007199254740992.0 - 0.5) * 0.02;
    const double truth_ab[2] = {1.5, -1.3}, truth_cd[2] = {0.2, 0.4};
    c->x[i] = 2.0 * i / (N_POINTS - 1);
    c->y[i] = model(truth_ab, truth_cd, c->x[i]) + noise;
  }
}

/* one point's residual and its gradient over (a, b, c, d) */
static double point(const curve *c, const double *ab, const double *cd, int i, double g[4]) {
  double x = c->x[i], e = exp(ab[1] * x);
  g[0] = e;
  g[1] = ab[0] * x * e;
  g[2] = 1.0;
  g[3] = x;
  return model(ab, cd, x) - c->y[i];
}

static int curve_rows(void *user, const double *const *p, double *r, double **jac) {
  const curve *c = user;
  for (int i = 0; i < N_POINTS; ++i) {
    double g[4];
    r[i] = point(c, p[0], p[1], i, g);
    if (jac && jac[0]) jac[0][2 * i] = g[0], jac[0][2 * i + 1] = g[1];
    if (jac && jac[1]) jac[1][2 * i] = g[2], jac[1][2 * i + 1] = g[3];
  }
  return 1;
}

static int curve_gram(void *user, const double *const *p, double *sum_squares, double *gram) {
  const curve *c = user;
  double s = 0.0;
  if (gram) memset(gram, 0, sizeof(double) * 25);
  for (int i = 0; i < N_POINTS; ++i) {
    double v[5];
    v[4] = point(c, p[0], p[1], i, v);
    s += v[4] * v[4];
    if (gram)
      for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b) gram[a * 5 + b] += v[a] * v[b];
  }
  *sum_squares = s;
  return 1;
}

static double curve_cost(const curve *c, const double *ab, const double *cd) {
  double s = 0.0, g[4];
  for (int i = 0; i < N_POINTS; ++i) s += pow(point(c, ab, cd, i, g), 2);
  return 0.5 * s;
}

/* Solves from (1, -0.5), (0, 0), as rows or through the Gram matrix. */
static void solve_curve(curve *c, int use_gram, int hold_cd, double ab[2], double cd[2],
                        sf_lsq_summary *sum) {
  ab[0] = 1.0, ab[1] = -0.5;
  cd[0] = hold_cd ? 0.2 : 0.0, cd[1] = hold_cd ? 0.4 : 0.0;
  sf_lsq_problem *p = sf_lsq_problem_new();
  int blocks[2] = {sf_lsq_add_block(p, ab, 2), sf_lsq_add_block(p, cd, 2)};
  if (hold_cd) sf_lsq_set_constant(p, blocks[1]);
  if (use_gram) CHECK(sf_lsq_add_gram_residuals(p, curve_gram, c, 2, blocks) == 0);
  else CHECK(sf_lsq_add_residuals(p, curve_rows, c, N_POINTS, 2, blocks, SF_LSQ_LOSS_NONE, 0) == 0);
  sf_lsq_options o;
  sf_lsq_options_default(&o);
  CHECK(sf_lsq_solve(p, &o, sum) == 0);
  sf_lsq_problem_free(p);
}

static void test_curve(curve *c, int hold_cd) {
  double ab_rows[2], cd_rows[2], ab_gram[2], cd_gram[2];
  sf_lsq_summary rows, gram;
  printf("-- exponential fit%s: rows against Gram matrix\n", hold_cd ? ", (c, d) held" : "");
  solve_curve(c, 0, hold_cd, ab_rows, cd_rows, &rows);
  solve_curve(c, 1, hold_cd, ab_gram, cd_gram, &gram);
  printf("iterations: rows %d, Gram %d; residuals seen by Ceres: %d, %d\n", rows.iterations,
         gram.iterations, rows.n_residuals, gram.n_residuals);
  CHECK(gram.n_residuals == 5);
  CHECK_REL(gram.final_cost, rows.final_cost, 1e-12);
  CHECK_REL(gram.final_cost, curve_cost(c, ab_gram, cd_gram), 1e-12);
  CHECK_REL(ab_gram[0], ab_rows[0], 1e-8);
  CHECK_REL(ab_gram[1], ab_rows[1], 1e-8);
  CHECK_REL(cd_gram[0], cd_rows[0], 1e-8);
  CHECK_REL(cd_gram[1], cd_rows[1], 1e-8);
  if (hold_cd) CHECK(cd_gram[0] == 0.2 && cd_gram[1] == 0.4);
}

/* ---- (a + b) x + c: columns 0 and 1 equal ---- */
static int line_gram(void *user, const double *const *p, double *sum_squares, double *gram) {
  const curve *c = user;
  const double *q = p[0];
  double s = 0.0;
  if (gram) memset(gram, 0, sizeof(double) * 16);
  for (int i = 0; i < N_POINTS; ++i) {
    double x = c->x[i], v[4] = {x, x, 1.0, (q[0] + q[1]) * x + q[2] - c->y[i]};
    s += v[3] * v[3];
    if (gram)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) gram[a * 4 + b] += v[a] * v[b];
  }
  *sum_squares = s;
  return 1;
}

static void test_rank_deficient(curve *c) {
  printf("-- (a + b) x + c through the Gram matrix (two equal columns)\n");
  /* closed form: least squares of y on [x 1] */
  double sx = 0, sxx = 0, sy = 0, sxy = 0, n = N_POINTS;
  for (int i = 0; i < N_POINTS; ++i) {
    sx += c->x[i], sxx += c->x[i] * c->x[i], sy += c->y[i], sxy += c->x[i] * c->y[i];
  }
  double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx), icpt = (sy - slope * sx) / n;
  double best = 0.0;
  for (int i = 0; i < N_POINTS; ++i) best += 0.5 * pow(slope * c->x[i] + icpt - c->y[i], 2);
  double q[3] = {0.3, -2.0, 5.0};
  sf_lsq_problem *p = sf_lsq_problem_new();
  int block = sf_lsq_add_block(p, q, 3);
  CHECK(sf_lsq_add_gram_residuals(p, line_gram, c, 1, &block) == 0);
  sf_lsq_options o;
  sf_lsq_options_default(&o);
  sf_lsq_summary sum;
  CHECK(sf_lsq_solve(p, &o, &sum) == 0);
  sf_lsq_problem_free(p);
  printf("termination: %s (%s)\n", sf_lsq_termination_name(sum.termination), sum.message);
  CHECK_REL(sum.final_cost, best, 1e-12);
  CHECK_REL(q[0] + q[1], slope, 1e-10);
  CHECK_REL(q[2], icpt, 1e-10);
}

/* ---- the sky kernels against sf_sky_form_f ---- */

/* Largest |got - want| / sqrt(want_aa want_bb) over the entries of k x k
 * Gram matrices (printed). */
static double worst_gram_error(const double *got, const double *want, int k) {
  double worst = 0;
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b) {
      double e = fabs(got[a * k + b] - want[a * k + b]) / sqrt(want[a * k + a] * want[b * k + b]);
      if (!(e <= worst)) worst = e;
    }
  printf("worst entry error / sqrt(G_aa G_bb): %.3g over %d entries\n", worst, k * k);
  return worst;
}

static void test_sky_gram(sf_sky_form form, const double *truth, const double *at, double scale) {
  int nc = sf_sky_form_n_coeffs(form), k = nc + 2;
  printf("-- %s Gram kernel against sf_sky_form_f\n", sf_sky_form_model_name(form));
  sf_sky_samples s;
  sf_error err = {0};
  CHECK(sf_sky_samples_alloc(&s, 40 * 60, 1, &err) == 0);
  double elev = 0.5;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 60; ++j) {
      double th = (i + 0.5) / 40 * 0.5 * SF_PI, ph = (double)j / 59 * SF_PI;
      int q = i * 60 + j;
      sf_sky_sample_set_angles(&s, q, th, cos(th) * sin(elev) + sin(th) * cos(elev) * cos(ph));
      s.radiance[q] = 1.7 * sf_sky_form_f(form, truth, s.cos_theta[q], s.gamma[q], s.cos_gamma[q], NULL);
    }
  sf_sky_fit_data d = {form, s.n, s.cos_theta, s.gamma, s.cos_gamma, s.radiance, 1, 0.8};
  double want[(SF_HOSEK_N_COEFFS + 2) * (SF_HOSEK_N_COEFFS + 2)] = {0};
  for (int i = 0; i < s.n; ++i) {
    double v[SF_HOSEK_N_COEFFS + 2];
    double f = sf_sky_form_f(form, at, s.cos_theta[i], s.gamma[i], s.cos_gamma[i], v);
    for (int a = 0; a < nc; ++a) v[a] *= d.weight * scale;
    v[nc] = d.weight * f;
    v[nc + 1] = d.weight * (scale * f - s.radiance[i]);
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) want[a * k + b] += v[a] * v[b];
  }
  double got[(SF_HOSEK_N_COEFFS + 2) * (SF_HOSEK_N_COEFFS + 2)], sum_squares = 0, cost_only = 0;
  CHECK(sf_sky_fit_gram(&d, at, scale, &sum_squares, got) == 0);
  CHECK(sf_sky_fit_gram(&d, at, scale, &cost_only, NULL) == 0);
  CHECK(worst_gram_error(got, want, k) <= 1e-12);
  CHECK_REL(sum_squares, want[k * k - 1], 1e-12);
  CHECK(sum_squares == got[k * k - 1]);
  CHECK(cost_only == sum_squares);
  sf_sky_samples_free(&s);
}

/* ---- the global (all elevations) fit's Gram against explicit rows ---- */
enum { N_BEZIER_ELEVATIONS = 7 };

static void test_bezier_gram(sf_sky_form form, const double *truth) {
  int nc = sf_sky_form_n_coeffs(form), p = SF_BEZIER_POINTS * (nc + 1), m = p + 1;
  printf("-- %s Bezier Gram against rows summed here\n", sf_sky_form_model_name(form));
  sf_sky_samples s[N_BEZIER_ELEVATIONS];
  sf_sky_fit_data d[N_BEZIER_ELEVATIONS];
  double bernstein[N_BEZIER_ELEVATIONS][SF_BEZIER_POINTS];
  sf_error err = {0};
  for (int e = 0; e < N_BEZIER_ELEVATIONS; ++e) {
    double x = (double)e / (N_BEZIER_ELEVATIONS - 1), elev = 0.5 * SF_PI * x * x * x;
    sf_bezier_weights(x, bernstein[e]);
    CHECK(sf_sky_samples_alloc(&s[e], 12 * 20, 2, &err) == 0);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 20; ++j) {
        double th = (i + 0.5) / 12 * 0.5 * SF_PI, ph = (double)j / 19 * SF_PI;
        int q = i * 20 + j;
        sf_sky_sample_set_angles(&s[e], q, th, cos(th) * sin(elev) + sin(th) * cos(elev) * cos(ph));
        /* channel 1 is fitted; channel 0 must be skipped by the stride */
        double f = sf_sky_form_f(form, truth, s[e].cos_theta[q], s[e].gamma[q], s[e].cos_gamma[q], NULL);
        s[e].radiance[2 * q] = -1.0;
        s[e].radiance[2 * q + 1] = (1.0 + 0.2 * x) * f;
      }
    d[e] = (sf_sky_fit_data){form, s[e].n, s[e].cos_theta, s[e].gamma, s[e].cos_gamma, s[e].radiance + 1, 2,
                             0.5 + 0.1 * e};
  }
  /* control points near the truth, each one a little off */
  double P[SF_BEZIER_POINTS * SF_HOSEK_N_COEFFS], Q[SF_BEZIER_POINTS];
  for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
    for (int i = 0; i < nc; ++i) P[j * nc + i] = truth[i] * (1.0 + 0.01 * ((i + 2 * j) % 5) - 0.02);
    Q[j] = 1.0 + 0.05 * j;
  }
  static double want[(SF_SKY_BEZIER_MAX_PARAMS + 1) * (SF_SKY_BEZIER_MAX_PARAMS + 1)];
  memset(want, 0, sizeof want);
  double rows_ss = 0.0;
  for (int e = 0; e < N_BEZIER_ELEVATIONS; ++e) {
    double c[SF_HOSEK_N_COEFFS] = {0}, scale = 0.0;
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
      for (int i = 0; i < nc; ++i) c[i] += bernstein[e][j] * P[j * nc + i];
      scale += bernstein[e][j] * Q[j];
    }
    for (int t = 0; t < s[e].n; ++t) {
      double grad[SF_HOSEK_N_COEFFS], row[SF_SKY_BEZIER_MAX_PARAMS + 1];
      double f = sf_sky_form_f(form, c, s[e].cos_theta[t], s[e].gamma[t], s[e].cos_gamma[t], grad);
      double w = d[e].weight;
      for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
        for (int i = 0; i < nc; ++i) row[j * nc + i] = w * scale * bernstein[e][j] * grad[i];
        row[SF_BEZIER_POINTS * nc + j] = w * bernstein[e][j] * f;
      }
      row[p] = w * (scale * f - s[e].radiance[2 * t + 1]);
      rows_ss += row[p] * row[p];
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) want[a * m + b] += row[a] * row[b];
    }
  }
  sf_sky_bezier_gram g;
  CHECK(sf_sky_bezier_gram_init(&g, form, N_BEZIER_ELEVATIONS, d, (const double(*)[SF_BEZIER_POINTS])bernstein) == 0);
  static double got[(SF_SKY_BEZIER_MAX_PARAMS + 1) * (SF_SKY_BEZIER_MAX_PARAMS + 1)];
  double sum_squares = 0.0, cost_only = 0.0;
  sf_sky_bezier_gram_eval(&g, P, Q, &sum_squares, got);
  sf_sky_bezier_gram_eval(&g, P, Q, &cost_only, NULL);
  CHECK(worst_gram_error(got, want, m) <= 1e-12);
  CHECK_REL(sum_squares, rows_ss, 1e-12);
  CHECK(sum_squares == got[m * m - 1]);
  CHECK(cost_only == sum_squares);
  /* the prepared one-sky Gram gives sf_sky_fit_gram's bits */
  double c0[SF_HOSEK_N_COEFFS], one[(SF_HOSEK_N_COEFFS + 2) * (SF_HOSEK_N_COEFFS + 2)];
  double two[(SF_HOSEK_N_COEFFS + 2) * (SF_HOSEK_N_COEFFS + 2)], ss1 = 0, ss2 = 0;
  memcpy(c0, P, sizeof(double) * (size_t)nc);
  CHECK(sf_sky_fit_gram(&d[3], c0, 1.1, &ss1, one) == 0);
  sf_sky_fit_prepared_gram(g.elevation[3], c0, 1.1, &ss2, two);
  CHECK(ss1 == ss2 && memcmp(one, two, sizeof(double) * (size_t)((nc + 2) * (nc + 2))) == 0);
  sf_sky_bezier_gram_free(&g);
  for (int e = 0; e < N_BEZIER_ELEVATIONS; ++e) sf_sky_samples_free(&s[e]);
}

int main(void) {
  curve *c = malloc(sizeof *c);
  make_curve(c);
  test_curve(c, 0);
  test_curve(c, 1);
  test_rank_deficient(c);
  free(c);

  sf_error err = {0};
  sf_hosek_dataset *ds = malloc(sizeof *ds);
  CHECK(sf_hosek_dataset_load_default(ds, &err) == 0);
  double truth[SF_HOSEK_N_COEFFS + 1], at[SF_HOSEK_N_COEFFS], R;
  sf_hosek_dataset_state(ds, 1, 4.0, 0.3, 0.5, truth, &R, &err);
  for (int i = 0; i < SF_HOSEK_N_COEFFS; ++i) at[i] = truth[i] * (1.0 + 0.03 * ((i % 3) - 1) + 0.02);
  test_sky_gram(SF_SKY_FORM_HOSEK, truth, at, 1.6);
  const double perez_truth[5] = {-1.1, -0.32, 8.0, -2.9, 0.45};
  double perez_at[5];
  for (int i = 0; i < 5; ++i) perez_at[i] = perez_truth[i] * (1.0 + 0.03 * ((i % 3) - 1) + 0.02);
  test_sky_gram(SF_SKY_FORM_PEREZ, perez_truth, perez_at, 1.6);
  test_bezier_gram(SF_SKY_FORM_HOSEK, truth);
  test_bezier_gram(SF_SKY_FORM_PEREZ, perez_truth);
  free(ds);
  return check_summary();
}
