#include "fit/candidate_metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "data/parallel_rows.h"
#include "models/rng.h"
#include "util/constants.h"
#include "util/clock.h"
#include "util/sort_doubles.h"

int sf_domain_samples_make(const sf_scene_domain *d, sf_candidate_quantity q, size_t n, uint64_t seed,
                           sf_domain_samples *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  if (n == 0) return sf_fail(err, SF_ERR_INPUT, "no samples asked for");
  out->quantity = q;
  out->n_inputs = sf_candidate_n_inputs(q);
  out->n = n;
  out->inputs = malloc(sizeof(double) * n * (size_t)out->n_inputs);
  if (!out->inputs) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for %zu samples", n);
  sf_rng rng;
  sf_rng_seed(&rng, seed, 0x646f6d61696eULL /* "domain" */, (uint64_t)q);
  for (size_t i = 0; i < n; ++i) {
    double *p = out->inputs + i * (size_t)out->n_inputs;
    double h = d->h_min_km + (d->h_max_km - d->h_min_km) * sf_rng_uniform(&rng);
    double mu = d->mu_min + (d->mu_max - d->mu_min) * sf_rng_uniform(&rng);
    double mu_s = d->mu_s_min + (d->mu_s_max - d->mu_s_min) * sf_rng_uniform(&rng);
    double phi = SF_PI * sf_rng_uniform(&rng);
    p[0] = h;
    p[1] = mu;
    if (out->n_inputs == 4) {
      double nu = mu * mu_s + sqrt(fmax(0.0, (1.0 - mu * mu) * (1.0 - mu_s * mu_s))) * cos(phi);
      p[2] = mu_s;
      p[3] = fmax(-1.0, fmin(1.0, nu));
    }
  }
  return SF_OK;
}

void sf_domain_samples_free(sf_domain_samples *s) {
  free(s->inputs);
  memset(s, 0, sizeof *s);
}

typedef struct values_job {
  const sf_candidate *c;
  const sf_domain_samples *s;
  double *values;
} values_job;

enum { VALUES_ROW = 256 };

static void values_row(void *ctx, int thread, long row) {
  (void)thread;
  const values_job *j = ctx;
  size_t begin = (size_t)row * VALUES_ROW, end = begin + VALUES_ROW;
  if (end > j->s->n) end = j->s->n;
  for (size_t i = begin; i < end; ++i)
    j->c->eval(j->c->ctx, j->s->inputs + i * (size_t)j->s->n_inputs,
               j->values + i * (size_t)j->c->n_channels);
}

void sf_candidate_values(const sf_candidate *c, const sf_domain_samples *s, double *values,
                         const sf_precompute_options *run) {
  values_job job = {c, s, values};
  long rows = (long)((s->n + VALUES_ROW - 1) / VALUES_ROW);
  sf_precompute_options quiet = {0};
  if (run) quiet.n_threads = run->n_threads;
  sf_parallel_rows(rows, &quiet, NULL, values_row, &job);
}

void sf_error_metrics_compute(const double *model, const double *reference, size_t n_values,
                              sf_error_metrics *out, size_t *n_non_finite) {
  memset(out, 0, sizeof *out);
  size_t bad = 0, n = 0;
  double ref_sq = 0.0;
  for (size_t i = 0; i < n_values; ++i)
    if (isfinite(reference[i])) ref_sq += reference[i] * reference[i];
  double ref_rms = n_values ? sqrt(ref_sq / (double)n_values) : 0.0;
  double floor = ref_rms > 0.0 ? 1e-3 * ref_rms : 1e-300;
  double sq = 0.0, rel = 0.0, rel_below = 0.0, mx = 0.0;
  size_t below = 0;
  for (size_t i = 0; i < n_values; ++i) {
    /* |value| > SF_METRICS_MAX_VALUE counts as non-finite: its square
     * would overflow the sums (a model that blew up). */
    if (!isfinite(model[i]) || !isfinite(reference[i]) || fabs(model[i]) > SF_METRICS_MAX_VALUE) {
      ++bad;
      continue;
    }
    double e = fabs(model[i] - reference[i]);
    sq += e * e;
    if (e > mx) mx = e;
    double r = e / fmax(fabs(reference[i]), floor);
    rel += r;
    if (fabs(reference[i]) < floor) {
      rel_below += r;
      ++below;
    }
    ++n;
  }
  out->n_values = n;
  out->n_below_floor = below;
  out->mean_rel_floor_share = rel > 0.0 ? rel_below / rel : 0.0;
  out->reference_rms = ref_rms;
  if (n > 0) {
    out->rmse = sqrt(sq / (double)n);   /* seed 000 eq. 61 */
    out->max_abs = mx;
    out->mean_rel = rel / (double)n;
    out->rel_rmse = ref_rms > 0.0 ? out->rmse / ref_rms : 0.0;
  }
  if (n_non_finite) *n_non_finite = bad;
}

int sf_candidate_time_pass(const sf_candidate *c, const sf_domain_samples *s, double *ns, sf_error *err) {
  size_t n = s->n, ni = (size_t)s->n_inputs, nc = (size_t)c->n_channels;
  float *in_f = NULL, *out_f = NULL;
  double *out_d = NULL;
  if (c->eval_f32) {
    in_f = malloc(sizeof(float) * n * ni);
    out_f = malloc(sizeof(float) * n * nc);
  } else {
    out_d = malloc(sizeof(double) * nc);
  }
  if ((c->eval_f32 && (!in_f || !out_f)) || (!c->eval_f32 && !out_d)) {
    free(in_f); free(out_f); free(out_d);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory timing %s", c->name);
  }
  if (in_f)
    for (size_t i = 0; i < n * ni; ++i) in_f[i] = (float)s->inputs[i];
  volatile double sink = 0.0;
  double t0 = sf_wall_seconds();
  if (c->eval_f32) {
    c->eval_f32(c->ctx, n, in_f, out_f);
    sink += out_f[n * nc - 1];
  } else {
    double acc = 0.0;
    for (size_t i = 0; i < n; ++i) {
      c->eval(c->ctx, s->inputs + i * ni, out_d);
      acc += out_d[0];
    }
    sink += acc;
  }
  *ns = (sf_wall_seconds() - t0) * 1e9 / (double)n;
  (void)sink;
  free(in_f); free(out_f); free(out_d);
  return SF_OK;
}

void sf_cost_from_passes(const sf_candidate *c, const sf_domain_samples *s, double *ns, int passes, sf_cost *out) {
  memset(out, 0, sizeof *out);
  out->ns_median = sf_median_doubles(ns, (size_t)passes);   /* sorts ns */
  out->ns_min = ns[0];
  out->ns_max = ns[passes - 1];
  out->repetitions = passes;
  out->n_points = s->n;
  out->precision_bits = c->eval_f32 ? 32 : 64;
}
