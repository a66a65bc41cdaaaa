/* `skyfit build` as a library function (SPEC §5, §11): scene -> reference
 * tables (cached in OUT/cache) -> every applicable candidate
 * (fit/candidate_registry.h) -> metrics and views (codegen/report.h) ->
 * selection per quantity (while none meets its budget, the next restart of
 * the seed's network for it, measured and selected again; by default not
 * where the networks miss it by more than SF_BUILD_RESTART_MAX_MISS) -> GLSL
 * and C for the selection
 * (codegen/codegen_file.h) -> report.html, report.md, metrics.json ->
 * OUT/cache pruned to its size limit (util/cache_prune.h) -> earlier runs'
 * weights files of models this run did not fit removed from OUT/weights
 * (fit/build_stale_weights.h).
 * An impossible budget is not an error: the best available model is
 * emitted and the report says it misses the budget. */
#ifndef SKYFIT_FIT_BUILD_PIPELINE_H
#define SKYFIT_FIT_BUILD_PIPELINE_H

#include "codegen/report.h"
#include "data/table_set.h"
#include "fit/candidate_registry.h"
#include "util/cache_prune.h"

typedef struct sf_build_options {
  const char *out_dir;
  sf_table_set_options tables;       /* cache_dir is set to OUT/cache */
  sf_report_options report;
  int quick;                         /* smaller fits */
  int mlp_transmittance_epochs;      /* 0: the build's defaults (fit/candidate_fitted.h) */
  int mlp_scattering_epochs;
  long mlp_scattering_samples;       /* 0: default; < 0: every grid point */
  int mlp_scattering_normalise;      /* 1 (default): the sky network brightness-normalised (fit/output_norm.h) */
  double mlp_scattering_normalise_cap;   /* its brightness's cap below the brightest (default
                                            SF_OUTPUT_NORM_CAP_BELOW); INFINITY: none */
  double mlp_scattering_loss_floor;  /* 0: the sky network trains on MSE; > 0: on the relative loss
                                        of that floor (sf_train_options.loss_floor) */
  int mlp_restarts;                  /* networks trained per quantity at most: while no model meets
                                        the budget, the seed's next restart (0: SF_BUILD_MLP_RESTARTS,
                                        1 with quick, and none where the networks miss the budget by
                                        more than SF_BUILD_RESTART_MAX_MISS; > 0: whatever the miss) */
  const char *exclude;               /* candidates left out (fit/candidate_registry.h
                                        sf_candidate_exclude_check); NULL: none */
  int emit;                          /* write the headers (default 1) */
  const char *header_c, *header_glsl;   /* where to write them, over the scene's outputs
                                           (NULL: the scene's, or OUT/sky.h, OUT/sky.glsl) */
  const char *prefix;                /* of the emitted names (NULL: skyfit; codegen/codegen_file.h) */
  long long cache_limit_bytes;       /* OUT/cache kept under it after a successful run,
                                        least recently used entries removed first
                                        (util/cache_prune.h); < 0: no limit */
  sf_candidate_note_fn note;         /* messages for the user; may be NULL */
  void *note_ctx;
} sf_build_options;

void sf_build_options_default(sf_build_options *o);

typedef struct sf_build_result {
  int tables_from_cache, tables_total;
  double seconds_tables, seconds_fit, seconds_report, seconds_total;   /* wall clock */
  double cpu_seconds_tables, cpu_seconds_fit, cpu_seconds_report;      /* process CPU, all threads */
  char report_html[SF_REPORT_PATH_LEN + 32];
  char chosen[SF_CANDIDATE_N_QUANTITIES][48];
  int meets_budget[SF_CANDIDATE_N_QUANTITIES];
  int asked[SF_CANDIDATE_N_QUANTITIES];
  char header_c[SF_REPORT_PATH_LEN], header_glsl[SF_REPORT_PATH_LEN];
  sf_cache_prune_result cache;       /* OUT/cache's entries and what the limit removed */
  char cache_problem[1024];          /* an entry that could not be removed (the build still succeeds) */
  int weights_removed;               /* OUT/weights files of models this run did not fit, removed
                                        (fit/build_stale_weights.h) */
  char weights_problem[1024];        /* one that could not be removed (the build still succeeds) */
  int views_removed;                 /* OUT/views pictures an earlier run left that this report does not name
                                        (codegen/report_views.h) */
  char views_problem[1024];          /* one that could not be removed (the build still succeeds) */
} sf_build_result;

/* The table options a build uses for a scene: base with cache_dir and the
 * scene's domain (SPEC §5: the scattering tables cover it alone; a scene
 * without sky radiance gets the transmittance table only). Whoever reads a
 * build's OUT/cache passes the same base to find the same tables. */
void sf_build_table_options(const sf_scene *scene, const sf_scene_domain *domain,
                            const sf_table_set_options *base, const char *cache_dir,
                            sf_table_set_options *out);

/* Where the build writes its headers: o->header_c / o->header_glsl, else
 * the scene's outputs, else OUT/sky.h and OUT/sky.glsl. */
int sf_build_header_paths(const sf_scene *scene, const sf_build_options *o, char *c_path, char *glsl_path, size_t n,
                          sf_error *err);

int sf_build_run(const sf_scene *scene, const sf_build_options *o, sf_build_result *res, sf_error *err);

#endif
