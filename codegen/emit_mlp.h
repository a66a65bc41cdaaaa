/* The neural sky (SPEC §7.4-7.5, seed 000 §9.6, models/mlp_sky.h) as
 * emitted code, operation for operation as the model's float32 path
 * (models/mlp_sky_impl.inc with REAL = float):
 *
 * transmittance network (model "mlp-transmittance"), N = channels:
 *   vecN skyfit_mlp_transmittance(float h_km, float mu)
 *       the ray to the ground or out of the atmosphere; a ground-hitting ray
 *       by eq. 43 with reversed rays (seed 000 §9.6.3); a viewer above the
 *       top first moved to where its ray enters (1 if it never does);
 *   vecN skyfit_mlp_transmittance_segment(float h_km, float mu, float t_km)
 *       the first t_km of that ray (eq. 43);
 *   vecN skyfit_mlp_transmittance_top(float h_km, float mu)
 *       the network's T_top itself (no ground handling; used by the above);
 *   its inputs as the model's mapping: sqrt(h), mu, or Bruneton's x_r, x_mu
 *   written out with the float operations of models/mlp_sky_impl.inc.
 * scattering network (model "mlp-scattering"; sun irradiance 1: multiply by
 * the sun's irradiance per channel):
 *   vecN skyfit_mlp_sky_radiance(float h_km, float mu, float mu_s, float nu)
 *   vecN skyfit_mlp_sky_radiance_segment(float h_km, float mu, float mu_s, float nu, float t_km)
 *       eq. 44, S(viewer) - T(viewer -> t) S(point at t), clamped at 0;
 *       emitted only when the transmittance network of the same atmosphere
 *       is in the same file (it supplies T).
 * Target "separate" adds each constituent's phase function at nu to its
 * single-scattering outputs (models/phase.h), in float32.
 *
 * Constants: in C one flat `static const float` array per network (W0 row
 * major, b0, W1, b1, ... as models/mlp.h); in GLSL matrix types as seed 000
 * §9.6.3: each layer split into blocks of at most 4 inputs x 4 outputs
 * (a 2-4-3 network is mat2x4 W0, vec4 b0, mat4x3 W1, vec3 b1; layers of 8
 * are vec4 halves and mat4 blocks; a 1-wide piece is a vector or float),
 * z = b + sum of blocks * inputs. */
#ifndef SKYFIT_CODEGEN_EMIT_MLP_H
#define SKYFIT_CODEGEN_EMIT_MLP_H

#include "codegen/code_writer.h"
#include "models/mlp_sky.h"

/* Checks that a network can be emitted (1-4 channels; for separate targets
 * one output block per channel count). Returns 0, or -1 with why in problem. */
int sf_emit_mlp_check(const sf_mlp_sky *m, char *problem, size_t n);

void sf_emit_mlp_transmittance(sf_code_writer *w, const sf_mlp_sky *t);
/* t may be NULL: no segment function. */
void sf_emit_mlp_scattering(sf_code_writer *w, const sf_mlp_sky *s, const sf_mlp_sky *t);

#endif
