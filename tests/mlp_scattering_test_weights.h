/* The header of a scattering network's weights file (SPEC §8) as
 * `skyfit fit mlp-scattering` writes it: inputs sqrt_h_km, mu, mu_s, nu with
 * the given normalisation, target separate of the built-in atmosphere's
 * rayleigh and mie, then multiple. The caller adds the params. */
#ifndef SKYFIT_TESTS_MLP_SCATTERING_TEST_WEIGHTS_H
#define SKYFIT_TESTS_MLP_SCATTERING_TEST_WEIGHTS_H

#include "models/weights_file.h"

static inline cJSON *mlp_scattering_weights_doc(const sf_atmosphere *atm, const sf_scene_domain *dom,
                                                const double *offset, const double *scale) {
  cJSON *doc = sf_weights_new("mlp-scattering", "sky_radiance", atm, dom);
  static const char *const names[4] = {"sqrt_h_km", "mu", "mu_s", "nu"};
  for (int k = 0; k < 4; ++k) sf_weights_add_input(doc, names[k], offset[k], scale[k]);
  cJSON *training = sf_weights_training(doc);
  cJSON_AddStringToObject(training, "target", "separate");
  cJSON *comps = cJSON_AddArrayToObject(training, "components");
  cJSON_AddItemToArray(comps, cJSON_CreateString("rayleigh"));
  cJSON_AddItemToArray(comps, cJSON_CreateString("mie"));
  cJSON_AddItemToArray(comps, cJSON_CreateString("multiple"));
  return doc;
}

#endif
