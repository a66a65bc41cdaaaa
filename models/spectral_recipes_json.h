/* Reading a recipe object (models/spectral_recipes.h) in the atmosphere file
 * and replacing it by the per-wavelength numbers it derives. */
#ifndef SKYFIT_MODELS_SPECTRAL_RECIPES_JSON_H
#define SKYFIT_MODELS_SPECTRAL_RECIPES_JSON_H

#include <cjson/cJSON.h>

#include "models/atmosphere.h"
#include "util/json_read.h"

typedef enum sf_recipe_target {
  SF_RECIPE_FOR_COEFFICIENT,   /* "scattering" / "absorption" of a constituent */
  SF_RECIPE_FOR_SUN            /* "sun_irradiance" */
} sf_recipe_target;

/* v is the recipe object at key path `path`; atm gives the channels
 * (spectral mode required) and the thickness; owner is the constituent the
 * coefficients belong to, with its density already read (NULL for the sun).
 * Fills out[0..atm->n_channels-1]; SF_ERR_INPUT "<source>: <path>: <problem>"
 * otherwise. */
int sf_read_recipe(const sf_json_ctx *c, const cJSON *v, const char *path, const sf_atmosphere *atm,
                   const sf_constituent *owner, sf_recipe_target target, double *out);

#endif
