#include "fit/build_pipeline_spectral4.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/emit_spectral4.h"
#include "fit/candidate_cache.h"
#include "fit/spectral4_run.h"
#include "models/atmosphere_file.h"
#include "models/weights_file.h"
#include "util/cache_prune.h"

static const char *const method_names[SF_REPORT_COLOR_METHODS] = {"spectral4", "rgb_680_550_440", "uniform4"};
static const char *const atm_names[2] = {"without_aerosols", "with_aerosols"};

static double number(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* The report's summary from a loaded weights file. */
static int summarise(const sf_weights *w, sf_report_spectral4 *out, sf_error *err) {
  int shape[1] = {4};
  if (sf_weights_param(w, "wavelengths_nm", 1, shape, out->lambda_nm, 4, err) != SF_OK ||
      sf_weights_param(w, "weights_nm", 1, shape, out->weight_nm, 4, err) != SF_OK)
    return err->status;
  const cJSON *m = cJSON_GetObjectItemCaseSensitive(w->root, "metrics");
  out->loss = number(m, "loss");
  out->rgb_loss = number(m, "rgb_680_550_440_loss");
  out->uniform_loss = number(m, "uniform4_loss");
  out->has_aerosols = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(m, "atmosphere_has_aerosols"));
  for (int a = 0; a < 2; ++a) {
    const cJSON *oa = cJSON_GetObjectItemCaseSensitive(m, atm_names[a]);
    for (int k = 0; k < SF_REPORT_COLOR_METHODS; ++k) {
      const cJSON *st = cJSON_GetObjectItemCaseSensitive(oa, method_names[k]);
      snprintf(out->method[k], sizeof out->method[k], "%s", method_names[k]);
      out->mean_de[a][k] = number(st, "mean_delta_e2000");
      out->p99_de[a][k] = number(st, "p99_delta_e2000");
      out->max_de[a][k] = number(st, "max_delta_e2000");
      out->samples[a][k] = number(st, "samples");
      if (!isfinite(out->mean_de[a][k]) || !isfinite(out->p99_de[a][k]) || !isfinite(out->max_de[a][k]) ||
          !isfinite(out->samples[a][k]))
        return sf_fail(err, SF_ERR_INPUT, "%s: metrics.%s.%s: missing or not a number", w->source, atm_names[a],
                       method_names[k]);
    }
  }
  if (!isfinite(out->loss) || !isfinite(out->rgb_loss) || !isfinite(out->uniform_loss))
    return sf_fail(err, SF_ERR_INPUT, "%s: metrics: loss figures missing", w->source);
  return SF_OK;
}

int sf_build_spectral4(const sf_scene *scene, const sf_build_spectral4_options *o, sf_report_spectral4 *out,
                       sf_error *err) {
  memset(out, 0, sizeof *out);
  sf_spectral4_run_options ro;
  sf_spectral4_run_options_default(&ro);
  if (o->quick) {
    ro.res.transmittance_mu = 32;
    ro.res.transmittance_h = 8;
    ro.res.scattering_h = 4;
    ro.res.scattering_mu = 16;
    ro.res.scattering_mu_s = 8;
    ro.res.scattering_nu = 4;
    ro.orders = 3;
    ro.train = (sf_spectral4_grid){6, 8, 6, 1};
    ro.eval = (sf_spectral4_grid){8, 8, 6, 0};
    ro.fit.grid_step_nm = 20.0;
    ro.fit.max_evaluations = 2000;
    ro.fit.restarts = 1;
  }
  ro.cache_dir = o->cache_dir;
  ro.n_threads = o->run.n_threads;
  ro.progress = o->run.progress;
  ro.progress_ctx = o->run.progress_ctx;
  ro.note = o->note;
  ro.note_ctx = o->note_ctx;

  /* Everything the fit depends on: the atmosphere, the scene's viewers,
   * views and sun range (the samples), and the options. */
  char hash[17];
  sf_atmosphere_hash_hex(&scene->atmosphere, hash);
  sf_cache_key k;
  k.text[0] = '\0';
  sf_cache_key_add_text(&k, "model", "spectral4");
  char code[256];
  sf_cache_code_identity(code, sizeof code);
  sf_cache_key_add_text(&k, "code", code);
  sf_cache_key_add_text(&k, "atmosphere", hash);
  sf_cache_key_add_number(&k, "h0", scene->viewer_altitude_km[0]);
  sf_cache_key_add_number(&k, "h1", scene->viewer_altitude_km[1]);
  sf_cache_key_add_number(&k, "sun0", scene->sun_elevation_deg[0]);
  sf_cache_key_add_number(&k, "sun1", scene->sun_elevation_deg[1]);
  sf_cache_key_add_number(&k, "view", scene->view);
  sf_cache_key_add_number(&k, "quick", o->quick);
  char path[4400];
  if (sf_cache_path(o->cache_dir, SF_CACHE_FITS, "spectral4", &k, path, sizeof path, err) != SF_OK) return err->status;

  sf_weights w;
  memset(&w, 0, sizeof w);
  int loaded = 0;
  if (sf_cache_exists(path)) {
    sf_error lerr = {0};
    /* what the header will need (codegen checks it only when it emits, and
     * a damaged entry had failed every build, naming a staging path long
     * gone), and this atmosphere's fit */
    sf_spectral4_emit emit;
    sf_scene_domain domain;
    sf_spectral4_weights_domain(scene, &domain);
    loaded = sf_weights_load_file(path, "spectral4", &w, &lerr) == SF_OK && summarise(&w, out, &lerr) == SF_OK &&
             sf_spectral4_emit_load(&w, &emit, &lerr) == SF_OK &&
             sf_cache_weights_belong(&w, &scene->atmosphere, &domain, &lerr) == SF_OK;
    if (!loaded) {
      sf_weights_free(&w);
      memset(&w, 0, sizeof w);
      if (o->note) {
        char text[1200];
        snprintf(text, sizeof text, "spectral4: cached fit unusable, refitting: %s", lerr.message);
        o->note(o->note_ctx, text);
      }
    }
  }
  out->from_cache = loaded;
  if (loaded) sf_cache_entry_used(path);
  if (!loaded) {
    sf_spectral4_report *rep = calloc(1, sizeof *rep);
    if (!rep) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
    cJSON *doc = NULL;
    int status = sf_spectral4_run(scene, &ro, rep, &doc, err);
    free(rep);
    if (status == SF_OK) status = sf_weights_write(doc, path, err);
    cJSON_Delete(doc);
    if (status != SF_OK) return status;
    if (sf_weights_load_file(path, "spectral4", &w, err) != SF_OK || summarise(&w, out, err) != SF_OK) {
      sf_weights_free(&w);
      return err->status;
    }
  }
  sf_weights_free(&w);
  if (sf_copy_weights_to_work_dir(path, o->work_dir, "spectral4", out->weights_path, sizeof out->weights_path, err) !=
      SF_OK)
    return err->status;
  out->present = 1;
  return SF_OK;
}

int sf_build_spectral4_check(const sf_scene *scene, sf_error *err) {
  if (scene->color != SF_COLOR_SPECTRAL4 || !(scene->quantities & SF_QUANTITY_SKY_RADIANCE)) return SF_OK;
  sf_spectral4_run_options ro;
  sf_spectral4_run_options_default(&ro);
  sf_error inner = {0};
  int status = sf_spectral4_check_scene(scene, &ro, &inner);
  if (status == SF_OK) return SF_OK;
  if (status != SF_ERR_INPUT) return sf_fail(err, status, "%s", inner.message);
  return sf_fail(err, SF_ERR_INPUT, "%s: %s (the scene's \"color\": \"spectral4\")",
                 scene->atmosphere_path[0] ? scene->atmosphere_path : "the built-in atmosphere", inner.message);
}
