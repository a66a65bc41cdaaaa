/* The naive sky (models/sky_naive.h) as emitted code:
 *   @vecN skyfit_naive_sky_radiance(float h_km, float mu, float mu_s, float nu)
 * the same midpoint sums in float32 (the steps unrolled by nothing: two
 * loops), a viewer above the top moved to where its ray enters
 * (skyfit_ray_enter), nu clamped as SPEC §3 says. 1 to 4 channels.
 * Schuler's sky (m->sun SF_SKY_SUN_CHAPMAN) is skyfit_schuler_sky_radiance,
 * the inner loop replaced by skyfit_schuler_sun_columns (the Chapman
 * baseline's columns from a point to the top, in a vec4): 1 to 4
 * constituents, at least one of them exponential (sf_sky_naive_emittable). */
#ifndef SKYFIT_CODEGEN_EMIT_SKY_NAIVE_H
#define SKYFIT_CODEGEN_EMIT_SKY_NAIVE_H

#include "codegen/code_writer.h"
#include "models/sky_naive.h"

/* Whether m can be emitted; else 0 with *why saying what is not. */
int sf_sky_naive_emittable(const sf_sky_naive *m, const char **why);

void sf_emit_sky_naive(sf_code_writer *w, const sf_sky_naive *m);

#endif
