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

/* skyfit_air_clip: [t0, t1] of the ray within the air and before the
 * ground, seg = (a, b, altitude at a, altitude at b); empty: b <= a. */
void sf_emitted_air_clip_between_f(float bottom, float thickness, float h, float mu, float t0, float t1,
                                   float seg[4]);

/* skyfit_shell_chord: the length of [t0, t1] between altitudes lo < hi. */
float sf_emitted_shell_chord_f(float bottom, float lo, float hi, float h, float mu, float t0, float t1);

/* skyfit_expm1: e^x - 1, a degree-6 Taylor polynomial below |x| = 0.1. */
float sf_emitted_expm1_f(float x);

/* skyfit_flat_up_diff: the flat model's column (seed 000 eq. 51) of
 * exp(-h/H) from point a minus from b = a + (dh, dh, ds), both rising. */
float sf_emitted_flat_up_diff_f(float H, float h_a, float r_a, float s_a, float dh, float ds);

/* What an emitted sky holds of its atmosphere, rounded to float32 once:
 * the radii (bottom and thickness), per constituent its scattering and
 * extinction per channel and its phase function, the sun per channel. */
typedef struct sf_sky_constants_f {
  int n_constituents, n_channels;
  float bottom, thickness;
  float scattering[SF_MAX_CONSTITUENTS][4], extinction[SF_MAX_CONSTITUENTS][4], sun[4];
  sf_phase phase[SF_MAX_CONSTITUENTS];
} sf_sky_constants_f;

/* 0, or -1 when the atmosphere has more than 4 channels. */
int sf_sky_constants_f_make(const sf_atmosphere *atm, sf_sky_constants_f *out);

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
