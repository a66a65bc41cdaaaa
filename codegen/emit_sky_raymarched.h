/* Leenman's raymarched sky (models/sky_raymarched.h) as emitted code:
 *   @vecN skyfit_<name>_sky_radiance(float h_km, float mu, float mu_s, float nu)
 * ("raymarched" with the seed's 5 steps, "flat" with one: Leenman's flat
 * sky, SF_SKY_FLAT_STEPS),
 * the same pieces in float32: the view ray in equal steps, split where the
 * sun ray grazes the ground, each piece integrated in closed form (seed 000
 * eq. 55) with the flat model's columns, a viewer above the top moved to
 * where its ray enters (skyfit_ray_enter), nu clamped as SPEC §3 says. Its
 * helpers skyfit_raymarched_columns (a segment's column of each
 * constituent, in a vec4) and skyfit_raymarched_sun_columns (from a point
 * to the top) come with it, once in a file that holds both skies. 1 to 4
 * channels and 1 to 4 constituents. */
#ifndef SKYFIT_CODEGEN_EMIT_SKY_RAYMARCHED_H
#define SKYFIT_CODEGEN_EMIT_SKY_RAYMARCHED_H

#include "codegen/code_writer.h"
#include "models/sky_raymarched.h"

/* Whether m can be emitted: 1-4 channels, 1-4 constituents and flat
 * depths; else 0 with *why saying what is not. */
int sf_sky_raymarched_emittable(const sf_sky_raymarched *m, const char **why);

/* name: the function's model name, "raymarched" or "flat". */
void sf_emit_sky_raymarched(sf_code_writer *w, const sf_sky_raymarched *m, const char *name);

#endif
