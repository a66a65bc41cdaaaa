/* A spectral4 weights file (fit/spectral4_run.h's params) with plausible
 * values, for the tests that emit and run its header: the matrices are the
 * format's (the colour matching functions at the wavelengths times the
 * weights, and the sRGB matrix times that, which codegen checks), so the
 * sRGB matrix has entries of both signs and its sums cancel. */
#ifndef SKYFIT_TESTS_SPECTRAL4_TEST_WEIGHTS_H
#define SKYFIT_TESTS_SPECTRAL4_TEST_WEIGHTS_H

#include <stdlib.h>

#include "models/atmosphere.h"
#include "models/spectral_data.h"
#include "models/weights_file.h"

static inline int write_spectral4_weights(const char *path, const sf_atmosphere *atm) {
  sf_scene_domain domain = {0.0, 100.0, -1.0, 1.0, -0.2, 1.0};
  cJSON *doc = sf_weights_new("spectral4", "sky_radiance", atm, &domain);
  double l[4] = {445.5, 518.25, 582.0, 630.75}, wgt[4] = {61.0, 72.5, 80.0, 95.25};
  double xyz[12], srgb[12];
  sf_cmf *cmf = malloc(sizeof *cmf);
  sf_error cmf_err;
  sf_error_clear(&cmf_err);
  if (!cmf || sf_cmf_load(cmf, &cmf_err)) {
    free(cmf);
    return SF_ERR_INPUT;
  }
  sf_spectral4_to_xyz(cmf, l, wgt, xyz);
  free(cmf);
  sf_spectral4_srgb_of_xyz(xyz, srgb);
  double sun[4] = {1.9, 1.85, 1.8, 1.6}, albedo[4] = {0.3, 0.3, 0.3, 0.3};
  double sc[12] = {0.0331, 0.0196, 0.0120, 0.0087, 0.0040, 0.0040, 0.0040, 0.0040, 0.0, 0.0, 0.0, 0.0};
  double ab[12] = {0.0, 0.0, 0.0, 0.0, 4.4e-4, 4.4e-4, 4.4e-4, 4.4e-4, 1.0e-4, 1.2e-3, 1.9e-3, 8.5e-4};
  int s4[1] = {4}, s34[2] = {3, 4}, sc4[2] = {3, 4};
  sf_weights_add_param(doc, "wavelengths_nm", 1, s4, l);
  sf_weights_add_param(doc, "weights_nm", 1, s4, wgt);
  sf_weights_add_param(doc, "to_xyz", 2, s34, xyz);
  sf_weights_add_param(doc, "to_linear_srgb", 2, s34, srgb);
  sf_weights_add_param(doc, "sun_irradiance", 1, s4, sun);
  sf_weights_add_param(doc, "ground_albedo", 1, s4, albedo);
  sf_weights_add_param(doc, "scattering", 2, sc4, sc);
  sf_weights_add_param(doc, "absorption", 2, sc4, ab);
  cJSON_AddNumberToObject(sf_weights_metrics(doc), "loss", 1e-4);
  sf_error err;
  sf_error_clear(&err);
  int status = sf_weights_write(doc, path, &err);
  cJSON_Delete(doc);
  return status;
}

#endif
