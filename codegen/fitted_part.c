#include "codegen/fitted_part.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "util/json_read.h"

const char *sf_fitted_emitters(void) {
  return "sigmoid, hosek, preetham, mlp-transmittance, mlp-scattering, spectral4";
}

static void emit_part(sf_code_writer *w, const void *model) {
  const sf_fitted_model *m = model;
  switch (m->kind) {
    case SF_FITTED_SIGMOID: sf_emit_sigmoid_ray(w, &m->sigmoid); break;
    case SF_FITTED_SKY: sf_emit_sky(w, &m->sky); break;
    case SF_FITTED_MLP_TRANSMITTANCE: sf_emit_mlp_transmittance(w, &m->mlp); break;
    case SF_FITTED_MLP_SCATTERING: sf_emit_mlp_scattering(w, &m->mlp, m->transmittance); break;
    case SF_FITTED_SPECTRAL4: sf_emit_spectral4(w, &m->spectral4); break;
  }
}

/* The fit's maximum searched where the model errs most (the horizon,
 * models/tangent_sweep.h), which the build's sample misses: the headers had
 * stated 0.505 for the default sigmoid, whose file holds 0.661. */
void sf_fitted_max_abs_text(double sample_max_abs, double fit_max_abs, char *out, size_t n) {
  if (fit_max_abs > sample_max_abs)
    snprintf(out, n, "max abs %.3g (the fit's search near the horizon; %.3g over the values)", fit_max_abs,
             sample_max_abs);
  else
    snprintf(out, n, "max abs %.3g", sample_max_abs);
}

/* The weights file's metrics as one line for the header comment: the
 * errors `skyfit build` measured over the scene's domain
 * (fit/build_weights_errors.h), as build's own header states them; else
 * the fit's error metrics; a network's losses are named as what they are,
 * losses on the targets it trained on (T^(1/4), the brightness-normalised
 * sky), not errors. */
static void metrics_line(const sf_weights *w, char *out, size_t n) {
  const cJSON *b = sf_json_get(sf_json_get(w->root, "metrics"), "build_error");
  const cJSON *rmse = sf_json_get(b, "rmse"), *max_abs = sf_json_get(b, "max_abs");
  const cJSON *mean_rel = sf_json_get(b, "mean_rel"), *rel_rmse = sf_json_get(b, "rel_rmse");
  const cJSON *values = sf_json_get(b, "values"), *over = sf_json_get(b, "over");
  if (cJSON_IsNumber(rmse) && cJSON_IsNumber(max_abs) && cJSON_IsNumber(mean_rel) && cJSON_IsNumber(rel_rmse) &&
      cJSON_IsNumber(values) && cJSON_IsString(over)) {
    char max_text[128];
    sf_fitted_max_abs_text(max_abs->valuedouble, sf_weights_metric(w, "max_abs"), max_text, sizeof max_text);
    snprintf(out, n, "RMSE %.3g, %s, mean rel %.3g, rel RMSE %.3g over %.0f values of %.80s (skyfit build)",
             rmse->valuedouble, max_text, mean_rel->valuedouble, rel_rmse->valuedouble, values->valuedouble,
             over->valuestring);
    return;
  }
  /* spectral4's error is a colour difference against the full spectrum
   * (seed 003); its loss had been stated alone */
  const cJSON *m = sf_json_get(w->root, "metrics");
  const cJSON *clean = sf_json_get(sf_json_get(m, "without_aerosols"), "spectral4");
  const cJSON *hazy = sf_json_get(sf_json_get(m, "with_aerosols"), "spectral4");
  const cJSON *de_mean = sf_json_get(clean, "mean_delta_e2000"), *de_p99 = sf_json_get(clean, "p99_delta_e2000");
  const cJSON *de_max = sf_json_get(clean, "max_delta_e2000");
  if (cJSON_IsNumber(de_mean) && cJSON_IsNumber(de_p99) && cJSON_IsNumber(de_max)) {
    int k = snprintf(out, n, "CIEDE2000 against the full spectrum, sky without aerosols: mean %.3g, p99 %.3g, max %.3g",
                     de_mean->valuedouble, de_p99->valuedouble, de_max->valuedouble);
    const cJSON *h_mean = sf_json_get(hazy, "mean_delta_e2000"), *h_max = sf_json_get(hazy, "max_delta_e2000");
    if (k > 0 && (size_t)k < n && cJSON_IsNumber(h_mean) && cJSON_IsNumber(h_max))
      snprintf(out + k, n - (size_t)k, "; with aerosols: mean %.3g, max %.3g", h_mean->valuedouble, h_max->valuedouble);
    return;
  }
  static const char *const names[] = {"rmse", "max_abs", "mean_rel", "rel_rmse", "loss", "train_loss",
                                      "validation_loss"};
  size_t k = 0;
  int errors = 0;
  out[0] = '\0';
  for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
    double v = sf_weights_metric(w, names[i]);
    if (v != v) continue;
    errors += i < 4;
    int written = snprintf(out + k, n - k, "%s%s %.3g", k ? ", " : "", names[i], v);
    if (written < 0 || (size_t)written >= n - k) break;
    k += (size_t)written;
  }
  const cJSON *targets = sf_json_get(sf_json_get(w->root, "metrics"), "loss_targets");
  if (k && !errors && cJSON_IsString(targets) && k < n)
    snprintf(out + k, n - k, " (losses on its %.40s training targets, not errors against the reference)",
             targets->valuestring);
  if (!k) snprintf(out, n, "(the weights file records none)");
}

static void fill_common(const sf_weights *w, sf_codegen_part *part, const char *name) {
  memset(part, 0, sizeof *part);
  snprintf(part->name, sizeof part->name, "%s", name);
  snprintf(part->quantity, sizeof part->quantity, "%s", w->quantity);
  snprintf(part->atmosphere_name, sizeof part->atmosphere_name, "%s", w->atmosphere.name);
  snprintf(part->atmosphere_hash, sizeof part->atmosphere_hash, "%s", w->atmosphere_hash);
  part->domain = w->domain;
  char metrics[400];
  metrics_line(w, metrics, sizeof metrics);
  /* The file's name, not its path: the text must not depend on where the
   * build runs. */
  const char *slash = strrchr(w->source, '/');
  snprintf(part->error, sizeof part->error, "%s (from %.180s)", metrics, slash ? slash + 1 : w->source);
}

static int load_sigmoid(const sf_weights *w, sf_fitted_model *m, sf_codegen_part *part, sf_error *err) {
  if (sf_sigmoid_model_load(w->source, &m->sigmoid.model, NULL, err) != SF_OK) return err->status;
  if (m->sigmoid.model.n_channels > 4)
    return sf_fail(err, SF_ERR_INPUT, "%s: emitted code returns vec1-vec4, the model has %d channels",
                   w->source, m->sigmoid.model.n_channels);
  m->kind = SF_FITTED_SIGMOID;
  m->sigmoid.bottom_radius_km = w->atmosphere.bottom_radius_km;
  m->sigmoid.top_radius_km = w->atmosphere.top_radius_km;
  fill_common(w, part, "sigmoid");
  snprintf(part->summary, sizeof part->summary,
           "sigmoid-polynomial transmittance (seed 000 §9.5), %d constituents x %d channels; "
           "segments as T(h, mu) / T(h_t, mu_t)",
           m->sigmoid.model.n_constituents, m->sigmoid.model.n_channels);
  return SF_OK;
}

static int load_sky(const sf_weights *w, sf_sky_form form, sf_fitted_model *m, sf_codegen_part *part,
                    sf_error *err) {
  if (sf_elevation_sky_load(w->source, form, &m->sky, NULL, err) != SF_OK) return err->status;
  if (m->sky.n_channels > 4)
    return sf_fail(err, SF_ERR_INPUT, "%s: emitted code returns vec1-vec4, the model has %d channels",
                   w->source, m->sky.n_channels);
  m->kind = SF_FITTED_SKY;
  fill_common(w, part, sf_sky_form_model_name(form));
  snprintf(part->summary, sizeof part->summary,
           "%s sky radiance for a viewer on the ground (seed 000 eq. %s), coefficients a quintic "
           "Bezier in the sun elevation fitted for [%.4g, %.4g] rad",
           form == SF_SKY_FORM_HOSEK ? "Hosek-Wilkie" : "Perez/Preetham",
           form == SF_SKY_FORM_HOSEK ? "35-37" : "33", m->sky.elevation_min_rad, m->sky.elevation_max_rad);
  return SF_OK;
}

static int load_mlp(const sf_weights *w, int scattering, sf_fitted_model *m, sf_codegen_part *part,
                    sf_error *err) {
  if (sf_mlp_sky_from_weights(w, &m->mlp, err) != SF_OK) return err->status;
  m->kind = scattering ? SF_FITTED_MLP_SCATTERING : SF_FITTED_MLP_TRANSMITTANCE;
  char problem[200];
  if (sf_emit_mlp_check(&m->mlp, problem, sizeof problem))
    return sf_fail(err, SF_ERR_INPUT, "%s: %s", w->source, problem);
  fill_common(w, part, "mlp");
  const sf_mlp_shape *s = &m->mlp.net.shape;
  char layers[96];
  int k = 0;
  for (int l = 0; l <= s->n_layers && k < (int)sizeof layers - 8; ++l)
    k += snprintf(layers + k, sizeof layers - (size_t)k, l ? "-%d" : "%d", s->sizes[l]);
  snprintf(part->summary, sizeof part->summary,
           scattering ? "scattering MLP %s (seed 000 §9.6.2, target %s), full ray"
                      : "transmittance MLP %s (seed 000 §9.6.1, target %s), full ray and segments "
                        "(eq. 43, reversed rays toward the ground)",
           layers, sf_mlp_target_name(m->mlp.target));
  return SF_OK;
}

int sf_fitted_part(const sf_weights *w, sf_fitted_model **model, sf_codegen_part *part,
                   sf_error *err) {
  *model = calloc(1, sizeof **model);
  if (!*model) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_fitted_model *m = *model;
  int status;
  if (strcmp(w->model, "sigmoid") == 0) status = load_sigmoid(w, m, part, err);
  else if (strcmp(w->model, "hosek") == 0) status = load_sky(w, SF_SKY_FORM_HOSEK, m, part, err);
  else if (strcmp(w->model, "preetham") == 0) status = load_sky(w, SF_SKY_FORM_PEREZ, m, part, err);
  else if (strcmp(w->model, "mlp-transmittance") == 0) status = load_mlp(w, 0, m, part, err);
  else if (strcmp(w->model, "mlp-scattering") == 0) status = load_mlp(w, 1, m, part, err);
  else if (strcmp(w->model, "spectral4") == 0) {
    status = sf_spectral4_emit_load(w, &m->spectral4, err);
    if (status == SF_OK) {
      m->kind = SF_FITTED_SPECTRAL4;
      fill_common(w, part, "spectral4");
      snprintf(part->summary, sizeof part->summary,
               "4-wavelength spectral weights (seed 003 §5.4): 3x4 colour matrices and the "
               "coefficients at %.4g, %.4g, %.4g, %.4g nm",
               m->spectral4.wavelengths_nm[0], m->spectral4.wavelengths_nm[1],
               m->spectral4.wavelengths_nm[2], m->spectral4.wavelengths_nm[3]);
    }
  } else
    return sf_fail(err, SF_ERR_INPUT, "%s: model: no emitter for model \"%s\" (emitters: %s)",
                   w->source, w->model, sf_fitted_emitters());
  if (status != SF_OK) return status;
  part->emit = emit_part;
  part->model = m;
  return SF_OK;
}

void sf_fitted_link(sf_fitted_model **models, sf_codegen_part *parts, int n) {
  for (int i = 0; i < n; ++i) {
    if (!models[i] || models[i]->kind != SF_FITTED_MLP_SCATTERING) continue;
    for (int j = 0; j < n; ++j) {
      if (!models[j] || models[j]->kind != SF_FITTED_MLP_TRANSMITTANCE) continue;
      /* eq. 44 takes the transmittance of the scattering network's own air:
       * the same atmosphere, not just the same radii (a hazy network had
       * been joined to an Earth one) */
      if (strcmp(parts[i].atmosphere_hash, parts[j].atmosphere_hash) != 0) continue;
      const sf_mlp_sky *t = &models[j]->mlp;
      models[i]->transmittance = t;
      size_t len = strlen(parts[i].summary);
      snprintf(parts[i].summary + len, sizeof parts[i].summary - len,
               " and segments (eq. 44, with the transmittance MLP)");
      break;
    }
  }
  /* The segment function calls the transmittance network's functions, and
   * C and GLSL declare a function before its use: a linked transmittance
   * part that comes later moves to just before its first caller. */
  for (int i = 0; i < n; ++i) {
    if (!models[i] || !models[i]->transmittance) continue;
    int j = i + 1;
    while (j < n && !(models[j] && &models[j]->mlp == models[i]->transmittance)) ++j;
    if (j == n) continue;   /* already before it */
    sf_fitted_model *model = models[j];
    sf_codegen_part part = parts[j];
    memmove(models + i + 1, models + i, (size_t)(j - i) * sizeof *models);
    memmove(parts + i + 1, parts + i, (size_t)(j - i) * sizeof *parts);
    models[i] = model;
    parts[i] = part;
    ++i;   /* the caller, now at i + 1 */
  }
}

void sf_fitted_free(sf_fitted_model *model) {
  if (!model) return;
  if (model->kind == SF_FITTED_MLP_TRANSMITTANCE || model->kind == SF_FITTED_MLP_SCATTERING)
    sf_mlp_sky_free(&model->mlp);
  free(model);
}
