#include "cli/eval_model.h"

#include <stdio.h>
#include <string.h>

#include "codegen/emit_sky.h"
#include "models/atmosphere_file.h"
#include "models/weights_file.h"

/* The models eval takes (the quantity each gives is its weights file's,
 * which models/weights_file.h checks against the model). */
static const struct {
  const char *model;
  sf_eval_model_kind kind;
} models[] = {
    {"sigmoid", SF_EVAL_MODEL_SIGMOID},
    {"mlp-transmittance", SF_EVAL_MODEL_MLP_TRANSMITTANCE},
    {"mlp-scattering", SF_EVAL_MODEL_MLP_SCATTERING},
    {"preetham", SF_EVAL_MODEL_SKY_FORM},
    {"hosek", SF_EVAL_MODEL_SKY_FORM},
};
#define N_MODELS (sizeof models / sizeof models[0])
#define MODELS_TAKEN "sigmoid and mlp-transmittance (transmittance); mlp-scattering, preetham and hosek (sky_radiance)"

static int load_kind(const sf_weights *w, sf_eval_model *m, sf_error *err) {
  switch (m->kind) {
    case SF_EVAL_MODEL_SIGMOID:
      if (sf_sigmoid_model_load(m->path, &m->sigmoid, NULL, err) != SF_OK) return err->status;
      m->n_channels = m->sigmoid.n_channels;
      return SF_OK;
    case SF_EVAL_MODEL_SKY_FORM: {
      sf_sky_form form = strcmp(m->name, "hosek") == 0 ? SF_SKY_FORM_HOSEK : SF_SKY_FORM_PEREZ;
      if (sf_elevation_sky_load(m->path, form, &m->sky, NULL, err) != SF_OK) return err->status;
      m->n_channels = m->sky.n_channels;
      return SF_OK;
    }
    case SF_EVAL_MODEL_MLP_TRANSMITTANCE:
    case SF_EVAL_MODEL_MLP_SCATTERING: {
      if (sf_mlp_sky_from_weights(w, &m->mlp, err) != SF_OK) return err->status;
      m->n_channels = m->mlp.n_channels;
      return SF_OK;
    }
  }
  return SF_OK;
}

int sf_eval_model_load(const char *path, const char *quantity, sf_eval_model *m, sf_error *err) {
  memset(m, 0, sizeof *m);
  snprintf(m->path, sizeof m->path, "%s", path);
  sf_weights w;
  if (sf_weights_load_file(path, NULL, &w, err) != SF_OK) return err->status;
  snprintf(m->name, sizeof m->name, "%s", w.model);
  m->atmosphere = w.atmosphere;
  m->domain = w.domain;
  size_t k = 0;
  while (k < N_MODELS && strcmp(models[k].model, w.model) != 0) ++k;
  int status;
  if (k == N_MODELS)
    status = sf_fail(err, SF_ERR_INPUT, "%s: model: eval does not evaluate model \"%s\" (it takes " MODELS_TAKEN ")",
                     path, w.model);
  else if (strcmp(w.quantity, quantity) != 0)
    status = sf_fail(err, SF_ERR_INPUT, "%s: model: \"%s\" gives %s, not %s", path, w.model, w.quantity, quantity);
  else {
    m->kind = models[k].kind;
    status = load_kind(&w, m, err);
  }
  sf_weights_free(&w);
  if (status != SF_OK) sf_eval_model_free(m);
  return status;
}

int sf_eval_model_load_transmittance(sf_eval_model *m, const char *path, sf_error *err) {
  if (m->kind != SF_EVAL_MODEL_MLP_SCATTERING)
    return sf_fail(err, SF_ERR_INPUT,
                   "%s: --transmittance-model joins an mlp-scattering model to its transmittance network; \"%s\" "
                   "is not one",
                   m->path, m->name);
  sf_weights w;
  if (sf_weights_load_file(path, NULL, &w, err) != SF_OK) return err->status;
  char hash[17];
  sf_atmosphere_hash_hex(&m->atmosphere, hash);
  int status = SF_OK;
  if (strcmp(w.model, "mlp-transmittance") != 0)
    status = sf_fail(err, SF_ERR_INPUT,
                     "%s: model: --transmittance-model takes an mlp-transmittance network, got \"%s\"", path, w.model);
  else if (strcmp(w.atmosphere_hash, hash) != 0)
    status = sf_fail(err, SF_ERR_INPUT,
                     "%s: atmosphere_hash: %s, fitted for another atmosphere than %s's (%s); eq. 44 takes the "
                     "transmittance of the scattering network's own air",
                     path, w.atmosphere_hash, m->path, hash);
  else if (sf_mlp_sky_from_weights(&w, &m->transmittance, err) == SF_OK)
    m->has_transmittance = 1;
  else
    status = err->status;
  sf_weights_free(&w);
  return status;
}

int sf_eval_model_check_ray(const sf_eval_model *m, sf_ray_end end, double distance, sf_error *err) {
  if ((end == SF_RAY_END_NEAREST && distance < 0.0) || m->kind == SF_EVAL_MODEL_MLP_TRANSMITTANCE ||
      m->kind == SF_EVAL_MODEL_SIGMOID)
    return SF_OK;
  if (m->kind == SF_EVAL_MODEL_MLP_SCATTERING && end == SF_RAY_END_NEAREST) {
    if (m->has_transmittance) return SF_OK;
    return sf_fail(err, SF_ERR_INPUT,
                   "%s: --to-distance: a segment of the mlp-scattering model (seed 000 eq. 44) takes its "
                   "transmittance network: add --transmittance-model T.json (mlp-transmittance, the same atmosphere)",
                   m->path);
  }
  /* the option given is named: --to-distance had been answered about --to top */
  const char *asked = distance >= 0.0 ? "--to-distance" : "--to top";
  const char *takes = distance >= 0.0 ? "sigmoid, mlp-transmittance or mlp-scattering (with --transmittance-model)"
                                      : "a transmittance model (sigmoid, mlp-transmittance)";
  return sf_fail(err, SF_ERR_INPUT,
                 "%s: model \"%s\" evaluates the full ray (to the ground or the top, whichever comes first)%s; "
                 "%s takes %s",
                 m->path, m->name, m->kind == SF_EVAL_MODEL_MLP_SCATTERING ? " and segments (--to-distance)" : "",
                 asked, takes);
}

void sf_eval_model_values(const sf_eval_model *m, const double *v, double distance, double *out) {
  switch (m->kind) {
    case SF_EVAL_MODEL_SIGMOID:
      if (distance >= 0.0) sf_sigmoid_model_eval_segment(&m->sigmoid, v[0], v[1], distance, out);
      else sf_sigmoid_model_eval(&m->sigmoid, v[0], v[1], out);
      return;
    case SF_EVAL_MODEL_SKY_FORM: sf_sky_radiance_clamped(&m->sky, v[1], v[2], v[3], out); return;
    case SF_EVAL_MODEL_MLP_SCATTERING:
      if (distance >= 0.0) sf_mlp_scattering_segment(&m->mlp, &m->transmittance, v[0], v[1], v[2], v[3], distance, out);
      else sf_mlp_scattering(&m->mlp, v[0], v[1], v[2], v[3], out);
      return;
    case SF_EVAL_MODEL_MLP_TRANSMITTANCE:
      if (distance >= 0.0) sf_mlp_transmittance_segment(&m->mlp, v[0], v[1], distance, out);
      else sf_mlp_transmittance(&m->mlp, v[0], v[1], out);
      return;
  }
}

int sf_eval_model_outside(const sf_eval_model *m, const double *v) {
  int sky = m->kind == SF_EVAL_MODEL_SKY_FORM || m->kind == SF_EVAL_MODEL_MLP_SCATTERING;
  return sf_scene_domain_outside(&m->domain, m->atmosphere.top_radius_km - m->atmosphere.bottom_radius_km, v[0],
                                 v[1], sky, sky ? v[2] : 0.0);
}

void sf_eval_model_free(sf_eval_model *m) {
  if (m->kind == SF_EVAL_MODEL_MLP_TRANSMITTANCE || m->kind == SF_EVAL_MODEL_MLP_SCATTERING) sf_mlp_sky_free(&m->mlp);
  if (m->has_transmittance) sf_mlp_sky_free(&m->transmittance);
  memset(&m->mlp, 0, sizeof m->mlp);
  memset(&m->transmittance, 0, sizeof m->transmittance);
  m->has_transmittance = 0;
}
