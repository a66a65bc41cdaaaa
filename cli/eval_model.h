/* `skyfit eval QUANTITY --model W.json` (SPEC §11): a fitted model's values
 * at the points instead of the reference's, in double, from the model's own
 * evaluation (what its emitted function computes in float32):
 *   transmittance  sigmoid            sf_sigmoid_model_eval, _segment (eq. 43)
 *                  mlp-transmittance  sf_mlp_transmittance, _segment (eq. 43)
 *   sky_radiance   mlp-scattering     sf_mlp_scattering (full ray), _segment
 *                                     (eq. 44, with its transmittance network)
 *                  preetham, hosek    sf_sky_radiance_clamped (a viewer on the
 *                                     ground: h is not an input)
 * The atmosphere is the one the model was fitted for (its weights file).
 * Each model is read by its own loader, as codegen/fitted_part.h reads
 * them, but not through that one: it also refuses what its emitters do not
 * take (more than 4 channels, some networks), which eval evaluates. */
#ifndef SKYFIT_CLI_EVAL_MODEL_H
#define SKYFIT_CLI_EVAL_MODEL_H

#include "models/atmosphere.h"
#include "models/hosek_sky_model.h"
#include "models/mlp_sky.h"
#include "models/optical_depth.h"
#include "models/scene_file.h"
#include "models/sigmoid_transmittance.h"
#include "util/error.h"

typedef enum sf_eval_model_kind {
  SF_EVAL_MODEL_SIGMOID = 0,
  SF_EVAL_MODEL_SKY_FORM,   /* preetham or hosek */
  SF_EVAL_MODEL_MLP_TRANSMITTANCE,
  SF_EVAL_MODEL_MLP_SCATTERING
} sf_eval_model_kind;

typedef struct sf_eval_model {
  sf_eval_model_kind kind;
  char name[64];              /* the weights file's "model" */
  char path[512];
  sf_atmosphere atmosphere;   /* the one it was fitted for */
  sf_scene_domain domain;     /* the one it was fitted on */
  int n_channels;
  sf_sigmoid_model sigmoid;
  sf_elevation_sky_model sky;
  sf_mlp_sky mlp;
  /* mlp-scattering: the transmittance network its segments (eq. 44)
   * take (sf_eval_model_load_transmittance), or none */
  int has_transmittance;
  sf_mlp_sky transmittance;
} sf_eval_model;

/* Loads the weights file at path for quantity ("transmittance" or
 * "sky_radiance"). SF_ERR_INPUT naming the file: unreadable or invalid (the
 * model's own loader), or a model that does not give the quantity. */
int sf_eval_model_load(const char *path, const char *quantity, sf_eval_model *m, sf_error *err);

/* For an mlp-scattering model m: the mlp-transmittance weights file at
 * path, fitted for the same atmosphere (its hash), which eq. 44 takes for
 * segments; codegen joins the two networks by the same rule
 * (codegen/fitted_part.h sf_fitted_link). SF_ERR_INPUT naming the file
 * otherwise. */
int sf_eval_model_load_transmittance(sf_eval_model *m, const char *path, sf_error *err);

/* Whether the model evaluates the stretch asked for (end, distance >= 0: a
 * segment): every model the full ray; the transmittance models (sigmoid,
 * mlp-transmittance) also the top and segments, mlp-scattering segments
 * with its transmittance network. SF_ERR_INPUT saying what the model
 * evaluates. */
int sf_eval_model_check_ray(const sf_eval_model *m, sf_ray_end end, double distance, sf_error *err);

/* out[m->n_channels] at v = (h_km, mu) or (h_km, mu, mu_s, nu), whose
 * ranges and ray the caller has checked as for the reference
 * (cli/cmd_eval.c): the ray to the top is then the full ray, which does
 * not hit the ground. distance >= 0: the segment to that distance. */
void sf_eval_model_values(const sf_eval_model *m, const double *v, double distance, double *out);

/* Whether v lies outside the domain the model was fitted on, where its
 * values are extrapolations: h_km (a viewer above the atmosphere counted
 * at the top, where its ray enters), mu for a viewer inside, mu_s for sky
 * radiance. */
int sf_eval_model_outside(const sf_eval_model *m, const double *v);

void sf_eval_model_free(sf_eval_model *m);

#endif
