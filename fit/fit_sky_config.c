/* Before any include: the inline helpers (fit/exp_lanes.h,
 * fit/rsqrt_lanes.h) must be compiled with the same options as the kernels
 * to be inlined into them. No contraction into fused multiply-adds: every
 * instruction-set clone below then does the same operations per lane. Not
 * trapping math: the clamps and NaN selects of the helpers are then plain
 * vector blends (with trapping math GCC keeps them as branches and the
 * AVX2 and SSE2 loops stay scalar); no exception flags are read here. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off", "no-trapping-math")
#endif
#include "fit/fit_sky_config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/exp_lanes.h"
#include "fit/rsqrt_lanes.h"
#include "models/hosek.h"
#include "models/perez.h"
#include "util/target_clones.h"

/* Everything about a sample that does not depend on the coefficients,
 * computed once per fit rather than once per residual evaluation: the
 * residual loop is then two exponentials and (Hosek) an inverse square root
 * per sample, in a form the compiler vectorises (fit/exp_lanes.h,
 * fit/rsqrt_lanes.h). */
typedef struct sky_fit_view {
  int n, n_coeffs;
  sf_sky_form form;
  double weight;
  double *inv_ct;      /* Hosek 1/(cos theta + 0.01), Perez 1/cos theta */
  double *gamma, *cg, *cg2, *one_plus_cg2, *root_ct;
  double *target;      /* weight * radiance */
} sky_fit_view;

/* Samples per tile: the coefficient-dependent intermediates of a tile stay
 * in L1 between the vectorised pass and the row-writing pass. */
#define TILE 128

/* The residual kernels are compiled for three instruction sets and chosen
 * at run time (util/target_clones.h; as fit/mlp_backward.c, the binary runs
 * on any x86-64); the helpers are inlined into each clone, which do the
 * same operations per lane, hence the same residuals. */

static void sky_view_free(sky_fit_view *v) { free(v->inv_ct); }

static int sky_view_make(const sf_sky_fit_data *d, sky_fit_view *v) {
  size_t n = (size_t)d->n;
  v->n = d->n;
  v->form = d->form;
  v->n_coeffs = sf_sky_form_n_coeffs(d->form);
  v->weight = d->weight;
  v->inv_ct = malloc(sizeof(double) * 7 * (n ? n : 1));
  if (!v->inv_ct) return -1;
  v->gamma = v->inv_ct + n;
  v->cg = v->gamma + n;
  v->cg2 = v->cg + n;
  v->one_plus_cg2 = v->cg2 + n;
  v->root_ct = v->one_plus_cg2 + n;
  v->target = v->root_ct + n;
  double offset = d->form == SF_SKY_FORM_HOSEK ? 0.01 : 0.0;   /* models/hosek.h, perez.h */
  for (size_t i = 0; i < n; ++i) {
    double ct = d->cos_theta[i], cg = d->cos_gamma[i];
    v->inv_ct[i] = 1.0 / (ct + offset);
    v->gamma[i] = d->gamma[i];
    v->cg[i] = cg;
    v->cg2[i] = cg * cg;
    v->one_plus_cg2[i] = 1.0 + cg * cg;
    v->root_ct[i] = sqrt(ct);
    v->target[i] = d->weight * d->radiance[i * (size_t)d->stride];
  }
  return 0;
}

/* The Gram matrix [J r]^T [J r] of a fit (fit/ceres_shim.h,
 * sf_lsq_gram_fn) summed over the samples without storing J: per tile one
 * vectorised pass computes the residuals and the Jacobian's columns (kept
 * in L1), a second adds their products into LANES partial sums per entry.
 * Lane l takes samples i = l (mod LANES) in order and the lanes are added
 * in order at the end, so every instruction-set clone adds the same numbers
 * in the same order: the same Gram matrix on any x86-64. The cost alone
 * (gram NULL) sums r^2 the same way, so it equals the Gram matrix's last
 * entry at the same parameters. Non-finite values pass through to the shim,
 * which rejects the evaluation. */
#define LANES 8

/* acc[q] += col[a] * col[b] lane-wise for the pairs q = (a <= b) of k
 * columns, over m_pad samples (a multiple of LANES; padding is zero). */
static inline void gram_add_tile(int k, int m_pad, double col[][TILE], double acc[][LANES]) {
  int q = 0;
  for (int a = 0; a < k; ++a)
    for (int b = a; b < k; ++b, ++q)
      for (int i = 0; i < m_pad; i += LANES)
        for (int l = 0; l < LANES; ++l) acc[q][l] += col[a][i + l] * col[b][i + l];
}

static inline void square_add_tile(int m_pad, const double *r, double acc[LANES]) {
  for (int i = 0; i < m_pad; i += LANES)
    for (int l = 0; l < LANES; ++l) acc[l] += r[i + l] * r[i + l];
}

static double lanes_sum(const double acc[LANES]) {
  double s = 0.0;
  for (int l = 0; l < LANES; ++l) s += acc[l];
  return s;
}

/* gram[k x k] (both triangles) from the pair sums. */
static void gram_from_pairs(int k, double acc[][LANES], double *gram) {
  int q = 0;
  for (int a = 0; a < k; ++a)
    for (int b = a; b < k; ++b, ++q) gram[a * k + b] = gram[b * k + a] = lanes_sum(acc[q]);
}

static int padded(int m) { return (m + LANES - 1) / LANES * LANES; }

/* Hosek F (models/hosek.h) and its gradient; columns A..I, the scale R,
 * the residual. */
static SF_X86_CLONES void hosek_gram(const sky_fit_view *v, const double *c, double scale,
                                  double *sum_squares, double *gram) {
  const double A = c[0], B = c[1], C = c[2], D = c[3], E = c[4], F = c[5], G = c[6], H = c[7],
               I = c[8], w = v->weight, ws = w * scale, hh = 1.0 + H * H, h2 = 2.0 * H;
  enum { K = SF_HOSEK_N_COEFFS + 2 };
  double acc[K * (K + 1) / 2][LANES] = {{0}}, acc_r[LANES] = {0};
  double col[K][TILE];
  for (int t0 = 0; t0 < v->n; t0 += TILE) {
    const int m = v->n - t0 < TILE ? v->n - t0 : TILE, m_pad = padded(m);
    const double *restrict inv = v->inv_ct + t0, *restrict gam = v->gamma + t0,
                           *restrict cg = v->cg + t0, *restrict cg2 = v->cg2 + t0,
                           *restrict opc = v->one_plus_cg2 + t0, *restrict root = v->root_ct + t0,
                           *restrict tgt = v->target + t0;
    for (int a = 0; a < K; ++a)
      for (int i = m; i < m_pad; ++i) col[a][i] = 0.0;
    double *restrict rt = col[K - 1];
    if (!gram) {
      for (int i = 0; i < m; ++i) {
        double et = sf_exp_lanes(B * inv[i]), eg = sf_exp_lanes(E * gam[i]);
        double den = hh - h2 * cg[i], rs = sf_rsqrt_lanes(den);
        double chi = opc[i] * ((rs * rs) * rs);   /* (1 + cos^2)/den^(3/2) */
        double f = (1.0 + A * et) * (C + D * eg + F * cg2[i] + G * chi + I * root[i]);
        rt[i] = ws * f - tgt[i];
      }
      square_add_tile(m_pad, rt, acc_r);
      continue;
    }
    double *restrict j0 = col[0], *restrict j1 = col[1], *restrict j2 = col[2],
                     *restrict j3 = col[3], *restrict j4 = col[4], *restrict j5 = col[5],
                     *restrict j6 = col[6], *restrict j7 = col[7], *restrict j8 = col[8],
                     *restrict jf = col[9];
    for (int i = 0; i < m; ++i) {
      double et = sf_exp_lanes(B * inv[i]), eg = sf_exp_lanes(E * gam[i]);
      double den = hh - h2 * cg[i], rs = sf_rsqrt_lanes(den), inv_den = rs * rs;
      double chi = opc[i] * (inv_den * rs);
      double dchi = -3.0 * chi * (H - cg[i]) * inv_den;   /* d chi / d H */
      double z = 1.0 + A * et;
      double s = C + D * eg + F * cg2[i] + G * chi + I * root[i];
      double wz = ws * z, wes = ws * et * s, f = z * s;
      rt[i] = ws * f - tgt[i];
      jf[i] = w * f;
      j0[i] = wes;
      j1[i] = A * wes * inv[i];
      j2[i] = wz;
      j3[i] = wz * eg;
      j4[i] = wz * D * gam[i] * eg;
      j5[i] = wz * cg2[i];
      j6[i] = wz * chi;
      j7[i] = wz * G * dchi;
      j8[i] = wz * root[i];
    }
    gram_add_tile(K, m_pad, col, acc);
  }
  if (gram) {
    gram_from_pairs(K, acc, gram);
    *sum_squares = gram[K * K - 1];
  } else {
    *sum_squares = lanes_sum(acc_r);
  }
}

/* Perez F (models/perez.h) and its gradient, as hosek_gram: columns A..E,
 * the scale K, the residual. */
static SF_X86_CLONES void perez_gram(const sky_fit_view *v, const double *c, double scale,
                                  double *sum_squares, double *gram) {
  const double A = c[0], B = c[1], C = c[2], D = c[3], E = c[4], w = v->weight, ws = w * scale;
  enum { K = SF_PEREZ_N_COEFFS + 2 };
  double acc[K * (K + 1) / 2][LANES] = {{0}}, acc_r[LANES] = {0};
  double col[K][TILE];
  for (int t0 = 0; t0 < v->n; t0 += TILE) {
    const int m = v->n - t0 < TILE ? v->n - t0 : TILE, m_pad = padded(m);
    const double *restrict inv = v->inv_ct + t0, *restrict gam = v->gamma + t0,
                           *restrict cg2 = v->cg2 + t0, *restrict tgt = v->target + t0;
    for (int a = 0; a < K; ++a)
      for (int i = m; i < m_pad; ++i) col[a][i] = 0.0;
    double *restrict rt = col[K - 1];
    if (!gram) {
      for (int i = 0; i < m; ++i) {
        double et = sf_exp_lanes(B * inv[i]), eg = sf_exp_lanes(D * gam[i]);
        double f = (1.0 + A * et) * (1.0 + C * eg + E * cg2[i]);
        rt[i] = ws * f - tgt[i];
      }
      square_add_tile(m_pad, rt, acc_r);
      continue;
    }
    double *restrict j0 = col[0], *restrict j1 = col[1], *restrict j2 = col[2],
                     *restrict j3 = col[3], *restrict j4 = col[4], *restrict jf = col[5];
    for (int i = 0; i < m; ++i) {
      double et = sf_exp_lanes(B * inv[i]), eg = sf_exp_lanes(D * gam[i]);
      double z = 1.0 + A * et, s = 1.0 + C * eg + E * cg2[i];
      double wz = ws * z, wes = ws * et * s, f = z * s;
      rt[i] = ws * f - tgt[i];
      jf[i] = w * f;
      j0[i] = wes;
      j1[i] = A * wes * inv[i];
      j2[i] = wz * eg;
      j3[i] = wz * C * gam[i] * eg;
      j4[i] = wz * cg2[i];
    }
    gram_add_tile(K, m_pad, col, acc);
  }
  if (gram) {
    gram_from_pairs(K, acc, gram);
    *sum_squares = gram[K * K - 1];
  } else {
    *sum_squares = lanes_sum(acc_r);
  }
}

static void sky_view_gram(const sky_fit_view *v, const double *coeffs, double scale,
                          double *sum_squares, double *gram) {
  if (v->form == SF_SKY_FORM_HOSEK) hosek_gram(v, coeffs, scale, sum_squares, gram);
  else perez_gram(v, coeffs, scale, sum_squares, gram);
}

/* sf_lsq_gram_fn over blocks [0] coefficients, [1] scale. */
static int sky_gram(void *user, const double *const *params, double *sum_squares, double *gram) {
  sky_view_gram(user, params[0], params[1][0], sum_squares, gram);
  return 1;
}

int sf_sky_fit_gram(const sf_sky_fit_data *d, const double *coeffs, double scale,
                    double *sum_squares, double *gram) {
  sky_fit_view view;
  if (sky_view_make(d, &view)) return -1;
  sky_view_gram(&view, coeffs, scale, sum_squares, gram);
  sky_view_free(&view);
  return 0;
}

struct sf_sky_fit_prepared {
  sky_fit_view view;
};

sf_sky_fit_prepared *sf_sky_fit_prepare(const sf_sky_fit_data *d) {
  sf_sky_fit_prepared *p = malloc(sizeof *p);
  if (p && sky_view_make(d, &p->view)) {
    free(p);
    return NULL;
  }
  return p;
}

void sf_sky_fit_prepared_gram(const sf_sky_fit_prepared *p, const double *coeffs, double scale,
                              double *sum_squares, double *gram) {
  sky_view_gram(&p->view, coeffs, scale, sum_squares, gram);
}

void sf_sky_fit_prepared_free(sf_sky_fit_prepared *p) {
  if (!p) return;
  sky_view_free(&p->view);
  free(p);
}

void sf_sky_fit_options_default(sf_lsq_options *o) {
  sf_lsq_options_default(o);
  /* J^T J by Cholesky: a third of a dense QR's time when the global fit
   * over elevations handed Ceres its rows (samples x 60 control points).
   * Every sky fit now reaches Ceres as the few rows of its Gram matrix's
   * factor (sf_fit_sky_config; fit/sky_bezier_gram.h), where both cost the
   * same (bench/ceres_vs_scipy.sh, BENCH_QR) */
  o->normal_equations = 1;
  /* Ceres' Levenberg-Marquardt damps with mu diag(J^T J) (Marquardt's
   * scaling), so its steps do not depend on the columns' scale and Jacobi
   * scaling changes nothing but rounding (same iterations and final costs
   * on bench/ceres_vs_scipy.sh); without it Ceres skips two passes over
   * the Jacobian per evaluation */
  o->jacobi_scaling = 0;
  /* Hosek fits are non-convex: with monotonic steps Ceres' LM settled in a
   * worse local minimum than MINPACK's from the same start (built-in sky,
   * 30 deg sun: cost 0.385 against 0.331); Ceres' non-monotonic steps reach
   * MINPACK's 0.331 (bench/ceres_vs_scipy.sh) */
  o->nonmonotonic_steps = 1;
}

void sf_sky_coeff_bounds(sf_sky_form form, sf_sky_bounds bounds, int i, double *lower,
                         double *upper) {
  int nc = sf_sky_form_n_coeffs(form);
  *lower = -INFINITY;
  *upper = INFINITY;
  if (i == nc) {
    *lower = 0.0;
    return;
  }
  if (bounds != SF_SKY_BOUNDS_PHYSICAL) return;
  if (form == SF_SKY_FORM_HOSEK && i == SF_HOSEK_H) {
    *lower = 0.0;
    *upper = SF_HOSEK_H_MAX;
  }
  if (form == SF_SKY_FORM_HOSEK && (i == SF_HOSEK_C || i == SF_HOSEK_D || i == SF_HOSEK_F || i == SF_HOSEK_I)) {
    *lower = -SF_HOSEK_LINEAR_MAX;
    *upper = SF_HOSEK_LINEAR_MAX;
  }
  if (i == 1) *upper = 0.0;   /* B of both forms */
}

void sf_sky_clamp_to_bounds(sf_sky_form form, sf_sky_bounds bounds, double *coeffs, double *scale) {
  int nc = sf_sky_form_n_coeffs(form);
  for (int i = 0; i <= nc; ++i) {
    double lo, hi, *v = i < nc ? &coeffs[i] : scale;
    sf_sky_coeff_bounds(form, bounds, i, &lo, &hi);
    if (*v < lo) *v = lo;
    if (*v > hi) *v = hi;
  }
}

double sf_sky_fit_cost(const sf_sky_fit_data *d, const double *coeffs, double scale) {
  double cost = 0.0;
  for (int i = 0; i < d->n; ++i) {
    double f = sf_sky_form_f(d->form, coeffs, d->cos_theta[i], d->gamma[i], d->cos_gamma[i], NULL);
    double r = d->weight * (scale * f - d->radiance[(size_t)i * d->stride]);
    cost += 0.5 * r * r;
  }
  return cost;
}

int sf_fit_sky_config(const sf_sky_fit_data *d, sf_sky_bounds bounds, int fix_scale,
                      const sf_lsq_options *o, double *coeffs, double *scale,
                      sf_lsq_summary *summary, sf_error *err) {
  int nc = sf_sky_form_n_coeffs(d->form);
  sf_sky_clamp_to_bounds(d->form, bounds, coeffs, scale);
  sky_fit_view view;
  sf_lsq_problem *p = sf_lsq_problem_new();
  if (!p || sky_view_make(d, &view)) {
    sf_lsq_problem_free(p);
    memset(summary, 0, sizeof *summary);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the sky fit");
  }
  int blocks[2] = {sf_lsq_add_block(p, coeffs, nc), sf_lsq_add_block(p, scale, 1)};
  for (int i = 0; i <= nc; ++i) {
    double lo, hi;
    sf_sky_coeff_bounds(d->form, bounds, i, &lo, &hi);
    if (i < nc) sf_lsq_set_bounds(p, blocks[0], i, lo, hi);
    else if (!fix_scale) sf_lsq_set_bounds(p, blocks[1], 0, lo, hi);
  }
  if (fix_scale) sf_lsq_set_constant(p, blocks[1]);
  /* all samples as one block through its Gram matrix: Ceres works on
   * n_coeffs + 2 rows whatever the number of samples (fit/ceres_shim.h) */
  sf_lsq_add_gram_residuals(p, sky_gram, &view, 2, blocks);
  int rc = sf_lsq_solve(p, o, summary);
  sf_lsq_problem_free(p);
  sky_view_free(&view);
  if (rc != 0)
    return sf_fail(err, SF_ERR_INTERNAL, "%s fit failed: %s", sf_sky_form_model_name(d->form),
                   summary->message);
  return SF_OK;
}

int sf_fit_sky_multistart(const sf_sky_fit_data *d, sf_sky_bounds bounds, int fix_scale,
                          const sf_lsq_options *o, int n_starts,
                          const double (*starts)[SF_HOSEK_N_COEFFS + 1],
                          double *coeffs, double *scale, int *winner, sf_lsq_summary *summary,
                          double *final_costs, sf_error *err) {
  int nc = sf_sky_form_n_coeffs(d->form);
  double best_cost = INFINITY;
  *winner = -1;
  sf_error last = {0};
  for (int s = 0; s < n_starts; ++s) {
    double c[SF_HOSEK_N_COEFFS + 1];
    memcpy(c, starts[s], sizeof(double) * (size_t)(nc + 1));
    sf_lsq_summary sum;
    sf_error e = {0};
    int rc = sf_fit_sky_config(d, bounds, fix_scale, o, c, &c[nc], &sum, &e);
    double cost = rc == 0 ? sum.final_cost : INFINITY;
    if (rc != 0) last = e;
    if (final_costs) final_costs[s] = cost;
    if (cost < best_cost) {
      best_cost = cost;
      *winner = s;
      memcpy(coeffs, c, sizeof(double) * (size_t)nc);
      *scale = c[nc];
      *summary = sum;
    }
  }
  if (*winner < 0)
    return sf_fail(err, SF_ERR_INTERNAL, "every start failed; last: %s", last.message);
  return SF_OK;
}

