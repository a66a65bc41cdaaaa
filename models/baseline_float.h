/* Four analytic transmittance baselines of SPEC §7.6 in float32, the
 * operations of their emitted code (codegen/baselines.c,
 * codegen/baseline_spline.c) in the same order, for the report's timing
 * (SPEC §12: the cost of the code that ships; they had been timed in
 * double): Schuler's Chapman approximation (seed 000 eq. 22-25), Gałaj's
 * Taylor transmittance (seed 002 eq. 12-17), Leenman's flat model (seed
 * 000 eq. 51, 53 about the closest point) and Gałaj's spline (seed 002 §IV.E, its
 * Hermite meshes as the emitted float arrays), the non-exponential
 * constituents as seed 000 eq. 59's shells. The whole ray only (what the
 * report times); tests/test_candidate_emit.c holds them to the compiled
 * emitted code. */
#ifndef SKYFIT_MODELS_BASELINE_FLOAT_H
#define SKYFIT_MODELS_BASELINE_FLOAT_H

#include "models/atmosphere.h"
#include "models/optical_depth_spline.h"

typedef enum sf_baseline_f_kind {
  SF_BASELINE_F_CHAPMAN = 0,
  SF_BASELINE_F_TAYLOR,
  SF_BASELINE_F_FLAT,
  SF_BASELINE_F_SPLINE
} sf_baseline_f_kind;

/* One spline mesh as the emitted code holds it: a float vec4 per node
 * (value, x slope, d slope, mixed slope), node (i, j) at j * n_x + i. */
typedef struct sf_spline_grid_f {
  int n_x, n_d;
  float x_step, x_end, d_first, d_step;
  const float (*node)[4];
} sf_spline_grid_f;

/* The atmosphere's numbers as the emitted code holds them (float32). */
typedef struct sf_baseline_f {
  sf_baseline_f_kind kind;
  int n_constituents, n_channels;
  float bottom, thickness, top;
  int is_shell[SF_MAX_CONSTITUENTS];
  float scale_height[SF_MAX_CONSTITUENTS];
  float factor[SF_MAX_CONSTITUENTS];     /* what multiplies the column: d0 (Chapman: H d0) */
  float shell_lo[SF_MAX_CONSTITUENTS], shell_hi[SF_MAX_CONSTITUENTS];
  float extinction[SF_MAX_CONSTITUENTS][4];
  /* SF_BASELINE_F_SPLINE: the exponential constituents' meshes (regions I
   * and II), in storage (owned: sf_baseline_f_free) */
  sf_spline_grid_f miss[SF_MAX_CONSTITUENTS], hit[SF_MAX_CONSTITUENTS];
  float (*storage)[4];
} sf_baseline_f;

/* 0, or -1 when the atmosphere has more than 4 channels. Chapman, Taylor
 * and flat: nothing to free. */
int sf_baseline_f_make(const sf_atmosphere *atm, sf_baseline_f_kind kind, sf_baseline_f *out);
/* The spline from its double meshes (model, made for atm): 0, or -1 (more
 * than 4 channels, out of memory; nothing to free). */
int sf_baseline_f_make_spline(const sf_atmosphere *atm, const sf_spline_model *model, sf_baseline_f *out);
void sf_baseline_f_free(sf_baseline_f *b);

/* depth[n_constituents]: the columns (km) over the piece seg of the ray
 * (h, mu), as skyfit_air_clip gives it (a, b, altitude at a, at b): the
 * depths inside the emitted skyfit_<name>_transmittance_between; 0 where
 * the piece is empty. */
void sf_baseline_columns_f(const sf_baseline_f *b, float h, float mu, const float seg[4], float *depth);

/* T[n_channels] of the ray from (h_km, mu) to the ground or out of the
 * atmosphere, a viewer above the top from where its ray enters: the
 * emitted skyfit_<name>_transmittance(h_km, mu). */
void sf_baseline_transmittance_f(const sf_baseline_f *b, float h_km, float mu, float *T);

#endif
