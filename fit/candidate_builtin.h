/* The candidates that need no fitting (fit/candidate.h):
 *  - the reference of each quantity: transmittance from the exact optical
 *    depth (models/optical_depth.h, adaptive Gauss-Kronrod), sky radiance
 *    from the reference tables (data/sky_lookup.h: single + multiple
 *    scattering, the only reference of multiple scattering there is);
 *  - the transmittance table lookup (Bruneton's 2D table, multilinear), a
 *    "lookup" model: what a renderer gets from shipping the table;
 *  - the analytic transmittance baselines of SPEC §7.6: the 16-step naive
 *    midpoint raymarch (seed 000 §11.2.6, the cost unit of SPEC §12),
 *    Schuler's Chapman approximation (seed 000 eq. 22-25), Gałaj's Taylor
 *    formula (seed 002 eq. 17, a = b = 0.45) and Leenman's flat model (seed
 *    000 eq. 48-53, 59). Chapman and Taylor treat a non-exponential
 *    constituent (the ozone tent) as the flat model's constant shell (seed
 *    000 §10.5), as codegen/baselines.h emits them.
 * Each constructor fills *out; tables and atmosphere are borrowed (must
 * outlive the candidate). Parameter counts of the baselines are the
 * atmosphere constants their emitted code holds (per constituent: one
 * extinction per channel, plus the profile: H and d0 for an exponential,
 * the shell's two radii, or the raymarch's 5 numbers per density layer;
 * plus the two radii), at 4 bytes each. */
#ifndef SKYFIT_FIT_CANDIDATE_BUILTIN_H
#define SKYFIT_FIT_CANDIDATE_BUILTIN_H

#include "data/sky_lookup.h"
#include "fit/candidate.h"
#include "models/atmosphere.h"
#include "util/error.h"

#define SF_NAIVE_COST_UNIT_STEPS 16

typedef enum sf_transmittance_baseline {
  SF_TB_NAIVE = 0,   /* N-step midpoint raymarch */
  SF_TB_CHAPMAN,
  SF_TB_TAYLOR,
  SF_TB_FLAT,
  SF_TB_SPLINE       /* Gałaj's Hermite meshes (models/optical_depth_spline.h) */
} sf_transmittance_baseline;

/* Exact reference transmittance (slow: ~3e5 evaluations/s). */
int sf_candidate_reference_transmittance(const sf_atmosphere *atm, sf_candidate *out, sf_error *err);
/* Transmittance from the tables' transmittance table. */
int sf_candidate_table_transmittance(const sf_sky_tables *sky, sf_candidate *out, sf_error *err);
/* Sky radiance from the tables: the reference of the sky-radiance models. */
int sf_candidate_table_sky_radiance(const sf_sky_tables *sky, sf_candidate *out, sf_error *err);
/* What a sky-radiance baseline's candidate sets after sf_candidate_init
 * (fit/candidate_sky_*.c): n_params float32 constants, its double
 * evaluation over ctx (owned: freed with free), and where emit is not NULL
 * the emitted code (skyfit_<emit_name>_sky_radiance), its model and its
 * float32 port, which the report times. */
void sf_candidate_sky_baseline_set(sf_candidate *out, const sf_atmosphere *atm, long n_params, const char *emit_name,
                                   void (*emit)(struct sf_code_writer *w, const void *model), const void *emit_model,
                                   sf_candidate_eval_fn eval, sf_candidate_eval_f32_fn eval_f32, void *ctx);
/* The naive sky (models/sky_naive.h): single scattering raymarched,
 * SF_SKY_NAIVE_VIEW_STEPS x SF_SKY_NAIVE_SUN_STEPS, the sky-radiance
 * baseline for every viewer (fit/candidate_sky_naive.c). */
int sf_candidate_sky_naive(const sf_atmosphere *atm, sf_candidate *out, sf_error *err);
/* Schuler's sky (models/sky_naive.h sf_sky_schuler_make): the naive sky's
 * view ray, the sun's depths by the Chapman approximation. */
int sf_candidate_sky_schuler(const sf_atmosphere *atm, sf_candidate *out, sf_error *err);
/* Leenman's raymarched sky (models/sky_raymarched.h): 5 closed-form steps
 * with the flat model's depths, for every viewer
 * (fit/candidate_sky_raymarched.c). */
int sf_candidate_sky_raymarched(const sf_atmosphere *atm, sf_candidate *out, sf_error *err);
/* Leenman's flat sky: the same model in one step (SF_SKY_FLAT_STEPS). */
int sf_candidate_sky_flat(const sf_atmosphere *atm, sf_candidate *out, sf_error *err);
/* An analytic transmittance baseline; steps is used by SF_TB_NAIVE only
 * (name "naive<steps>"). SF_ERR_INPUT when the model does not apply (no
 * exponential constituent for Chapman/Taylor/flat/spline). */
int sf_candidate_transmittance_baseline(const sf_atmosphere *atm, sf_transmittance_baseline kind,
                                        int steps, sf_candidate *out, sf_error *err);

#endif
