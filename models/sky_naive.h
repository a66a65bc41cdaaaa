/* The naive sky (SPEC §7.6 "N-step raymarch"; seed 000 §11.2.6, Terrell
 * 2016 with ozone): single scattering by direct numerical integration,
 *   L = E_sun sum_i P_i(nu) beta_s,i sum_k rho_i(p_k) T(viewer -> p_k) T(p_k -> sun) dt,
 * p_k the midpoints of view_steps equal steps of the view ray (to the
 * ground or out of the atmosphere), T(viewer -> p_k) by the same midpoint
 * sum, T(p_k -> sun) by a sun_steps midpoint raymarch to the top, 0 where
 * the planet hides the sun. No multiple scattering and no ground light,
 * as in the seed: the sky-radiance baseline of the speed-against-error
 * report, for every viewer (a viewer above the top starts where its ray
 * enters, as the reference does), where Preetham and Hosek take a ground
 * viewer only. Converges to the reference's single scattering times the
 * phase functions (models/single_scattering.h) as the steps grow
 * (tests/test_sky_naive.c); codegen/emit_sky_naive.h emits the same sums
 * in float32.
 *
 * Schuler's sky (seed 000 §11.2.7) is this model with the sun's optical
 * depth at each step from Schuler's Chapman approximation (seed 000 eq.
 * 22-25, models/optical_depth_chapman.h) instead of the inner raymarch,
 * and 24 view steps (§12.3.1). The seed's leaves ozone out, the
 * approximation holding for exponential profiles only; here, as in the
 * Chapman transmittance baseline, a non-exponential constituent's sun
 * column is its seed 000 eq. 59 shell's chord, its density along the view
 * ray the true one. */
#ifndef SKYFIT_MODELS_SKY_NAIVE_H
#define SKYFIT_MODELS_SKY_NAIVE_H

#include "models/atmosphere.h"
#include "models/baseline_float.h"
#include "models/emitted_float.h"

/* Terrell's steps: 16 along the view ray, 8 toward the sun. */
#define SF_SKY_NAIVE_VIEW_STEPS 16
#define SF_SKY_NAIVE_SUN_STEPS 8
/* seed 000 §12.3.1: Schuler's model takes 24 steps. */
#define SF_SKY_SCHULER_VIEW_STEPS 24

typedef enum sf_sky_sun_depth {
  SF_SKY_SUN_RAYMARCH = 0,   /* the naive sky: sun_steps midpoints */
  SF_SKY_SUN_CHAPMAN         /* Schuler's sky: seed 000 eq. 24, eq. 59 shells */
} sf_sky_sun_depth;

typedef struct sf_sky_naive {
  const sf_atmosphere *atm;
  int view_steps, sun_steps;   /* >= 1 each (sun_steps: SF_SKY_SUN_RAYMARCH) */
  sf_sky_sun_depth sun;
  /* SF_SKY_SUN_CHAPMAN: the shells of the non-exponential constituents
   * (km above the ground; models/optical_depth_flat.h) */
  double shell_lo[SF_MAX_CONSTITUENTS], shell_hi[SF_MAX_CONSTITUENTS];
} sf_sky_naive;

/* Schuler's sky for atm: SF_SKY_SCHULER_VIEW_STEPS, the Chapman sun. */
void sf_sky_schuler_make(const sf_atmosphere *atm, sf_sky_naive *out);

/* L[atm->n_channels] at (h_km, mu, mu_s, nu), nu clamped to what mu and
 * mu_s allow (SPEC §3). */
void sf_sky_naive_radiance(const sf_sky_naive *m, double h_km, double mu, double mu_s, double nu, double *L);

/* The same sums in float32, as the emitted code runs them (the report
 * times this): the atmosphere's numbers rounded once by
 * sf_sky_naive_f_make, at most 4 channels. */
typedef struct sf_sky_naive_f {
  int view_steps, sun_steps;
  sf_sky_sun_depth sun;
  sf_sky_constants_f sky;
  sf_density_f density[SF_MAX_CONSTITUENTS];
  sf_baseline_f chapman;   /* SF_SKY_SUN_CHAPMAN: the sun's columns */
} sf_sky_naive_f;

/* 0, or -1 when the atmosphere has more than 4 channels (Schuler's: more
 * than 4 constituents too, or no exponential one). */
int sf_sky_naive_f_make(const sf_sky_naive *m, sf_sky_naive_f *out);
void sf_sky_naive_radiance_f(const sf_sky_naive_f *m, float h_km, float mu, float mu_s, float nu, float *L);

#endif
