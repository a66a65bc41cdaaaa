#include "fit/fit_weights_doc.h"

#include <math.h>
#include <stdlib.h>

#include "models/weights_file.h"
#include "util/constants.h"

/* SPEC §8's "seed" and "epochs" for a least-squares fit: nothing is drawn
 * (seed 0, as spectral4's), and an epoch, one pass over every residual and
 * its Jacobian, is a Levenberg-Marquardt iteration: the most that any one of
 * the final fit's separate problems took (one per constituent and channel
 * for the sigmoid, per channel for the sky forms' fit across elevations). */
static void add_least_squares_run(cJSON *training, int iterations) {
  cJSON_AddNumberToObject(training, "seed", 0);
  cJSON_AddNumberToObject(training, "epochs", iterations);
}

static int sigmoid_most_iterations(const sf_sigmoid_model *m, const sf_sigmoid_fit_report *rep) {
  int most = 0;
  for (int c = 0; c < m->n_constituents; ++c)
    for (int k = 0; k < m->n_channels; ++k)
      if (!rep->entry[c][k].transparent && rep->entry[c][k].iterations > most) most = rep->entry[c][k].iterations;
  return most;
}

int sf_sigmoid_weights_write(const sf_atmosphere *atm, const sf_scene_domain *domain,
                             const sf_sigmoid_fit_options *o, const sf_sigmoid_model *m,
                             const sf_sigmoid_fit_report *rep, const char *path, sf_error *err) {
  int nc = m->n_constituents, nk = m->n_channels;
  cJSON *doc = sf_weights_new("sigmoid", "transmittance", atm, domain);
  double *a = malloc(sizeof *a * (size_t)(nc * nk * SF_SIGMOID_N_COEFFS));
  int status = SF_OK;
  if (!doc || !a) {
    status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  } else {
    for (int c = 0; c < nc; ++c)
      for (int k = 0; k < nk; ++k)
        for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j) a[(c * nk + k) * SF_SIGMOID_N_COEFFS + j] = m->a[c][k][j];
    int shape[3] = {nc, nk, SF_SIGMOID_N_COEFFS};
    sf_weights_add_input(doc, "h_km", 0.0, 1.0);
    sf_weights_add_input(doc, "mu", 0.0, 1.0);
    sf_weights_add_param(doc, "a", 3, shape, a);
    cJSON *mt = sf_weights_metrics(doc);
    cJSON_AddNumberToObject(mt, "rmse", rep->rmse);
    cJSON_AddNumberToObject(mt, "max_abs", rep->max_abs);
    cJSON_AddNumberToObject(mt, "worst_h_km", rep->worst_h_km);
    cJSON_AddNumberToObject(mt, "worst_mu", rep->worst_mu);
    cJSON_AddStringToObject(mt, "worst_channel", atm->channel_names[rep->worst_channel]);
    cJSON_AddNumberToObject(mt, "points", rep->full.n_points / nk);
    cJSON_AddNumberToObject(mt, "rmse_ground_rays", rep->full_ground.rmse);
    cJSON_AddNumberToObject(mt, "rmse_sky_rays", rep->full_sky.rmse);
    cJSON_AddNumberToObject(mt, "top_rmse", rep->top.rmse);
    cJSON_AddNumberToObject(mt, "top_max_abs", rep->top.max_abs);
    cJSON_AddNumberToObject(mt, "top_worst_h_km", rep->top.worst_h_km);
    cJSON_AddNumberToObject(mt, "top_worst_mu", rep->top.worst_mu);
    cJSON_AddNumberToObject(mt, "top_points", rep->n_points);
    cJSON *per = cJSON_AddObjectToObject(mt, "per_constituent");
    for (int c = 0; c < nc; ++c) {
      cJSON *cj = cJSON_AddObjectToObject(per, atm->constituents[c].name);
      for (int k = 0; k < nk; ++k) {
        const sf_sigmoid_fit_entry *e = &rep->entry[c][k];
        cJSON *kj = cJSON_AddObjectToObject(cj, atm->channel_names[k]);
        cJSON_AddNumberToObject(kj, "rmse", e->rmse);
        cJSON_AddNumberToObject(kj, "max_abs", e->max_abs);
        cJSON_AddNumberToObject(kj, "worst_h_km", e->worst_h_km);
        cJSON_AddNumberToObject(kj, "worst_mu", e->worst_mu);
      }
    }
    cJSON *tr = sf_weights_training(doc);
    add_least_squares_run(tr, sigmoid_most_iterations(m, rep));
    cJSON_AddStringToObject(tr, "loss", "least squares on T_top (rays to the top, mu >= 0)");
    cJSON_AddNumberToObject(tr, "fit_h_min_km", rep->fit_h_min_km);
    cJSON_AddNumberToObject(tr, "fit_h_max_km", rep->fit_h_max_km);
    cJSON_AddNumberToObject(tr, "fit_mu_min", rep->fit_mu_min);
    cJSON_AddNumberToObject(tr, "fit_mu_max", rep->fit_mu_max);
    cJSON_AddStringToObject(tr, "solver", "ceres levenberg-marquardt, dense qr, 1 thread");
    cJSON_AddStringToObject(tr, "start", "weighted logit linear least squares");
    cJSON_AddStringToObject(tr, "reference", "exact optical depth (models/optical_depth.h)");
    cJSON_AddNumberToObject(tr, "grid_h", o->n_h);
    cJSON_AddNumberToObject(tr, "grid_mu", o->n_mu);
    status = sf_weights_write(doc, path, err);
  }
  free(a);
  cJSON_Delete(doc);
  return status;
}

int sf_sky_form_weights_write(const sf_atmosphere *atm, const sf_scene_domain *domain,
                              const sf_sky_elevation_options *o, const char *tables_kind, const sf_elevation_sky_model *m,
                              const sf_sky_elevation_report *rep, const char *path, sf_error *err) {
  cJSON *doc = sf_weights_new(sf_sky_form_model_name(m->form), "sky_radiance", atm, domain);
  if (!doc || sf_elevation_sky_add_params(doc, m)) {
    cJSON_Delete(doc);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  cJSON *mt = sf_weights_metrics(doc);
  cJSON_AddNumberToObject(mt, "rmse", rep->rmse);
  cJSON_AddNumberToObject(mt, "held_out_rmse", rep->held_out_rmse);
  cJSON_AddNumberToObject(mt, "rel_rmse", rep->rel_rmse);
  cJSON_AddNumberToObject(mt, "normalised_rmse", rep->normalised_rmse);
  cJSON_AddNumberToObject(mt, "max_abs", rep->max_abs);
  cJSON_AddNumberToObject(mt, "worst_sun_elevation_deg", rep->worst_elevation_rad * 180 / SF_PI);
  cJSON_AddNumberToObject(mt, "worst_theta_deg", rep->worst_theta * 180 / SF_PI);
  cJSON_AddNumberToObject(mt, "worst_gamma_deg", rep->worst_gamma * 180 / SF_PI);
  cJSON_AddNumberToObject(mt, "per_elevation_rmse", rep->per_elevation_rmse);
  cJSON_AddNumberToObject(mt, "samples", rep->n_samples);
  cJSON_AddNumberToObject(mt, "metric_samples", (double)rep->n_metric_samples);
  cJSON_AddNumberToObject(mt, "sun_elevations", rep->n_elevations);
  cJSON_AddNumberToObject(mt, "metric_sun_elevations", rep->n_metric_elevations);
  if (isfinite(rep->preetham_rmse)) {
    cJSON_AddNumberToObject(mt, "published_preetham_rmse", rep->preetham_rmse);
    cJSON_AddNumberToObject(mt, "published_preetham_turbidity", rep->preetham_turbidity);
  }
  if (isfinite(rep->hosek_published_rmse)) {
    cJSON_AddNumberToObject(mt, "published_hosek_rmse", rep->hosek_published_rmse);
    cJSON_AddNumberToObject(mt, "published_hosek_turbidity", rep->hosek_published_turbidity);
  }
  cJSON *wins = cJSON_AddObjectToObject(mt, "start_wins");
  for (int q = 0; q < rep->n_starts; ++q) cJSON_AddNumberToObject(wins, rep->start_names[q], rep->start_wins[q]);
  static const char *const global_names[4] = {"curve through per-elevation fits", "constant from elevation n/4",
                                              "constant from elevation n/2", "constant from elevation 3n/4"};
  cJSON *gw = cJSON_AddObjectToObject(mt, "elevation_fit_start_wins");
  for (int q = 0; q < 4; ++q) cJSON_AddNumberToObject(gw, global_names[q], rep->global_start_wins[q]);
  cJSON *tr = sf_weights_training(doc);
  int most = 0;
  for (int k = 0; k < rep->n_channels; ++k)
    if (rep->global_iterations_channel[k] > most) most = rep->global_iterations_channel[k];
  add_least_squares_run(tr, most);
  cJSON_AddStringToObject(tr, "loss", "least squares, residuals normalised per elevation and channel");
  cJSON_AddStringToObject(tr, "solver", o->lsq.normal_equations
                                            ? "ceres levenberg-marquardt, dense normal cholesky (gram), 1 thread"
                                            : "ceres levenberg-marquardt, dense qr, 1 thread");
  cJSON_AddNumberToObject(tr, "max_iterations", o->elevation_fit_max_iterations);
  cJSON *cap = cJSON_AddArrayToObject(tr, "elevation_fit_at_iteration_cap");
  for (int k = 0; k < rep->n_channels; ++k)
    if (rep->global_at_cap_channel[k]) cJSON_AddItemToArray(cap, cJSON_CreateString(atm->channel_names[k]));
  cJSON_AddNumberToObject(tr, "elevations", o->n_elevations);
  /* step 3's suns: the fit suns and two between each pair */
  cJSON_AddNumberToObject(tr, "elevation_fit_suns", rep->n_curve_elevations);
  cJSON_AddNumberToObject(tr, "n_theta", o->n_theta);
  cJSON_AddNumberToObject(tr, "n_phi", o->n_phi);
  cJSON_AddNumberToObject(tr, "global_initial_cost", rep->global_initial_cost);
  cJSON_AddNumberToObject(tr, "global_final_cost", rep->global_final_cost);
  cJSON_AddNumberToObject(tr, "global_iterations", rep->global_iterations);
  cJSON_AddStringToObject(tr, "tables", tables_kind);
  int status = sf_weights_write(doc, path, err);
  cJSON_Delete(doc);
  return status;
}
