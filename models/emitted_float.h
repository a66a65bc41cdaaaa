/* What emitted code computes, in float32 and in C, for the float32
 * evaluations the report times (SPEC §12: the cost of the shipped code):
 * the emitted helpers' ray geometry (codegen/emit_helpers.c), which takes
 * altitudes, not radii (R - r in float32 loses a low viewer's altitude:
 * a viewer 1 m up looking down had come out 2.3 % off the emitted code),
 * and a constituent's density as sf_emit_constituent_density writes it
 * (codegen/baselines.h). Each function is the emitted one's operations in
 * the same order. */
#ifndef SKYFIT_MODELS_EMITTED_FLOAT_H
#define SKYFIT_MODELS_EMITTED_FLOAT_H

#include "models/atmosphere.h"

/* skyfit_ray_enter: a viewer above the top (h > h_top) moved to where its
 * ray enters, *h, *mu and (if not NULL) *mu_s updated; 0 if the ray never
 * enters. A viewer inside is left as it is (returns 1). */
int sf_emitted_ray_enter_f(float R, float h_top, float *h, float *mu, float *mu_s, float nu);

/* skyfit_sphere_hits: distances near <= far to the sphere of radius R from
 * radius r, R - r passed as an altitude difference; near > far where the
 * line misses. */
void sf_emitted_sphere_hits_f(float r, float mu, float R, float R_minus_r, float *near, float *far);

/* skyfit_air_clip of the whole ray (t0 = 0, t1 = 3.4e38): [*a, *b] within
 * the air, *b <= *a when empty. */
void sf_emitted_air_clip_f(float bottom, float thickness, float h, float mu, float *a, float *b);

/* A constituent's density profile rounded to float32 once. */
typedef struct sf_density_f {
  int n_layers;
  float layer_top[SF_MAX_LAYERS];   /* cumulative widths */
  float linear[SF_MAX_LAYERS], constant[SF_MAX_LAYERS], exp_term[SF_MAX_LAYERS], exp_scale[SF_MAX_LAYERS];
} sf_density_f;

void sf_density_f_make(const sf_constituent *c, sf_density_f *out);
/* The density at altitude h: linear h + constant + exp_term e^(exp_scale h)
 * of h's layer (the first whose cumulative top lies above h, else the
 * last), clamped to [0, 1]. */
float sf_density_f_at(const sf_density_f *d, float h);

#endif
