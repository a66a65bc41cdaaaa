/* Fitted models (weights files, SPEC §8) as parts of an emitted file: the
 * dispatcher from a weights file's "model" to its emitter. Each model's
 * parameters are read with the model's own loader (models/<model>.h), so
 * the emitted constants are exactly what the model evaluates.
 *   sigmoid            -> skyfit_sigmoid_transmittance[_segment]     (codegen/emit_sigmoid.h)
 *   hosek, preetham    -> skyfit_<model>_sky_radiance                (codegen/emit_sky.h)
 *   mlp-transmittance  -> skyfit_mlp_transmittance[_segment]         (codegen/emit_mlp.h)
 *   mlp-scattering     -> skyfit_mlp_sky_radiance[_segment]          (the segment only with
 *                         a transmittance network of the same atmosphere: sf_fitted_link)
 *   spectral4          -> skyfit_spectral4_*                         (codegen/emit_spectral4.h) */
#ifndef SKYFIT_CODEGEN_FITTED_PART_H
#define SKYFIT_CODEGEN_FITTED_PART_H

#include "codegen/codegen_file.h"
#include "codegen/emit_mlp.h"
#include "codegen/emit_sigmoid.h"
#include "codegen/emit_sky.h"
#include "codegen/emit_spectral4.h"
#include "models/weights_file.h"

typedef enum sf_fitted_kind {
  SF_FITTED_SIGMOID = 0,
  SF_FITTED_SKY,            /* hosek or preetham */
  SF_FITTED_MLP_TRANSMITTANCE,
  SF_FITTED_MLP_SCATTERING,
  SF_FITTED_SPECTRAL4
} sf_fitted_kind;

/* The loaded model an emitter writes. */
typedef struct sf_fitted_model {
  sf_fitted_kind kind;
  sf_sigmoid_emit sigmoid;
  sf_elevation_sky_model sky;
  sf_mlp_sky mlp;
  const sf_mlp_sky *transmittance;   /* scattering: the linked transmittance network, or NULL */
  sf_spectral4_emit spectral4;
} sf_fitted_model;

/* Loads the model of w (already loaded from w->source) into *model
 * (free with sf_fitted_free) and fills part, which points into *model.
 * SF_ERR_INPUT "<file>: model: no emitter for model \"x\"" for models
 * without an emitter. */
int sf_fitted_part(const sf_weights *w, sf_fitted_model **model, sf_codegen_part *part,
                   sf_error *err);
void sf_fitted_free(sf_fitted_model *model);

/* Gives every mlp-scattering model among models[0..n) the mlp-transmittance
 * model of the same atmosphere (the same atmosphere hash),
 * so that its segment function (eq. 44) is emitted; updates its part's
 * summary, and moves a linked transmittance part that comes after its
 * scattering part to just before it (the segment function calls it, and
 * C and GLSL declare a function before its use). Call after all parts are
 * made; models[k] and parts[k] stay paired. */
void sf_fitted_link(sf_fitted_model **models, sf_codegen_part *parts, int n);

/* The model names that have an emitter, comma-separated. */
const char *sf_fitted_emitters(void);

/* "max abs X" for a header's measured-error line: the largest error over
 * the values the build sampled, or, where the fit's own search near the
 * horizon (the weights file's metrics.max_abs; NAN: none) found a larger
 * one, that with the sample's beside it. Both headers (skyfit build's and
 * skyfit codegen's) state it so. */
void sf_fitted_max_abs_text(double sample_max_abs, double fit_max_abs, char *out, size_t n);

#endif
