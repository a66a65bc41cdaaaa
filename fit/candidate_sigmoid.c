/* The sigmoid-polynomial transmittance as a candidate: fitted with
 * sf_fit_sigmoid over the scene's domain (fit/fit_sigmoid.h), evaluated
 * with sf_sigmoid_model_eval, emitted with its ray geometry and segments
 * (codegen/emit_sigmoid.h sf_emit_sigmoid_ray) and timed in float32 as that
 * code computes it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "codegen/emit_sigmoid.h"
#include "fit/candidate_cache.h"
#include "fit/candidate_fitted.h"
#include "fit/fit_sigmoid.h"
#include "fit/fit_weights_doc.h"
#include "models/emitted_float.h"
#include "util/cache_prune.h"

typedef struct sigmoid_ctx {
  sf_sigmoid_model model;
  sf_sigmoid_emit emitted;   /* the model with its atmosphere's radii */
  int n_constituents, n_channels;
  float a[SF_MAX_CONSTITUENTS][4][SF_SIGMOID_N_COEFFS];
  float bottom_f, h_top_f;   /* as the emitted code holds them */
} sigmoid_ctx;

/* Fits and writes the weights file (models/sigmoid_transmittance.h) to path (if not ""). */
static int fit_and_store(const sf_candidate_inputs *in, const sf_sigmoid_fit_options *o, const char *path,
                         sf_sigmoid_model *m, sf_error *err) {
  sf_sigmoid_fit_report *rep = calloc(1, sizeof *rep);
  if (!rep) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int status = sf_fit_sigmoid(in->atm, &in->domain, o, m, rep, err);
  if (status == SF_OK && path[0]) status = sf_sigmoid_weights_write(in->atm, &in->domain, o, m, rep, path, err);
  free(rep);
  return status;
}

static void sigmoid_eval(const void *ctx, const double *in, double *out) {
  sf_sigmoid_model_eval(&((const sigmoid_ctx *)ctx)->model, in[0], in[1], out);
}

/* skyfit_sigmoid_transmittance_segment in double (eq. 43). */
static void sigmoid_segment(const void *ctx, const double *in, double *out) {
  sf_sigmoid_model_eval_segment(&((const sigmoid_ctx *)ctx)->model, in[0], in[1], in[2], out);
}

/* log T_top per channel in float32: sum_c -softplus(-x) (seed 000 §9.5). */
static void log_top_f(const sigmoid_ctx *s, float h, float mu, float *out) {
  for (int k = 0; k < s->n_channels; ++k) {
    out[k] = 0.0f;
    for (int c = 0; c < s->n_constituents; ++c) {
      const float *a = s->a[c][k];
      float x = a[0] + a[1] * h + a[2] * mu + a[3] * mu * mu;
      out[k] -= fmaxf(-x, 0.0f) + logf(1.0f + expf(-fabsf(x)));
    }
  }
}

/* The full ray in float32, operation for operation as the emitted
 * skyfit_sigmoid_transmittance (codegen/emit_sigmoid.c, with the helpers
 * skyfit_ray_enter and skyfit_sphere_hits of codegen/emit_helpers.c): a
 * viewer in space moved to where its ray enters, rays to the ground
 * reversed (eq. 43), rays past the tangent point through it. What the
 * report times (tests/test_candidate_emit.c compares the two). */
static void sigmoid_eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const sigmoid_ctx *s = ctx;
  const int nc = s->n_channels;
  const float R = s->bottom_f, h_top = s->h_top_f;
  for (size_t p = 0; p < n; ++p) {
    float *T = out + (size_t)nc * p;
    float h = fmaxf(in[2 * p], 0.0f), mu = fminf(fmaxf(in[2 * p + 1], -1.0f), 1.0f);
    if (h > h_top && !sf_emitted_ray_enter_f(R, h_top, &h, &mu, NULL, 0.0f)) {   /* above the top, missing it */
      for (int k = 0; k < nc; ++k) T[k] = 1.0f;
      continue;
    }
    float up[4], other[4];
    if (mu >= 0.0f) {
      log_top_f(s, h, mu, up);
      for (int k = 0; k < nc; ++k) T[k] = expf(up[k]);
      continue;
    }
    float r = R + h;
    float disc = -h * (r + R) + (r * mu) * (r * mu);   /* skyfit_sphere_hits(r, mu, R, -h) */
    log_top_f(s, h, -mu, up);
    if (!(disc >= 0.0f)) {   /* past the tangent point and up again */
      float h_t = fmaxf(-disc, 0.0f) / (sqrtf(r * r * ((1.0f - mu) * (1.0f + mu))) + R);
      log_top_f(s, h_t, 0.0f, other);
      for (int k = 0; k < nc; ++k) T[k] = expf(fminf(0.0f, 2.0f * other[k] - up[k]));
    } else {                 /* reversed rays from the ground point (eq. 43) */
      log_top_f(s, 0.0f, sqrtf(fmaxf(disc, 0.0f)) / R, other);
      for (int k = 0; k < nc; ++k) T[k] = expf(fminf(0.0f, other[k] - up[k]));
    }
  }
}

static void emit(struct sf_code_writer *w, const void *model) { sf_emit_sigmoid_ray(w, model); }

int sf_candidate_applies_sigmoid(const sf_candidate_inputs *in, char *why, size_t why_len) {
  if (in->atm->n_channels > 4) {
    snprintf(why, why_len, "the emitted sigmoid holds at most 4 channels, the atmosphere has %d",
             in->atm->n_channels);
    return 0;
  }
  return 1;
}

int sf_candidate_make_sigmoid(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err) {
  sigmoid_ctx *s = calloc(1, sizeof *s);
  if (!s) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_sigmoid_fit_options o;
  sf_sigmoid_fit_options_default(&o);
  if (in->quick) {
    o.n_h = 12;
    o.n_mu = 24;
  }
  o.progress = in->run.progress;
  o.progress_ctx = in->run.progress_ctx;
  sf_cache_key key;
  sf_cache_key_begin(&key, "sigmoid", in);
  sf_cache_key_add_number(&key, "n_h", o.n_h);
  sf_cache_key_add_number(&key, "n_mu", o.n_mu);
  char path[4400];
  if (sf_cache_path(in->cache_dir, SF_CACHE_FITS, "sigmoid", &key, path, sizeof path, err) != SF_OK) {
    free(s);
    return err->status;
  }
  int loaded = 0;
  if (sf_cache_exists(path)) {
    sf_error lerr = {0};
    loaded = sf_cache_fit_belongs(path, "sigmoid", in->atm, &in->domain, &lerr) == SF_OK &&
             sf_sigmoid_model_load(path, &s->model, NULL, &lerr) == SF_OK;
    if (loaded) sf_cache_entry_used(path);
    if (!loaded && in->note) {
      char text[1200];
      snprintf(text, sizeof text, "sigmoid: cached fit unusable, refitting: %s", lerr.message);
      in->note(in->note_ctx, text);
    }
  }
  /* Fresh fits too are evaluated as loaded from the file: a rerun computes the same. */
  if (!loaded && (fit_and_store(in, &o, path, &s->model, err) != SF_OK ||
                  (path[0] && sf_sigmoid_model_load(path, &s->model, NULL, err) != SF_OK))) {
    free(s);
    return err->status;
  }
  char weights[sizeof out->weights_path] = "";
  if (path[0] && in->work_dir &&
      sf_copy_weights_to_work_dir(path, in->work_dir, "sigmoid", weights, sizeof weights, err) != SF_OK) {
    free(s);
    return err->status;
  }
  s->emitted.model = s->model;
  s->emitted.bottom_radius_km = in->atm->bottom_radius_km;
  s->emitted.top_radius_km = in->atm->top_radius_km;
  s->bottom_f = (float)in->atm->bottom_radius_km;
  s->h_top_f = (float)(in->atm->top_radius_km - in->atm->bottom_radius_km);
  s->n_constituents = s->model.n_constituents;
  s->n_channels = s->model.n_channels;
  for (int c = 0; c < s->n_constituents; ++c)
    for (int k = 0; k < s->n_channels && k < 4; ++k)
      for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j) s->a[c][k][j] = (float)s->model.a[c][k][j];
  sf_candidate_init(out, SF_CANDIDATE_TRANSMITTANCE, SF_ROLE_FITTED, "sigmoid", "Sigmoid polynomial (fitted)");
  snprintf(out->description, sizeof out->description,
           "T_top = prod_c 1/(1+exp(-a1 - a2 h - a3 mu - a4 mu^2)) per constituent and channel (seed 000 §9.5), "
           "least squares (Ceres) on rays to the top over the scene's (h, mu) box; other rays from it by eq. 43 "
           "(rays to the ground reversed).");
  snprintf(out->weights_path, sizeof out->weights_path, "%s", weights);
  out->n_channels = s->n_channels;
  out->n_params = (long)s->n_constituents * s->n_channels * SF_SIGMOID_N_COEFFS;
  out->constant_bytes = 4 * out->n_params;
  out->valid = in->domain;
  snprintf(out->emit_name, sizeof out->emit_name, "sigmoid");
  out->emit = emit;
  out->emit_model = &s->emitted;
  out->eval = sigmoid_eval;
  out->eval_segment = sigmoid_segment;
  out->eval_f32 = sigmoid_eval_f32;
  out->ctx = s;
  out->free_ctx = free;
  return SF_OK;
}
