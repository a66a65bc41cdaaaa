/* The functions `skyfit build` adds to the headers it emits: the scene's
 * selection under stable names, so that a renderer's code does not change
 * when a new atmosphere or budget selects another model (the Preetham fit
 * of a ground scene is skyfit_preetham_sky_radiance(mu, mu_s, nu), the
 * network of a flying one skyfit_mlp_sky_radiance(h_km, mu, mu_s, nu)):
 *   vecN skyfit_transmittance(float h_km, float mu)
 *   vecN skyfit_transmittance_segment(float h_km, float mu, float t_km)
 *   vecN skyfit_sky_radiance(float h_km, float mu, float mu_s, float nu)
 *   vecN skyfit_sky_radiance_segment(float h_km, float mu, float mu_s, float nu, float t_km)
 * each present when the scene selected a model of that quantity (and that
 * model has segments); a ground-only sky model takes h_km and ignores it. */
#ifndef SKYFIT_CODEGEN_EMIT_SELECTION_ALIAS_H
#define SKYFIT_CODEGEN_EMIT_SELECTION_ALIAS_H

#include "codegen/code_writer.h"

typedef struct sf_selection_alias {
  int n_channels;
  char transmittance[64];   /* the selected model's function prefix (skyfit_<it>_...), "" for none */
  char sky_radiance[64];
  int sky_takes_altitude;   /* 0: a ground viewer's model, f(mu, mu_s, nu) */
  int sky_has_segment;
} sf_selection_alias;

/* Writes the functions above; model is an sf_selection_alias. */
void sf_emit_selection_alias(sf_code_writer *w, const void *model);

#endif
