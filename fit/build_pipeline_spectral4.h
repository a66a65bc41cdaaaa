/* The colour stage of `skyfit build` for a scene with "color": "spectral4"
 * (SPEC §5, §7.3): the 4 wavelengths and weights of seed 003 §5.4 fitted
 * with sf_spectral4_run (fit/spectral4_run.h: the spectral reference of the
 * scene's atmosphere, grid search + Nelder-Mead), cached as its weights file
 * in CACHE/fits (fit/candidate_cache.h; the spectral tables in CACHE
 * itself), copied to WORK/spectral4.json, and summarised for the report. */
#ifndef SKYFIT_FIT_BUILD_PIPELINE_SPECTRAL4_H
#define SKYFIT_FIT_BUILD_PIPELINE_SPECTRAL4_H

#include "codegen/report.h"
#include "data/precompute_options.h"
#include "models/scene_file.h"
#include "util/error.h"

typedef struct sf_build_spectral4_options {
  const char *cache_dir, *work_dir;
  int quick;                           /* small tables and grids (tests) */
  sf_precompute_options run;
  void (*note)(void *ctx, const char *message);
  void *note_ctx;
} sf_build_spectral4_options;

int sf_build_spectral4(const sf_scene *scene, const sf_build_spectral4_options *o, sf_report_spectral4 *out,
                       sf_error *err);

/* What the fit needs of the scene's atmosphere and sun range
 * (sf_spectral4_check_scene), checked before the build's tables: SF_OK for
 * a scene that is not spectral4; else SF_ERR_INPUT naming the atmosphere
 * file (an atmosphere whose sky without aerosols is black had failed
 * after the tables, exit 1). */
int sf_build_spectral4_check(const sf_scene *scene, sf_error *err);

#endif
