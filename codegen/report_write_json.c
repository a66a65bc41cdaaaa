/* metrics.json: every measured figure of the report, machine-readable.
 * Non-finite numbers are never written as numbers (JSON has none): they
 * become null, and the tests require that none occurs. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "codegen/report.h"
#include "util/json_exact.h"
#include "util/path_from_folder.h"

static void add_number(cJSON *o, const char *key, double v) {
  if (isfinite(v)) cJSON_AddNumberToObject(o, key, v);
  else cJSON_AddNullToObject(o, key);
}

static cJSON *model_json(const sf_report *rep, const sf_report_model *m) {
  const sf_candidate *c = m->candidate;
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "quantity", sf_candidate_quantity_name(c->quantity));
  cJSON_AddStringToObject(o, "name", c->name);
  cJSON_AddStringToObject(o, "label", c->label);
  cJSON_AddStringToObject(o, "role", sf_candidate_role_name(c->role));
  cJSON_AddStringToObject(o, "description", c->description);
  add_number(o, "parameters", (double)c->n_params);
  add_number(o, "constant_bytes", (double)c->constant_bytes);
  cJSON_AddBoolToObject(o, "valid_over_domain", m->valid_over_domain);
  if (c->weights_path[0]) {
    char shown[4096];   /* from the report's folder, as every path it holds */
    sf_path_from_folder(rep->out_dir, c->weights_path, shown, sizeof shown);
    cJSON_AddStringToObject(o, "weights", shown);
  }
  if (m->has_errors) {
    cJSON *e = cJSON_AddObjectToObject(o, "errors");
    add_number(e, "rmse", m->errors.rmse);
    add_number(e, "max_abs", m->errors.max_abs);
    add_number(e, "mean_rel", m->errors.mean_rel);
    add_number(e, "rel_rmse", m->errors.rel_rmse);
    add_number(e, "reference_rms", m->errors.reference_rms);
    /* mean_rel's floor: how many references lie below it and what share
     * of mean_rel they make (fit/candidate_metrics.h) */
    add_number(e, "values_below_rel_floor", (double)m->errors.n_below_floor);
    add_number(e, "mean_rel_share_below_floor", m->errors.mean_rel_floor_share);
    add_number(e, "values", (double)m->errors.n_values);
    add_number(e, "non_finite_values", (double)m->non_finite);
    cJSON_AddStringToObject(e, "over", m->errors_over_valid_part ? "its valid part of the domain" : "the domain");
    /* the segment function's (codegen/report.h); absent: it has none */
    if (m->has_segment_errors) {
      add_number(e, "segment_rmse", m->segment_errors.rmse);
      add_number(e, "segment_max_abs", m->segment_errors.max_abs);
      add_number(e, "segment_rel_rmse", m->segment_errors.rel_rmse);
      add_number(e, "segment_reference_rms", m->segment_errors.reference_rms);
      add_number(e, "segment_values", (double)m->segment_errors.n_values);
      add_number(e, "segment_non_finite_values", (double)m->segment_non_finite);
      if (m->segment_partner) cJSON_AddStringToObject(e, "segment_transmittance", m->segment_partner->name);
    }
    if (m->errors_over_valid_part) {
      cJSON *d = cJSON_AddObjectToObject(e, "domain");
      add_number(d, "h_min_km", m->errors_domain.h_min_km);
      add_number(d, "h_max_km", m->errors_domain.h_max_km);
      add_number(d, "mu_min", m->errors_domain.mu_min);
      add_number(d, "mu_max", m->errors_domain.mu_max);
      add_number(d, "mu_s_min", m->errors_domain.mu_s_min);
      add_number(d, "mu_s_max", m->errors_domain.mu_s_max);
    }
  }
  if (m->has_cost) {
    cJSON *k = cJSON_AddObjectToObject(o, "cost");
    add_number(k, "ns_median", m->cost.ns_median);
    add_number(k, "ns_min", m->cost.ns_min);
    add_number(k, "ns_max", m->cost.ns_max);
    add_number(k, "repetitions", m->cost.repetitions);
    add_number(k, "points", (double)m->cost.n_points);
    add_number(k, "precision_bits", m->cost.precision_bits);
    add_number(k, "ratio_to_naive16", m->cost_ratio_naive16);
    cJSON_AddStringToObject(k, "over", m->errors_over_valid_part ? "its valid part of the domain" : "the domain");
  }
  cJSON *views = cJSON_AddArrayToObject(o, "views");
  for (int v = 0; v < m->n_views; ++v) {
    const sf_report_view *rv = &m->views[v];
    if (!rv->rendered) continue;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "view", rv->name);
    cJSON_AddStringToObject(j, "png", rv->png);
    add_number(j, "compared_fraction", rv->compared_fraction);
    if (c->role != SF_ROLE_REFERENCE) {
      add_number(j, "non_finite_pixels", (double)rv->non_finite_pixels);
      add_number(j, "rmse", rv->rmse);
      add_number(j, "mean_delta_e2000", rv->mean_delta_e);
      cJSON_AddStringToObject(j, "error_exr", rv->error_exr);
    }
    cJSON_AddItemToArray(views, j);
  }
  (void)rep;
  if (c->role != SF_ROLE_REFERENCE) {
    add_number(o, "budget_metric", m->budget_metric);
    cJSON_AddBoolToObject(o, "meets_budget", m->meets_budget);
    cJSON_AddBoolToObject(o, "selected", m->selected);
    cJSON_AddBoolToObject(o, "can_ship", m->selectable);
    cJSON_AddBoolToObject(o, "on_pareto_front", m->on_front);
  }
  return o;
}

int sf_report_write_json(const sf_report *rep, const char *path, sf_error *err) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddNumberToObject(root, "skyfit_report", 1);
  cJSON_AddStringToObject(root, "scene", rep->scene_name);
  cJSON *atm = cJSON_AddObjectToObject(root, "atmosphere");
  cJSON_AddStringToObject(atm, "name", rep->atmosphere_name);
  cJSON_AddStringToObject(atm, "hash", rep->atmosphere_hash);
  add_number(root, "channels", rep->n_channels);
  cJSON *d = cJSON_AddObjectToObject(root, "domain");
  add_number(d, "h_min_km", rep->domain.h_min_km);
  add_number(d, "h_max_km", rep->domain.h_max_km);
  add_number(d, "mu_min", rep->domain.mu_min);
  add_number(d, "mu_max", rep->domain.mu_max);
  add_number(d, "mu_s_min", rep->domain.mu_s_min);
  add_number(d, "mu_s_max", rep->domain.mu_s_max);
  cJSON *o = cJSON_AddObjectToObject(root, "options");
  add_number(o, "domain_samples", (double)rep->options.domain_samples);
  add_number(o, "timing_points", (double)rep->options.timing_points);
  add_number(o, "timing_repetitions", rep->options.timing_repetitions);
  add_number(o, "view_width", rep->options.view_width);
  add_number(o, "view_height", rep->options.view_height);
  add_number(o, "seed", (double)rep->options.seed);
  cJSON *unit = cJSON_AddObjectToObject(root, "cost_unit");
  add_number(unit, "naive16_ns_float32", rep->naive16_ns_f32);
  add_number(unit, "naive16_ns_double", rep->naive16_ns_f64);
  cJSON *models = cJSON_AddArrayToObject(root, "models");
  for (int i = 0; i < rep->n_models; ++i) cJSON_AddItemToArray(models, model_json(rep, &rep->models[i]));
  cJSON *sel = cJSON_AddObjectToObject(root, "selection");
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    const sf_report_selection *s = &rep->selection[q];
    if (!s->asked) continue;
    cJSON *j = cJSON_AddObjectToObject(sel, sf_candidate_quantity_name((sf_candidate_quantity)q));
    cJSON_AddStringToObject(j, "metric", s->metric);
    add_number(j, "budget", s->budget);
    if (s->model >= 0) cJSON_AddStringToObject(j, "model", rep->models[s->model].candidate->name);
    else cJSON_AddStringToObject(j, "model", "");   /* none: see reason */
    cJSON_AddBoolToObject(j, "meets_budget", s->meets_budget);
    cJSON_AddStringToObject(j, "reason", s->reason);
    if (s->emitted_c[0]) cJSON_AddStringToObject(j, "c_header", s->emitted_c);
    if (s->emitted_glsl[0]) cJSON_AddStringToObject(j, "glsl", s->emitted_glsl);
    if (s->emit_note[0]) cJSON_AddStringToObject(j, "emit_note", s->emit_note);
    char segment_note[1024];
    sf_report_segment_note(rep, q, segment_note, sizeof segment_note);
    if (segment_note[0]) cJSON_AddStringToObject(j, "segment_note", segment_note);
  }
  if (rep->views_note[0]) cJSON_AddStringToObject(root, "views_note", rep->views_note);
  if (rep->notes[0]) cJSON_AddStringToObject(root, "notes", rep->notes);
  if (rep->reference_check.present) {
    static const char *const band_keys[SF_SKY_CHECK_BANDS] = {"sun_above_5.7_deg", "sun_0_to_5.7_deg",
                                                              "sun_0_to_minus_5.7_deg", "sun_below_minus_5.7_deg"};
    const sf_sky_table_check *c = &rep->reference_check;
    cJSON *o = cJSON_AddObjectToObject(root, "reference_check");
    cJSON_AddStringToObject(o, "what", "the sky tables' single scattering (phases applied) against direct integration");
    add_number(o, "points", (double)c->n_points);
    add_number(o, "points_outside", (double)c->n_outside);
    add_number(o, "rmse", c->rmse);
    add_number(o, "rel_rmse", c->rel_rmse);
    add_number(o, "max_abs", c->max_abs);
    cJSON *w = cJSON_AddObjectToObject(o, "worst");
    add_number(w, "h_km", c->worst_h_km);
    add_number(w, "mu", c->worst_mu);
    add_number(w, "mu_s", c->worst_mu_s);
    add_number(w, "nu", c->worst_nu);
    cJSON_AddStringToObject(w, "channel", c->worst_channel_name);
    add_number(w, "table", c->worst_table);
    add_number(w, "direct", c->worst_direct);
    cJSON *bands = cJSON_AddObjectToObject(o, "rel_rmse_by_sun");
    for (int b = 0; b < SF_SKY_CHECK_BANDS; ++b)
      if (c->band[b].n_points > 0 && isfinite(c->band[b].rel_rmse))
        add_number(bands, band_keys[b], c->band[b].rel_rmse);
    add_number(o, "multiple_share", c->multiple_share);
  }
  if (rep->spectral4.present) {
    const sf_report_spectral4 *sp = &rep->spectral4;
    cJSON *o = cJSON_AddObjectToObject(root, "spectral4");
    char shown[4096];
    sf_path_from_folder(rep->out_dir, sp->weights_path, shown, sizeof shown);
    cJSON_AddStringToObject(o, "weights", shown);
    cJSON *l = cJSON_AddArrayToObject(o, "wavelengths_nm"), *w = cJSON_AddArrayToObject(o, "weights_nm");
    for (int i = 0; i < 4; ++i) {
      cJSON_AddItemToArray(l, cJSON_CreateNumber(isfinite(sp->lambda_nm[i]) ? sp->lambda_nm[i] : 0.0));
      cJSON_AddItemToArray(w, cJSON_CreateNumber(isfinite(sp->weight_nm[i]) ? sp->weight_nm[i] : 0.0));
    }
    add_number(o, "loss", sp->loss);
    add_number(o, "rgb_680_550_440_loss", sp->rgb_loss);
    add_number(o, "uniform4_loss", sp->uniform_loss);
    static const char *const atm[2] = {"without_aerosols", "with_aerosols"};
    for (int a = 0; a < 2; ++a) {
      cJSON *oa = cJSON_AddObjectToObject(o, atm[a]);
      for (int k = 0; k < SF_REPORT_COLOR_METHODS; ++k) {
        cJSON *om = cJSON_AddObjectToObject(oa, sp->method[k]);
        add_number(om, "mean_delta_e2000", sp->mean_de[a][k]);
        add_number(om, "p99_delta_e2000", sp->p99_de[a][k]);
        add_number(om, "max_delta_e2000", sp->max_de[a][k]);
        add_number(om, "samples", sp->samples[a][k]);
      }
    }
  }
  int status = sf_json_write_exact(root, path, err);
  cJSON_Delete(root);
  return status;
}
