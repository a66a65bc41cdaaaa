/* The frame the emitted single-scattering skies share (codegen/
 * emit_sky_naive.h, emit_sky_raymarched.h): what they declare per
 * constituent, the view ray's start and the return.
 *
 * sf_emit_sky_open writes, after the caller's comment,
 *   @fn vecN skyfit_<name>_sky_radiance(float h_km, float mu, float mu_s, float nu) {
 *     nu clamped (SPEC §3); float l<k> = 0 per channel;
 *     a viewer above the top moved to where its ray enters (skyfit_ray_enter):
 *     hv, m, ms its altitude, view and sun cosines there;
 *     seg = skyfit_air_clip(...) of the whole ray; r = bottom + hv;
 *     p<i> the phase functions of the constituents that scatter;
 * inside two open blocks (the ray enters; seg is not empty), which
 * sf_emit_sky_close closes, the l<k> scaled by the sun, returned. */
#ifndef SKYFIT_CODEGEN_EMIT_SKY_FRAME_H
#define SKYFIT_CODEGEN_EMIT_SKY_FRAME_H

#include "codegen/code_writer.h"
#include "models/atmosphere.h"

/* Whether constituent i scatters light of channel k (its phase function
 * emitted as p<i>), in some channel, and whether it dims some channel: the
 * variables an emitted sky declares, so that none is emitted that nothing
 * reads (-Wall -Werror: an absorber's phase function, a transparent
 * constituent's depths; the transmittance baselines' too,
 * codegen/baselines.c). */
int sf_emit_sky_scatters(const sf_atmosphere *atm, int i, int k);
int sf_emit_sky_scatters_any(const sf_atmosphere *atm, int i);
int sf_emit_sky_dims_any(const sf_atmosphere *atm, int i);

void sf_emit_sky_open(sf_code_writer *w, const sf_atmosphere *atm, const char *name);
/* sun_factor: what multiplies each l<k> with the sun's irradiance ("" or
 * "dt * "). */
void sf_emit_sky_close(sf_code_writer *w, const sf_atmosphere *atm, const char *sun_factor);

#endif
