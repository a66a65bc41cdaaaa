/* A candidate model of one quantity, as `skyfit build` and `skyfit report`
 * see it (SPEC §5, §12): something that maps the inputs of the quantity to a
 * value per colour channel, with a name, a parameter count, the bytes of
 * constants its emitted code holds, a double-precision evaluation (for the
 * error metrics and the standard views) and, where one exists, a float32
 * batch evaluation (for the cost in ns per evaluation).
 *
 * Quantities and their inputs (SPEC §3, §11 "eval"):
 *   SF_CANDIDATE_TRANSMITTANCE  in = {h_km, mu}: transmittance along the ray
 *       from a viewer at altitude h_km looking along mu until it hits the
 *       ground or leaves the atmosphere (a viewer above the top starts where
 *       the ray enters; 1 if it never does).
 *   SF_CANDIDATE_SKY_RADIANCE   in = {h_km, mu, mu_s, nu}: sky radiance along
 *       that ray (single scattering with the phase functions + multiple
 *       scattering, the atmosphere's sun irradiance, no direct sun, the
 *       ground seen at the end of the ray not included), as
 *       data/sky_lookup.h defines it. h_km may exceed the top of the
 *       atmosphere (space views).
 * out has n_channels values. Both evaluations must be thread-safe (the
 * context is read only) and deterministic.
 *
 * How a fitted model plugs in (see fit/candidate_registry.h): its fitter
 * fills an sf_candidate (name, counts, valid domain, eval, eval_f32_batch,
 * ctx, free_ctx) from its fitted parameters; the registry lists one factory
 * per model. Nothing else in the pipeline changes. */
#ifndef SKYFIT_FIT_CANDIDATE_H
#define SKYFIT_FIT_CANDIDATE_H

#include <stddef.h>

#include "models/scene_file.h"

struct sf_code_writer;

typedef enum sf_candidate_quantity {
  SF_CANDIDATE_TRANSMITTANCE = 0,
  SF_CANDIDATE_SKY_RADIANCE = 1
} sf_candidate_quantity;
#define SF_CANDIDATE_N_QUANTITIES 2

typedef enum sf_candidate_role {
  SF_ROLE_REFERENCE = 0,   /* the truth the others are measured against; never selected */
  SF_ROLE_LOOKUP,          /* a table lookup of the reference (needs the tables at run time); never selected */
  SF_ROLE_BASELINE,        /* analytic, from the atmosphere alone (SPEC §7.6) */
  SF_ROLE_FITTED           /* fitted to the reference tables (SPEC §7.1-7.5) */
} sf_candidate_role;

/* Number of inputs of a quantity: 2 or 4. */
int sf_candidate_n_inputs(sf_candidate_quantity q);
/* "transmittance", "sky_radiance". */
const char *sf_candidate_quantity_name(sf_candidate_quantity q);
/* "reference", "lookup", "baseline", "fitted". */
const char *sf_candidate_role_name(sf_candidate_role r);

typedef void (*sf_candidate_eval_fn)(const void *ctx, const double *in, double *out);
/* n points: in holds n * n_inputs floats, out n * n_channels floats. */
typedef void (*sf_candidate_eval_f32_fn)(const void *ctx, size_t n, const float *in, float *out);

typedef struct sf_candidate {
  char name[48];           /* short id, [a-z0-9_-]: file names, JSON keys ("naive16") */
  char label[96];          /* for people ("Naive raymarch, 16 steps") */
  char description[400];   /* one or two sentences: what it is, where it comes from */
  sf_candidate_quantity quantity;
  sf_candidate_role role;
  int n_channels;
  long n_params;           /* fitted or stored numbers (0 for a formula of the atmosphere alone) */
  long constant_bytes;     /* bytes of constants the emitted code holds (float32) */
  /* Where the model is meant to be used (e.g. Hosek: ground viewer, sun
   * up); the standard views outside it are not rendered for it. */
  sf_scene_domain valid;
  /* Code generation (codegen/codegen_file.h): the function prefix
   * (skyfit_<emit_name>_<quantity>) and the emitter with its model; emit
   * NULL when the model cannot be emitted. */
  char emit_name[48];
  void (*emit)(struct sf_code_writer *w, const void *model);
  const void *emit_model;
  /* The emitted sky function is skyfit_<emit_name>_sky_radiance(mu, mu_s,
   * nu), a viewer on the ground (Preetham, Hosek); 0: it takes h_km first
   * (the network). A property of the code, not of the valid domain: a
   * network fitted to a ground-only scene still takes h_km. */
  int emit_ground_viewer;
  /* Weights file written by its fitter ("" for none). */
  char weights_path[4096];
  sf_candidate_eval_fn eval;             /* required */
  sf_candidate_eval_f32_fn eval_f32;     /* NULL: timed through eval, in double */
  /* The model's segment, as its emitted skyfit_<emit_name>_<quantity>_segment
   * computes it (seed 000 eq. 43 for transmittance, eq. 44 for sky
   * radiance), in double as eval: in = the quantity's inputs, then t_km,
   * the distance from the viewer where the segment ends (a viewer above the
   * top counts it from itself, as the emitted code does); the report's
   * segment errors (codegen/report.h). NULL: whole rays only. */
  sf_candidate_eval_fn eval_segment;
  /* A sky model whose segment takes a transmittance model's (eq. 44: the
   * sky network's takes the transmittance network's): that transmittance
   * candidate's ctx second; segment_transmittance is its emit_name (the
   * report pairs it with the fitted transmittance of that name that the
   * build emits beside it: the selected one, else the one of smallest
   * whole-ray RMSE; sf_report_transmittance_partner in codegen/report.h).
   * NULL: none (eval_segment, if any, stands alone). */
  void (*eval_segment_paired)(const void *ctx, const void *transmittance_ctx, const double *in, double *out);
  char segment_transmittance[48];
  void *ctx;
  void (*free_ctx)(void *ctx);           /* NULL: ctx is not owned */
} sf_candidate;

/* Zeroes c and sets the valid domain to everything (any h, mu, mu_s). */
void sf_candidate_init(sf_candidate *c, sf_candidate_quantity q, sf_candidate_role role,
                       const char *name, const char *label);
/* Releases ctx (if owned) and zeroes c. */
void sf_candidate_free(sf_candidate *c);

/* 1 when (h_km, mu_s) of a viewer lies in the candidate's valid domain
 * (h above the top of the atmosphere counts as the top). */
int sf_candidate_valid_for(const sf_candidate *c, double h_km_clamped, double mu_s);

/* A growable list of candidates (owned). */
typedef struct sf_candidate_list {
  sf_candidate *items;
  int count, capacity;
} sf_candidate_list;

void sf_candidate_list_init(sf_candidate_list *l);
/* Moves *c into the list (c is zeroed). Returns 0, or -1 out of memory (c freed). */
int sf_candidate_list_add(sf_candidate_list *l, sf_candidate *c);
void sf_candidate_list_free(sf_candidate_list *l);
/* Index of the candidate called name for quantity q, or -1. */
int sf_candidate_list_find(const sf_candidate_list *l, sf_candidate_quantity q, const char *name);

#endif
