#include "fit/fit_sigmoid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fit/linear_lsq.h"
#include "models/optical_depth.h"

#define CHUNK 256

void sf_sigmoid_fit_options_default(sf_sigmoid_fit_options *o) {
  memset(o, 0, sizeof *o);
  o->n_h = 48;
  o->n_mu = 96;
  sf_lsq_options_default(&o->lsq);
}

typedef struct sigmoid_chunk {
  const double *h, *mu, *t;
  int begin, count;
} sigmoid_chunk;

static int sigmoid_residuals(void *user, const double *const *params, double *r, double **jac) {
  const sigmoid_chunk *c = user;
  for (int q = 0; q < c->count; ++q) {
    int i = c->begin + q;
    double grad[SF_SIGMOID_N_COEFFS];
    r[q] = sf_sigmoid_transmittance_grad(params[0], c->h[i], c->mu[i], grad) - c->t[i];
    if (jac && jac[0])
      for (int k = 0; k < SF_SIGMOID_N_COEFFS; ++k) jac[0][q * SF_SIGMOID_N_COEFFS + k] = grad[k];
  }
  return 1;
}

static double seconds_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Weighted logit fit: the start. */
static void logit_start(int n, const double *h, const double *mu, const double *t, double *a) {
  double *A = malloc(sizeof *A * (size_t)n * SF_SIGMOID_N_COEFFS);
  double *b = malloc(sizeof *b * (size_t)n), *w = malloc(sizeof *w * (size_t)n);
  int ok = A && b && w;
  for (int i = 0; ok && i < n; ++i) {
    double ti = fmin(fmax(t[i], 1e-12), 1.0 - 1e-12);
    A[i * 4 + 0] = 1.0;
    A[i * 4 + 1] = h[i];
    A[i * 4 + 2] = mu[i];
    A[i * 4 + 3] = mu[i] * mu[i];
    b[i] = log(ti / (1.0 - ti));
    w[i] = ti * (1.0 - ti) + 1e-6;
  }
  if (!ok || sf_linear_lsq(n, SF_SIGMOID_N_COEFFS, A, b, w, a) != 0) {
    a[0] = 1.0;
    a[1] = a[2] = a[3] = 0.0;
  }
  free(A);
  free(b);
  free(w);
}

int sf_fit_sigmoid(const sf_atmosphere *atm, const sf_scene_domain *domain,
                   const sf_sigmoid_fit_options *o, sf_sigmoid_model *out,
                   sf_sigmoid_fit_report *rep, sf_error *err) {
  double t0 = seconds_now();
  memset(out, 0, sizeof *out);
  memset(rep, 0, sizeof *rep);
  if (o->n_h < 2 || o->n_mu < 2 || (long)o->n_h * o->n_mu > 4000000L)
    return sf_fail(err, SF_ERR_INPUT, "sigmoid fit: grid %d x %d: need 2..4e6 points per side product",
                   o->n_h, o->n_mu);
  int nc = atm->n_constituents, nk = atm->n_channels, n = o->n_h * o->n_mu;
  double thickness = sf_atmosphere_thickness_km(atm);
  double h0 = fmax(domain->h_min_km, 0.0), h1 = fmin(domain->h_max_km, thickness);
  if (h1 < h0) h0 = h1;
  out->n_constituents = nc;
  out->n_channels = nk;
  rep->n_points = n;
  double *h = malloc(sizeof *h * (size_t)n), *mu = malloc(sizeof *mu * (size_t)n);
  double *depth = malloc(sizeof *depth * (size_t)n * (size_t)nc);
  double *t = malloc(sizeof *t * (size_t)n);
  double *model_total = malloc(sizeof *model_total * (size_t)n * (size_t)nk);
  double *ref_total = malloc(sizeof *ref_total * (size_t)n * (size_t)nk);
  int n_chunks = (n + CHUNK - 1) / CHUNK;
  sigmoid_chunk *chunks = calloc((size_t)n_chunks, sizeof *chunks);
  int status = (h && mu && depth && t && model_total && ref_total && chunks)
                   ? SF_OK
                   : sf_fail(err, SF_ERR_INTERNAL, "out of memory for the sigmoid fit");
  for (int i = 0; status == SF_OK && i < o->n_h; ++i) {
    for (int j = 0; j < o->n_mu; ++j) {
      int p = i * o->n_mu + j;
      h[p] = h0 + (h1 - h0) * i / (o->n_h - 1);
      mu[p] = domain->mu_min + (domain->mu_max - domain->mu_min) * j / (o->n_mu - 1);
      sf_optical_depth_ray(atm, h[p], mu[p], SF_RAY_END_NEAREST, &depth[(size_t)p * nc]);
    }
    if (o->progress) o->progress(o->progress_ctx, "reference optical depth", (double)(i + 1) / o->n_h);
  }
  for (int p = 0; status == SF_OK && p < n * nk; ++p) model_total[p] = ref_total[p] = 1.0;
  for (int c = 0; c < nc && status == SF_OK; ++c) {
    for (int k = 0; k < nk && status == SF_OK; ++k) {
      sf_sigmoid_fit_entry *en = &rep->entry[c][k];
      double *a = out->a[c][k];
      double ext = sf_extinction(atm, c, k);
      for (int p = 0; p < n; ++p) t[p] = exp(-ext * depth[(size_t)p * nc + c]);
      if (ext == 0.0) {
        en->transparent = 1;
        a[0] = SF_SIGMOID_TRANSPARENT_A1;
        a[1] = a[2] = a[3] = 0.0;
      } else {
        logit_start(n, h, mu, t, a);
        sf_lsq_problem *prob = sf_lsq_problem_new();
        if (!prob) {
          status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
          break;
        }
        int block = sf_lsq_add_block(prob, a, SF_SIGMOID_N_COEFFS);
        for (int q = 0; q < n_chunks; ++q) {
          chunks[q] = (sigmoid_chunk){h, mu, t, q * CHUNK, n - q * CHUNK < CHUNK ? n - q * CHUNK : CHUNK};
          sf_lsq_add_residuals(prob, sigmoid_residuals, &chunks[q], chunks[q].count, 1, &block,
                               SF_LSQ_LOSS_NONE, 0.0);
        }
        sf_lsq_summary sum;
        int rc = sf_lsq_solve(prob, &o->lsq, &sum);
        sf_lsq_problem_free(prob);
        if (rc != 0) {
          status = sf_fail(err, SF_ERR_INTERNAL, "sigmoid fit of %s channel %s failed: %s",
                           atm->constituents[c].name, atm->channel_names[k], sum.message);
          break;
        }
        en->start_cost = sum.initial_cost;
        en->final_cost = sum.final_cost;
        en->iterations = sum.iterations;
      }
      double sse = 0;
      for (int p = 0; p < n; ++p) {
        double m = sf_sigmoid_transmittance(a, h[p], mu[p]), d = m - t[p];
        sse += d * d;
        if (!(fabs(d) <= en->max_abs)) {
          en->max_abs = fabs(d);
          en->worst_h_km = h[p];
          en->worst_mu = mu[p];
        }
        model_total[(size_t)p * nk + k] *= m;
        ref_total[(size_t)p * nk + k] *= t[p];
      }
      en->rmse = sqrt(sse / n);
      if (o->progress) o->progress(o->progress_ctx, "sigmoid fits", (double)(c * nk + k + 1) / (nc * nk));
    }
  }
  if (status == SF_OK) {
    double sse = 0;
    for (int p = 0; p < n; ++p)
      for (int k = 0; k < nk; ++k) {
        double d = model_total[(size_t)p * nk + k] - ref_total[(size_t)p * nk + k];
        sse += d * d;
        if (!(fabs(d) <= rep->max_abs)) {
          rep->max_abs = fabs(d);
          rep->worst_h_km = h[p];
          rep->worst_mu = mu[p];
          rep->worst_channel = k;
        }
      }
    rep->rmse = sqrt(sse / ((double)n * nk));
  }
  free(h);
  free(mu);
  free(depth);
  free(t);
  free(model_total);
  free(ref_total);
  free(chunks);
  rep->seconds = seconds_now() - t0;
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}
