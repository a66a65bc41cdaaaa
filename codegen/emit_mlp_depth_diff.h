/* The transmittance network's tau_top(a) - tau_top(b) as emitted code
 * (eq. 43 in depth mode, SPEC §10's cancellation): the two forward passes
 * and their difference carried beside them (models/mlp_sky_impl.inc
 * t_depth_diff, operation for operation). Emits, for a network whose
 * output is exp_neg or exp_neg_exp:
 *   the per-unit difference helpers its activations need,
 *   vec2 skyfit_mlp_transmittance_inputs_diff(...)  x_a - x_b of the inputs,
 *   vecN skyfit_mlp_transmittance_depth_diff(float h_a, float mu_a,
 *                                            float h_b, float mu_b).
 * Needs skyfit_mlp_transmittance_inputs(h, mu) emitted before it. */
#ifndef SKYFIT_CODEGEN_EMIT_MLP_DEPTH_DIFF_H
#define SKYFIT_CODEGEN_EMIT_MLP_DEPTH_DIFF_H

#include "codegen/code_writer.h"
#include "models/mlp_sky.h"

void sf_emit_mlp_depth_diff(sf_code_writer *w, const sf_mlp_sky *t);

#endif
