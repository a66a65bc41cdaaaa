/* The built-in scene, and its reference tables read from the cache of a
 * `skyfit build` of it in out_dir (with the build's own table options, so
 * its cache entries are found; computed and cached there if missing): for
 * the benches that measure a default build (bench_views_scale,
 * bench_views_calibration). */
#ifndef SKYFIT_BENCH_BUILD_TABLES_H
#define SKYFIT_BENCH_BUILD_TABLES_H

#include <stdio.h>
#include <stdlib.h>

#include "data/table_set.h"
#include "fit/build_pipeline.h"
#include "models/scene_file.h"
#include "util/error.h"

/* The built-in scene and its domain; NULL, with err set, on failure. The
 * caller frees the scene. */
static sf_scene *bench_default_scene(sf_scene_domain *domain, sf_error *err) {
  sf_scene *scene = malloc(sizeof *scene);   /* large: holds an atmosphere */
  if (!scene) {
    sf_fail(err, SF_ERR_INTERNAL, "out of memory");
    return NULL;
  }
  sf_scene_default(scene);
  if (sf_scene_get_domain(scene, domain, err)) {
    free(scene);
    return NULL;
  }
  return scene;
}

/* The tables of the build in out_dir over domain. */
static int bench_build_tables(const char *out_dir, const sf_scene *scene, const sf_scene_domain *domain,
                              sf_table_set *set, sf_error *err) {
  char cache[4096];
  snprintf(cache, sizeof cache, "%s/cache", out_dir);
  sf_build_options build;
  sf_build_options_default(&build);
  sf_table_set_options topt;
  sf_build_table_options(scene, domain, &build.tables, cache, &topt);
  return sf_table_set_make(set, &scene->atmosphere, &topt, err);
}

#endif
