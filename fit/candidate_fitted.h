/* Factories of the fitted models for fit/candidate_registry.c, one file
 * each (fit/candidate_<model>.c). See fit/candidate_registry.h for the
 * contract. */
#ifndef SKYFIT_FIT_CANDIDATE_FITTED_H
#define SKYFIT_FIT_CANDIDATE_FITTED_H

#include "fit/candidate_registry.h"
#include "fit/fit_sky_elevation.h"
#include "models/hosek_sky_model.h"

/* Training inside `skyfit build` (fit/candidate_mlp.c); `skyfit fit mlp-*`
 * trains longer by default. Overridden by sf_candidate_inputs. */
#define SF_BUILD_MLP_TRANSMITTANCE_EPOCHS 50
#define SF_BUILD_MLP_SCATTERING_EPOCHS 60
#define SF_BUILD_MLP_SCATTERING_SAMPLES 0L   /* every grid point in the domain */
/* The build's transmittance network trains on T^(1/4) (fit/target_root.h):
 * over build seeds 1-12 its max abs error over the domain 0.0095-0.0169
 * against 0.0151-0.1526 on T, its RMSE there 0.00050-0.00078 against
 * 0.00040-0.00102 (README). */
#define SF_BUILD_MLP_TRANSMITTANCE_TARGET_ROOT 4
/* Networks per quantity at most: while no model meets the scene's budget,
 * the build trains the seed's next restart (fit/build_pipeline.h). */
#define SF_BUILD_MLP_RESTARTS 3
/* A restart's error differs from the first network's by the spread over
 * seeds, which is bounded: over build seeds 1-12 the networks' budget
 * metrics spanned 1.6x (transmittance RMSE 0.00050-0.00078; 2.6x,
 * 0.00040-0.00102, trained on T itself) and 1.5x (sky relative RMSE
 * 0.042-0.064). Where the best network misses the budget by
 * more than this, the build's default trains no restart; an explicit
 * --mlp-restarts N does (fit/build_pipeline.c). */
#define SF_BUILD_RESTART_MAX_MISS 3.0

/* 1 if the build made the sky-radiance tables with a single-scattering
 * table to fit (fit/candidate_registry.c); else 0 and why, for the sky
 * factories' applies: an atmosphere whose constituents only absorb has a
 * black sky, and saying "the tables were not made" sent its user looking
 * for a missing option. */
int sf_candidate_sky_tables_ready(const sf_candidate_inputs *in, char *why, size_t why_len);

/* Sigmoid-polynomial transmittance (SPEC §7.1): fit/fit_sigmoid.h. */
int sf_candidate_applies_sigmoid(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_sigmoid(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);

/* Our fitted Hosek and Preetham/Perez skies (SPEC §7.2): ground viewer, sun
 * up; fit/fit_sky_elevation.h (fit/candidate_sky_form.c). */
int sf_candidate_applies_hosek(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_hosek(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);
int sf_candidate_applies_preetham(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_preetham(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);
/* The options of our ground-level sky fits for the scene of in (the
 * scene's sun range above the horizon, the view grid, --quick's coarser
 * one) and the box they are valid on (ground viewer, sun in that range). */
void sf_candidate_sky_options(const sf_candidate_inputs *in, sf_sky_form form, sf_sky_elevation_options *o,
                              sf_scene_domain *valid);

/* An elevation sky model (fitted, or the published Hosek's baked at one
 * turbidity) as a sky-radiance candidate valid on valid: the evaluation
 * of its emitted function in double and, for the cost, in float32, and
 * its emitter (codegen/emit_sky.h, functions skyfit_<form>_sky_radiance).
 * The candidate holds a copy of m. */
int sf_candidate_of_sky_model(const sf_elevation_sky_model *m, const sf_scene_domain *valid, sf_candidate_role role,
                              const char *name, const char *label, const char *description, sf_candidate *out,
                              sf_error *err);

/* The published Hosek 2012 and Preetham 1999 skies as baselines, at their
 * best-fitting turbidity and factors (fit/candidate_published_sky.c). */
int sf_candidate_applies_hosek_published(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_hosek_published(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);
int sf_candidate_applies_preetham_published(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_preetham_published(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);

/* The neural sky (SPEC §7.4-7.5): fit/train.h on fit/dataset_sky.h
 * (fit/candidate_mlp.c). */
int sf_candidate_applies_mlp_transmittance(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_mlp_transmittance(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);
int sf_candidate_applies_mlp_scattering(const sf_candidate_inputs *in, char *why, size_t why_len);
int sf_candidate_make_mlp_scattering(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);

/* Both networks in one emitted file: their functions share the prefix
 * skyfit_mlp_, and the scattering network's segment function (eq. 44)
 * needs the transmittance network. emit_model of each MLP candidate is its
 * sf_mlp_sky. */
struct sf_code_writer;
typedef struct sf_mlp_emit_pair {
  const void *transmittance, *scattering;   /* const sf_mlp_sky * */
} sf_mlp_emit_pair;
void sf_candidate_emit_mlp_pair(struct sf_code_writer *w, const void *pair);

#endif
