#include "fit/fit_sky_config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK 1024

typedef struct chunk {
  const sf_sky_fit_data *d;
  int begin, count;
} chunk;

/* Blocks: [0] coefficients, [1] scale. */
static int sky_residuals(void *user, const double *const *params, double *r, double **jac) {
  const chunk *c = user;
  const sf_sky_fit_data *d = c->d;
  int nc = sf_sky_form_n_coeffs(d->form);
  const double *coeffs = params[0];
  double scale = params[1][0];
  for (int t = 0; t < c->count; ++t) {
    int i = c->begin + t;
    double grad[SF_HOSEK_N_COEFFS];
    double f = sf_sky_form_f(d->form, coeffs, d->cos_theta[i], d->gamma[i], d->cos_gamma[i], grad);
    r[t] = d->weight * (scale * f - d->radiance[(size_t)i * d->stride]);
    if (!isfinite(r[t])) return 0;
    if (jac && jac[0])
      for (int k = 0; k < nc; ++k) jac[0][t * nc + k] = d->weight * scale * grad[k];
    if (jac && jac[1]) jac[1][t] = d->weight * f;
  }
  return 1;
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
  int n_chunks = (d->n + CHUNK - 1) / CHUNK;
  chunk *chunks = calloc((size_t)n_chunks, sizeof *chunks);
  sf_lsq_problem *p = sf_lsq_problem_new();
  if (!chunks || !p) {
    free(chunks);
    sf_lsq_problem_free(p);
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
  for (int c = 0; c < n_chunks; ++c) {
    chunks[c].d = d;
    chunks[c].begin = c * CHUNK;
    chunks[c].count = d->n - c * CHUNK < CHUNK ? d->n - c * CHUNK : CHUNK;
    sf_lsq_add_residuals(p, sky_residuals, &chunks[c], chunks[c].count, 2, blocks,
                         SF_LSQ_LOSS_NONE, 0.0);
  }
  int rc = sf_lsq_solve(p, o, summary);
  sf_lsq_problem_free(p);
  free(chunks);
  if (rc != 0)
    return sf_fail(err, SF_ERR_INTERNAL, "%s fit failed: %s", sf_sky_form_model_name(d->form),
                   summary->message);
  return SF_OK;
}

int sf_fit_sky_multistart(const sf_sky_fit_data *d, sf_sky_bounds bounds, int fix_scale,
                          const sf_lsq_options *o, int n_starts, const double *starts,
                          double *coeffs, double *scale, int *winner, sf_lsq_summary *summary,
                          double *final_costs, sf_error *err) {
  int nc = sf_sky_form_n_coeffs(d->form);
  double best_cost = INFINITY;
  *winner = -1;
  sf_error last = {0};
  for (int s = 0; s < n_starts; ++s) {
    double c[SF_HOSEK_N_COEFFS + 1];
    memcpy(c, starts + (size_t)s * (nc + 1), sizeof(double) * (size_t)(nc + 1));
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
