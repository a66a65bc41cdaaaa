/* Our fitted Hosek and Preetham/Perez skies (SPEC §7.2,
 * models/hosek_sky_model.h) as sky-radiance candidates: fitted with
 * sf_fit_sky_elevation (fit/fit_sky_elevation.h) to the reference tables
 * over the scene's sun range above the horizon, cached as their weights
 * file (fit/candidate_cache.h), emitted by codegen/emit_sky.h. Valid for a
 * viewer on the ground (h = 0) and the sun up (SPEC §5).
 *
 * Evaluation is what the emitted skyfit_<model>_sky_radiance(mu, mu_s, nu)
 * computes: inputs clamped as sf_sky_radiance_clamped does (h is not an
 * input: a ground viewer; below the horizon the horizon's radiance), in
 * double for the errors and operation for operation in float32 for the
 * cost: the Bezier state of the sun elevation, then F. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/emit_sky.h"
#include "fit/candidate_cache.h"
#include "fit/candidate_fitted.h"
#include "fit/fit_sky_elevation.h"
#include "fit/fit_weights_doc.h"
#include "models/hosek_dataset.h"
#include "util/cache_prune.h"
#include "util/constants.h"

typedef struct sky_form_ctx {
  sf_elevation_sky_model model;
  int n_channels, n_coeffs;
  float cp[SF_MAX_CHANNELS][SF_BEZIER_POINTS][SF_HOSEK_N_COEFFS + 1];   /* coefficients, then scale */
} sky_form_ctx;

static void sky_form_eval(const void *ctx, const double *in, double *out) {
  sf_sky_radiance_clamped(&((const sky_form_ctx *)ctx)->model, in[1], in[2], in[3], out);
}

static float clampf(float x, float lo, float hi) { return fminf(fmaxf(x, lo), hi); }

/* models/single_scattering.h sf_clamp_nu in float: nu within
 * mu mu_s +- sqrt((1 - mu^2)(1 - mu_s^2)). */
static float clamp_nu_f(float mu, float mu_s, float nu) {
  float s = sqrtf(fmaxf(0.0f, (1.0f - mu * mu) * (1.0f - mu_s * mu_s)));
  return clampf(nu, mu * mu_s - s, mu * mu_s + s);
}

static void sky_form_eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const sky_form_ctx *s = ctx;
  const int nc = s->n_channels, hosek = s->model.form == SF_SKY_FORM_HOSEK;
  const float two_over_pi = (float)(2.0 / SF_PI);
  for (size_t p = 0; p < n; ++p) {
    const float *x_in = in + 4 * p;
    float *o = out + (size_t)nc * p;
    float ct = clampf(x_in[1], hosek ? 0.0f : (float)SF_SKY_PEREZ_MIN_MU, 1.0f);
    float ms = clampf(x_in[2], -1.0f, 1.0f);
    float cg = clamp_nu_f(ct, ms, clampf(x_in[3], -1.0f, 1.0f));
    float gamma = acosf(cg);
    float x = powf(clampf(asinf(ms) * two_over_pi, 0.0f, 1.0f), 1.0f / 3.0f);   /* models/hosek_bezier.h */
    float u = 1.0f - x;
    float w[6] = {u * u * u * u * u, 5.0f * u * u * u * u * x, 10.0f * u * u * u * x * x,
                  10.0f * u * u * x * x * x, 5.0f * u * x * x * x * x, x * x * x * x * x};
    for (int k = 0; k < nc; ++k) {
      float c[SF_HOSEK_N_COEFFS + 1] = {0};
      for (int i = 0; i <= s->n_coeffs; ++i)
        for (int j = 0; j < 6; ++j) c[i] += w[j] * s->cp[k][j][i];
      float f;
      if (hosek) {   /* seed 000 eq. 35-36 */
        float q = 1.0f + c[7] * c[7] - 2.0f * c[7] * cg;
        float chi = (1.0f + cg * cg) / (q * sqrtf(q));
        f = (1.0f + c[0] * expf(c[1] / (ct + 0.01f))) *
            (c[2] + c[3] * expf(c[4] * gamma) + c[5] * cg * cg + c[6] * chi + c[8] * sqrtf(ct));
      } else {       /* seed 000 eq. 33 */
        f = (1.0f + c[0] * expf(c[1] / ct)) * (1.0f + c[2] * expf(c[3] * gamma) + c[4] * cg * cg);
      }
      o[k] = fmaxf(c[s->n_coeffs] * f, 0.0f);   /* never negative (codegen/emit_sky.h) */
    }
  }
}

static void emit(struct sf_code_writer *w, const void *model) { sf_emit_sky(w, model); }

static int applies(const sf_candidate_inputs *in, sf_sky_form form, char *why, size_t why_len) {
  const char *name = sf_sky_form_model_name(form);
  if (!sf_candidate_sky_tables_ready(in, why, why_len)) return 0;
  if (in->domain.h_min_km > 0.0) {
    snprintf(why, why_len, "%s models a viewer on the ground; the scene's lowest viewer is at %g km", name,
             in->domain.h_min_km);
    return 0;
  }
  if (!(in->domain.mu_s_max > 0.0)) {
    snprintf(why, why_len, "%s models the sun above the horizon; the scene's sun never rises", name);
    return 0;
  }
  return 1;
}

int sf_candidate_applies_hosek(const sf_candidate_inputs *in, char *why, size_t why_len) {
  return applies(in, SF_SKY_FORM_HOSEK, why, why_len);
}
int sf_candidate_applies_preetham(const sf_candidate_inputs *in, char *why, size_t why_len) {
  return applies(in, SF_SKY_FORM_PEREZ, why, why_len);
}

/* Fits the model and writes its weights file to path (if not ""). */
static int fit_and_store(const sf_candidate_inputs *in, const sf_sky_elevation_options *o,
                         const sf_scene_domain *valid, const char *path, sf_elevation_sky_model *m, sf_error *err) {
  sf_hosek_dataset *published = NULL;
  if (in->atm->n_channels == SF_HOSEK_DATASET_CHANNELS) {
    published = malloc(sizeof *published);
    if (!published) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
    if (sf_hosek_dataset_load_default(published, err) != SF_OK) {
      free(published);
      return err->status;
    }
  }
  sf_sky_elevation_report *rep = calloc(1, sizeof *rep);
  if (!rep) {
    free(published);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  int status = sf_fit_sky_elevation(in->sky, o, published, m, rep, err);
  free(published);
  if (status == SF_OK && path[0])
    status = sf_sky_form_weights_write(in->atm, valid, o, sf_parameterization_name(in->tables->params.kind), m, rep,
                                       path, err);
  free(rep);
  return status;
}

void sf_candidate_sky_options(const sf_candidate_inputs *in, sf_sky_form form, sf_sky_elevation_options *o,
                              sf_scene_domain *valid) {
  sf_sky_elevation_options_default(o, form);
  o->elevation_min_rad = asin(fmax(0.0, in->domain.mu_s_min));
  o->elevation_max_rad = asin(fmin(1.0, in->domain.mu_s_max));
  /* --quick: a coarser view grid, the same 19 suns. With 11 the Bezier
   * swung between them: the default tables' Hosek came out at RMSE 0.0081
   * (0.0115 held out) against 0.0015 with 19, worse than the published
   * Hosek's 0.0051, for 0.6 s saved (skyfit fit hosek --grid 8x12) */
  if (in->quick) {
    o->n_theta = 8;
    o->n_phi = 12;
  }
  *valid = in->domain;
  valid->h_min_km = valid->h_max_km = 0.0;
  valid->mu_min = 0.0;
  valid->mu_max = 1.0;
  valid->mu_s_min = sin(o->elevation_min_rad);
  valid->mu_s_max = sin(o->elevation_max_rad);
}

/* Says which channels' fit across elevations stopped at the iteration cap
 * (training.elevation_fit_at_iteration_cap of the weights file, so a fit
 * from the cache says it too): usable, but not converged. */
static void note_iteration_cap(const sf_candidate_inputs *in, const char *name, const char *path) {
  sf_weights w;
  sf_error ignored = {0};
  if (!in->note || sf_weights_load_file(path, NULL, &w, &ignored) != SF_OK) return;
  const cJSON *tr = cJSON_GetObjectItemCaseSensitive(w.root, "training");
  const cJSON *cap = cJSON_GetObjectItemCaseSensitive(tr, "elevation_fit_at_iteration_cap");
  const cJSON *most = cJSON_GetObjectItemCaseSensitive(tr, "max_iterations");
  char channels[256] = "";
  const cJSON *c;
  cJSON_ArrayForEach(c, cap) {
    if (cJSON_IsString(c))
      snprintf(channels + strlen(channels), sizeof channels - strlen(channels), "%s%s", channels[0] ? ", " : "",
               c->valuestring);
  }
  if (channels[0] && cJSON_IsNumber(most)) {
    char text[600];
    snprintf(text, sizeof text,
             "%s: the fit across sun elevations stopped at its %d-iteration cap in channel(s) %s before "
             "converging: a usable fit, not a converged one", name, (int)most->valuedouble, channels);
    in->note(in->note_ctx, text);
  }
  sf_weights_free(&w);
}

static int make(const sf_candidate_inputs *in, sf_sky_form form, sf_candidate *out, sf_error *err) {
  const char *name = sf_sky_form_model_name(form);
  sf_sky_elevation_options o;
  sf_scene_domain valid;
  sf_candidate_sky_options(in, form, &o, &valid);
  o.progress = in->run.progress;
  o.progress_ctx = in->run.progress_ctx;

  sf_cache_key key;
  sf_cache_key_begin(&key, name, in);
  sf_cache_key_add_tables(&key, in);
  sf_cache_key_add_number(&key, "elevations", o.n_elevations);
  sf_cache_key_add_number(&key, "n_theta", o.n_theta);
  sf_cache_key_add_number(&key, "n_phi", o.n_phi);
  char path[4400];
  if (sf_cache_path(in->cache_dir, SF_CACHE_FITS, name, &key, path, sizeof path, err) != SF_OK) return err->status;

  sf_elevation_sky_model *m = calloc(1, sizeof *m);
  if (!m) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int loaded = 0;
  if (sf_cache_exists(path)) {
    sf_error lerr = {0};
    loaded = sf_cache_fit_belongs(path, name, in->atm, &valid, &lerr) == SF_OK &&
             sf_elevation_sky_load(path, form, m, NULL, &lerr) == SF_OK;
    if (loaded) sf_cache_entry_used(path);
    if (!loaded && in->note) {
      char text[1200];
      snprintf(text, sizeof text, "%s: cached fit unusable, refitting: %s", name, lerr.message);
      in->note(in->note_ctx, text);
    }
  }
  /* Fresh fits too are evaluated as loaded from the file: a rerun computes the same. */
  if (!loaded && (fit_and_store(in, &o, &valid, path, m, err) != SF_OK ||
                  (path[0] && sf_elevation_sky_load(path, form, m, NULL, err) != SF_OK))) {
    free(m);
    return err->status;
  }
  if (path[0]) note_iteration_cap(in, name, path);
  char weights[sizeof out->weights_path] = "";
  if (path[0] && in->work_dir &&
      sf_copy_weights_to_work_dir(path, in->work_dir, name, weights, sizeof weights, err) != SF_OK) {
    free(m);
    return err->status;
  }
  int hosek = form == SF_SKY_FORM_HOSEK;
  char description[400];
  snprintf(description, sizeof description,
           "%s per channel (seed 000 eq. %s), fitted to the reference sky per sun elevation and channel "
           "(Ceres), then across elevations as a quintic Bezier in elevation^(1/3) (Hosek 2012). Ground "
           "viewer, sun %.1f..%.1f deg.",
           hosek ? "Hosek F(theta,gamma) R, 9 coefficients" : "Perez F(theta,gamma) K, 5 coefficients",
           hosek ? "35-36" : "33", o.elevation_min_rad * 180.0 / SF_PI, o.elevation_max_rad * 180.0 / SF_PI);
  int status = sf_candidate_of_sky_model(m, &valid, SF_ROLE_FITTED, name,
                                         hosek ? "Hosek-Wilkie (fitted)" : "Preetham/Perez (fitted)", description,
                                         out, err);
  free(m);
  if (status == SF_OK) snprintf(out->weights_path, sizeof out->weights_path, "%s", weights);
  return status;
}

int sf_candidate_of_sky_model(const sf_elevation_sky_model *m, const sf_scene_domain *valid, sf_candidate_role role,
                              const char *name, const char *label, const char *description, sf_candidate *out,
                              sf_error *err) {
  sky_form_ctx *s = calloc(1, sizeof *s);
  if (!s) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  s->model = *m;
  s->n_channels = s->model.n_channels;
  s->n_coeffs = s->model.n_coeffs;
  for (int k = 0; k < s->n_channels; ++k)
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
      for (int i = 0; i < s->n_coeffs; ++i) s->cp[k][j][i] = (float)s->model.coefficients[k][j][i];
      s->cp[k][j][s->n_coeffs] = (float)s->model.scale[k][j];
    }
  sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, role, name, label);
  snprintf(out->description, sizeof out->description, "%s", description);
  out->n_channels = s->n_channels;
  out->n_params = (long)s->n_channels * SF_BEZIER_POINTS * (s->n_coeffs + 1);
  out->constant_bytes = 4 * out->n_params;
  out->valid = *valid;
  snprintf(out->emit_name, sizeof out->emit_name, "%s", sf_sky_form_model_name(m->form));
  /* The emitted code returns vec1..vec4 (codegen/emit_sky.c): a model of
   * more channels is measured and reported, and not emitted (it had been
   * selected, and the build failed at code generation). */
  if (s->n_channels <= 4) {
    out->emit = emit;
    out->emit_model = &s->model;
  }
  out->emit_ground_viewer = 1;
  out->eval = sky_form_eval;
  out->eval_f32 = sky_form_eval_f32;
  out->ctx = s;
  out->free_ctx = free;
  return SF_OK;
}

int sf_candidate_make_hosek(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err) {
  return make(in, SF_SKY_FORM_HOSEK, out, err);
}
int sf_candidate_make_preetham(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err) {
  return make(in, SF_SKY_FORM_PEREZ, out, err);
}
