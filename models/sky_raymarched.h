/* Leenman's raymarched sky (seed 000 §10.4, §11.2.10; SPEC §7.6 "Leenman's
 * raymarched model"): single scattering in a few long steps, each step
 * integrated in closed form instead of sampled. On a piece [a, b] of the
 * view ray the scattering density is taken as constant (the piece's column
 * of each constituent spread evenly) and the optical depth from the viewer
 * to the point and on to the sun as linear between its values at the ends,
 * A and B; the piece then gives (seed 000 eq. 54-55)
 *   L += E_sun sum_i P_i(nu) beta_s,i col_i (e^-A - e^-B) / (B - A),
 * the integral of e^-(A + s (B - A)) over s in [0, 1] (eq. 46-47). The
 * optical depths come from Leenman's flat model (seed 000 §10.1-10.3,
 * models/optical_depth_flat.h, with the closest point as the midpoint of a
 * descending ray: columns that add up along the ray), the sun's from the
 * end point to the top; the seed takes 5 equal steps.
 *
 * Beyond the seed: the planet's shadow. Where the sun ray from a point
 * grazes the ground the ray is split (models/sun_shadow.h), and a piece
 * in the shadow gives nothing, so the shadow's edge is where the geometry
 * puts it instead of at a step; the ray is split too where the sun line
 * passes closest to the ground, where the edges appear as the sun sets
 * (the radiance continuous as they do). No multiple scattering and no ground light,
 * as in the seed; a viewer above the top starts where its ray enters, as
 * the reference does.
 *
 * With the reference's optical depths in place of the flat model's
 * (SF_RAYMARCHED_DEPTHS_EXACT) and many steps it converges to the
 * reference single scattering times the phase functions
 * (tests/test_sky_raymarched.c): the integrator checked apart from the
 * depths. */
#ifndef SKYFIT_MODELS_SKY_RAYMARCHED_H
#define SKYFIT_MODELS_SKY_RAYMARCHED_H

#include "models/atmosphere.h"
#include "models/emitted_float.h"
#include "models/optical_depth_flat.h"

/* seed 000 §11.2.10: "set to 5, as this provides a good tradeoff". */
#define SF_SKY_RAYMARCHED_STEPS 5

/* Leenman's flat sky (seed 000 §10.1-10.3, §11.2.9) is this model in one
 * step: looking up, the one piece from the viewer to the top is eq. 52 (A
 * the sun's depth at the viewer, B the view ray's; the columns end at the
 * top where eq. 51's run on, which differs by about e^-(top - h)/H of
 * them: tests/test_sky_raymarched.c); toward the ground it is eq. 55's one
 * segment, as §11.2.9 says. The seed's flat sky has no shadow (its
 * planet-shadow-orbit figure in App. B is 1.40, a mean squared error);
 * here the splits above are kept, so a shadowed ray takes up to 4 pieces. */
#define SF_SKY_FLAT_STEPS 1

typedef enum sf_raymarched_depths {
  SF_RAYMARCHED_DEPTHS_FLAT = 0,   /* the model: seed 000 §10.1-10.3 */
  SF_RAYMARCHED_DEPTHS_EXACT       /* the reference's (models/optical_depth.h): the integrator alone */
} sf_raymarched_depths;

typedef struct sf_sky_raymarched {
  const sf_atmosphere *atm;
  int steps;                       /* equal steps of the view ray, >= 1 */
  sf_raymarched_depths depths;
  sf_flat_model flat;              /* the flat model's shells (SF_RAYMARCHED_DEPTHS_FLAT) */
} sf_sky_raymarched;

void sf_sky_raymarched_make(const sf_atmosphere *atm, int steps, sf_raymarched_depths depths,
                            sf_sky_raymarched *out);

/* L[atm->n_channels] at (h_km, mu, mu_s, nu), nu clamped to what mu and
 * mu_s allow (SPEC §3). */
void sf_sky_raymarched_radiance(const sf_sky_raymarched *m, double h_km, double mu, double mu_s, double nu,
                                double *L);

/* (e^-a - e^-b) / (b - a), the mean of e^-x over [a, b] (either order), a,
 * b >= 0; e^-a where they meet, without the cancellation of the quotient. */
double sf_exp_mean_between(double a, double b);

/* The same pieces in float32, as the emitted code runs them
 * (codegen/emit_sky_raymarched.h; the report times this): the
 * atmosphere's numbers rounded once by sf_sky_raymarched_f_make, the
 * phase functions in double rounded to float as the networks' float32
 * evaluation takes them. At most 4 channels and 4 constituents. */
typedef struct sf_sky_raymarched_f {
  int steps;
  sf_sky_constants_f sky;
  int is_shell[4];
  float scale_height[4], density[4];   /* exponential constituents: H and d0 */
  float shell_lo[4], shell_hi[4];      /* the others: the shell's altitudes */
} sf_sky_raymarched_f;

/* 0, or -1 where the model cannot be emitted (sf_sky_raymarched_emittable). */
int sf_sky_raymarched_f_make(const sf_sky_raymarched *m, sf_sky_raymarched_f *out);
void sf_sky_raymarched_radiance_f(const sf_sky_raymarched_f *m, float h_km, float mu, float mu_s, float nu,
                                  float *L);

#endif
