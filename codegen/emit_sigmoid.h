/* The sigmoid-polynomial transmittance (SPEC §7.1, seed 000 §9.5,
 * models/sigmoid_transmittance.h) as emitted code, N = channels:
 *   vecN skyfit_sigmoid_transmittance(float h_km, float mu)
 *       the full ray (to the ground or the top) from the fitted
 *       T_top = prod_c 1 / (1 + exp(-(a1 + a2 h + a3 mu + a4 mu^2))) per
 *       channel, in logs (skyfit_sigmoid_log_top: log T_top = -sum
 *       softplus(-x); skyfit_sigmoid_log_line): rays looking up T_top
 *       itself, rays to the ground eq. 43 with reversed rays, rays past the
 *       tangent point through it; the constants as one const array
 *       a[c][k][4]; a viewer above the top first moved to where its ray
 *       enters (1 if it never does);
 *   vecN skyfit_sigmoid_transmittance_segment(float h_km, float mu, float t_km)
 *       the first t_km of that ray: the model gives the transmittance from
 *       any point of the ray to the ray's end (the same ground point or top
 *       exit), so T(viewer -> t) = T(h, mu) / T(h_t, mu_t), computed as
 *       exp(min(0, log T(h, mu) - log T(h_t, mu_t))) with
 *       log T = -sum softplus(-x) (no division of tiny numbers, SPEC §10);
 *       t at or beyond the ray's end gives the whole ray. */
#ifndef SKYFIT_CODEGEN_EMIT_SIGMOID_H
#define SKYFIT_CODEGEN_EMIT_SIGMOID_H

#include "codegen/code_writer.h"
#include "models/sigmoid_transmittance.h"

typedef struct sf_sigmoid_emit {
  sf_sigmoid_model model;
  double bottom_radius_km, top_radius_km;   /* of the weights file's atmosphere */
} sf_sigmoid_emit;

/* The functions above. */
void sf_emit_sigmoid_ray(sf_code_writer *w, const sf_sigmoid_emit *m);

#endif
