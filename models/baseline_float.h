/* Three analytic transmittance baselines of SPEC §7.6 in float32, the
 * operations of their emitted code (codegen/baselines.c) in the same
 * order, for the report's timing (SPEC §12: the cost of the code that
 * ships; they had been timed in double): Schuler's Chapman approximation
 * (seed 000 eq. 22-25), Gałaj's Taylor transmittance (seed 002 eq. 12-17)
 * and Leenman's flat model (seed 000 eq. 51, 53 at the viewer), the
 * non-exponential constituents as seed 000 eq. 59's shells. The whole ray
 * only (what the report times); tests/test_candidate_emit.c holds them to
 * the compiled emitted code. */
#ifndef SKYFIT_MODELS_BASELINE_FLOAT_H
#define SKYFIT_MODELS_BASELINE_FLOAT_H

#include "models/atmosphere.h"

typedef enum sf_baseline_f_kind {
  SF_BASELINE_F_CHAPMAN = 0,
  SF_BASELINE_F_TAYLOR,
  SF_BASELINE_F_FLAT
} sf_baseline_f_kind;

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
} sf_baseline_f;

/* 0, or -1 when the atmosphere has more than 4 channels. */
int sf_baseline_f_make(const sf_atmosphere *atm, sf_baseline_f_kind kind, sf_baseline_f *out);

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
