/* Every model `skyfit build` tries for a scene (SPEC §5 "fits every model
 * that is valid there"), as a table of factories. A fitted model plugs in
 * with one line in fit/candidate_registry.c's table and one factory
 * function (its own file, e.g. fit/candidate_sigmoid.c):
 *
 *   int sf_candidate_make_<model>(const sf_candidate_inputs *in,
 *                                 sf_candidate *out, sf_error *err);
 *
 * which calls the model's library fit function (never the CLI) on the
 * scene's domain, may write its weights file into in->work_dir, and fills
 * *out (fit/candidate.h): name, label, description, counts, the valid
 * domain, eval (double) and eval_f32 (float32 batch, what the cost is
 * measured on), ctx and free_ctx. `applies` says whether the model is
 * valid for the scene at all (e.g. Hosek: ground viewers, sun up) and why
 * not. SF_ERR_INPUT from make is reported and the model skipped; other
 * errors stop the build. */
#ifndef SKYFIT_FIT_CANDIDATE_REGISTRY_H
#define SKYFIT_FIT_CANDIDATE_REGISTRY_H

#include <stddef.h>
#include <stdint.h>

#include "data/precompute_options.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/candidate.h"
#include "util/error.h"

typedef struct sf_candidate_inputs {
  const sf_scene *scene;
  sf_scene_domain domain;
  const sf_atmosphere *atm;          /* &scene->atmosphere */
  const sf_table_set *tables;
  const sf_sky_tables *sky;
  const char *work_dir;              /* where fitters may write weights files (exists) */
  const char *cache_dir;             /* the build's cache (fit/candidate_cache.h); NULL: none */
  int orders;                        /* scattering orders of the tables */
  uint64_t seed;
  int restart;                       /* seeded fits: which restart of the seed (0: the first; a
                                        later one after the first missed the budget) */
  int quick;                         /* smaller fits (tests) */
  int mlp_transmittance_epochs;      /* 0: the build's default (fit/candidate_fitted.h) */
  int mlp_scattering_epochs;         /* 0: the build's default */
  long mlp_scattering_samples;       /* training samples kept (0: the default; < 0: all) */
  int mlp_scattering_normalise;      /* 1: the sky network brightness-normalised (fit/output_norm.h) */
  double mlp_scattering_normalise_cap;   /* its brightness's cap below the brightest (>= 0); INFINITY: none */
  double mlp_scattering_loss_floor;  /* 0: the sky network trains on MSE; > 0: on the relative loss of
                                        that floor (sf_train_options.loss_floor) */
  sf_precompute_options run;         /* threads, progress */
  const char *exclude;               /* comma-separated names left out (sf_candidate_exclude_check); NULL: none */
  void (*note)(void *ctx, const char *message);   /* messages for the user; may be NULL */
  void *note_ctx;
} sf_candidate_inputs;

typedef struct sf_candidate_factory {
  const char *name;
  sf_candidate_quantity quantity;
  /* 1 if the model applies to in->scene; else 0 and a reason in why. */
  int (*applies)(const sf_candidate_inputs *in, char *why, size_t why_len);
  int (*make)(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err);
  /* 1: a seeded fit (a network), whose restart in->restart > 0 is another
   * fit of the same data, named "<name>-<restart + 1>". */
  int restartable;
} sf_candidate_factory;

int sf_candidate_factories(const sf_candidate_factory **out);

/* 1 when name[0..len) names a restartable factory's model (a network) or
 * one of its restarts, "<name>-<n>" (n = 2, 3, ...: no sign, no leading
 * zero); else 0. */
int sf_candidate_network_name(const char *name, size_t len);

/* `skyfit build --exclude LIST`: the comma-separated candidate names left
 * out of a build (not made, measured or selected): a fitted model's (a
 * network's restarts with it) or an analytic baseline's, not the
 * references, the table lookups or naive16, the cost unit. 0, or -1 with
 * why saying which name is not one. */
int sf_candidate_exclude_check(const char *list, char *why, size_t why_len);
/* 1 when name, or the network it is a restart of, is in the list. */
int sf_candidate_excluded(const char *list, const char *name);

/* Called for each model skipped or failed, with a sentence. */
typedef void (*sf_candidate_note_fn)(void *ctx, const char *message);

/* The references (transmittance: exact; sky radiance: tables — only if
 * the scene asks for sky radiance), the naive16 raymarch (always: it is the
 * cost unit), the transmittance table lookup and the other analytic
 * baselines (if the scene asks for transmittance), then every registered
 * factory of a quantity the scene asks for that applies; those in->exclude
 * names are left out, each said once. */
int sf_candidates_make_all(const sf_candidate_inputs *in, sf_candidate_list *list, sf_candidate_note_fn note,
                           void *note_ctx, sf_error *err);

/* Restart in->restart (> 0) of every restartable factory of quantity q
 * that applies, added to list; *n_added counts them. A fit that fails on
 * its input is noted and skipped, as in sf_candidates_make_all. */
int sf_candidates_make_restart(const sf_candidate_inputs *in, sf_candidate_quantity q, sf_candidate_list *list,
                               int *n_added, sf_candidate_note_fn note, void *note_ctx, sf_error *err);

#endif
