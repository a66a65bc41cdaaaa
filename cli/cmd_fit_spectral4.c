/* skyfit fit spectral4: the 4-wavelength spectral weights (SPEC §7.3, seed
 * 003 §5.4) for a scene, with the side-by-side colour error of the fit,
 * plain RGB at 680/550/440 nm and 4 uniformly spaced wavelengths. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "cli/atmosphere_warnings.h"
#include "cli/cache_limit_option.h"
#include "cli/fit_commands.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "fit/spectral4_run.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"
#include "models/weights_file.h"
#include "util/make_folders.h"

#define COMMAND "skyfit fit spectral4"

static void usage(FILE *out) {
  fprintf(out,
          "usage: skyfit fit spectral4 [--scene S.json | --atmosphere A.json] --out W.json [options]\n"
          "\n"
          "Finds 4 wavelengths and 4 weights (seed 003 eq. 5.12) whose 3x4 matrix turns the sky\n"
          "radiance at those wavelengths into the colour of the full spectrum (360-830 nm at 5 nm,\n"
          "CIE 1931 2°, linear sRGB): grid search, then NLopt Nelder-Mead on the mean squared error\n"
          "of eq. 5.13 over the scene's viewers, directions over the sphere and sun elevations\n"
          "-2..90° (crowded toward sunrise/sunset), with Rayleigh and ozone only. Prints and stores\n"
          "ΔE2000 after exposure (SPEC §12) of the fit, plain RGB at 680/550/440 nm and 4 uniform\n"
          "wavelengths, without and with the atmosphere's aerosols. An RGB atmosphere is turned\n"
          "into its spectral counterpart (models/spectral_atmosphere.h). The spectral reference\n"
          "tables are computed once and cached.\n"
          "\n"
          "options:\n"
          "  --out W.json            weights file to write (atomically); required\n"
          "  --scene S.json          scene (SPEC §5): atmosphere, viewers, view, sun range\n"
          "  --atmosphere A.json     atmosphere (with the built-in scene)\n"
          "  --cache DIR             reference-table cache (default: skyfit-cache beside W.json)\n"
          "  --cache-limit N         after a successful run, keep the cache under N MiB (default %lld),\n"
          "                          removing the tables unused the longest (never this run's); none:\n"
          "                          no limit\n"
          "  --resolution T,S        reference tables MUxH,HxMUxMU_SxNU (default 128x32,16x64x16x8)\n"
          "  --orders N              highest scattering order (default 64, stopping once the orders\n"
          "                          left would add < 5e-4 of the sky in every wavelength)\n"
          "  --threads N             worker threads (default: all cores); results do not depend on it\n"
          "  --quiet                 no progress, notes or summary\n"
          "  --help                  this text\n",
          SF_CACHE_LIMIT_DEFAULT_BYTES / (1024LL * 1024));
}

static void print_summary(const sf_spectral4_report *r, const char *out) {
  const sf_spectral4_params *p = &r->fit.best;
  printf("spectral4: wavelengths %.2f %.2f %.2f %.2f nm, weights %.3f %.3f %.3f %.3f nm\n", p->lambda_nm[0],
         p->lambda_nm[1], p->lambda_nm[2], p->lambda_nm[3], p->weight_nm[0], p->weight_nm[1], p->weight_nm[2],
         p->weight_nm[3]);
  printf("loss (eq. 5.13, linear sRGB MSE): grid %.4g -> Nelder-Mead %.4g (%d evaluations, %ld grid quadruples); "
         "plain RGB %.4g, uniform4 %.4g\n", r->fit.grid_loss, r->fit.loss, r->fit.evaluations,
         r->fit.grid_candidates, r->rgb_loss, r->uniform_loss);
  printf("ΔE2000 after exposure vs the full spectrum (%zu evaluation samples):\n", r->stats[0][0].n);
  printf("  %-18s %-31s %-31s\n", "method", "without aerosols", r->has_aerosols ? "with aerosols" : "with aerosols (none)");
  printf("  %-18s %9s %10s %10s %9s %10s %10s\n", "", "mean", "p99", "max", "mean", "p99", "max");
  for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m)
    printf("  %-18s %9.4f %10.4f %10.4f %9.4f %10.4f %10.4f\n", r->methods[m].name, r->stats[0][m].mean,
           r->stats[0][m].p99, r->stats[0][m].max, r->stats[1][m].mean, r->stats[1][m].p99, r->stats[1][m].max);
  printf("time: reference %.2f s (%s), fit %.3f s (grid %.3f s, Nelder-Mead %.3f s, %zu training samples), "
         "evaluation %.2f s\n", r->reference_seconds,
         r->tables_cached[0] && (!r->has_aerosols || r->tables_cached[1]) ? "cached" : "computed",
         r->fit_seconds, r->fit.grid_seconds, r->fit.nelder_mead_seconds, r->n_train, r->eval_seconds);
  printf("wrote %s\n", out);
}

/* The cache under limit_bytes after a successful run, this run's tables
 * kept: those it wrote or hit since run_start, less a second (file times
 * come from a coarser clock). Without it the default cache beside W.json
 * would keep every atmosphere's spectral tables ever fitted. A failure is
 * a warning: the weights are written. */
static void prune_cache(const char *cache_dir, long long limit_bytes, struct timespec run_start, int quiet) {
  struct timespec used_since = run_start;
  used_since.tv_sec -= 1;
  sf_cache_prune_result res;
  sf_error problem = {0};
  if (sf_cache_prune(cache_dir, limit_bytes, used_since, &res, &problem) != SF_OK)
    fprintf(stderr, "%s: warning: %s\n", COMMAND, problem.message);
  if (!quiet) sf_cli_print_cache_pruned(COMMAND, &res, limit_bytes);
}

int sf_cmd_fit_spectral4(int argc, char **argv) {
  const char *out = NULL, *scene_path = NULL, *atm_path = NULL, *cache = NULL;
  int quiet = 0;
  long long cache_limit_bytes = SF_CACHE_LIMIT_DEFAULT_BYTES;
  sf_spectral4_run_options opt;
  sf_spectral4_run_options_default(&opt);
  sf_error err = {0};
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *v = sf_cli_value_after(argc, argv, i), *missing = NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (sf_cli_valued(a, "--out", v, &missing)) {
      out = argv[++i];
    } else if (sf_cli_valued(a, "--scene", v, &missing)) {
      scene_path = argv[++i];
    } else if (sf_cli_valued(a, "--atmosphere", v, &missing)) {
      atm_path = argv[++i];
    } else if (sf_cli_valued(a, "--cache", v, &missing)) {
      cache = argv[++i];
    } else if (sf_cli_valued(a, "--cache-limit", v, &missing)) {
      if (sf_cli_parse_cache_limit(COMMAND, argv[++i], &cache_limit_bytes)) return 2;
    } else if (sf_cli_valued(a, "--resolution", v, &missing)) {
      if (sf_table_resolution_parse(argv[++i], &opt.res, &err) ||
          sf_table_resolution_check(&opt.res, SF_PARAM_BRUNETON, &err)) {
        fprintf(stderr, "%s: %s\n", COMMAND, err.message);
        return 2;
      }
    } else if (sf_cli_valued(a, "--orders", v, &missing)) {
      char *end = NULL;
      long n = strtol(argv[++i], &end, 10);
      if (!end || *end || n < 1 || n > 64) {
        fprintf(stderr, "%s: --orders: expected 1..64, got '%s'\n", COMMAND, argv[i]);
        return 2;
      }
      opt.orders = (int)n;
    } else if (sf_cli_valued(a, "--threads", v, &missing)) {
      char *end = NULL;
      long n = strtol(argv[++i], &end, 10);
      if (!end || *end || n < 1 || n > 1024) {
        fprintf(stderr, "%s: --threads: expected 1..1024, got '%s'\n", COMMAND, argv[i]);
        return 2;
      }
      opt.n_threads = (int)n;
    } else {
      return sf_cli_bad_option(COMMAND, a, missing);
    }
  }
  if (!out) {
    fprintf(stderr, "%s: --out W.json is required; see --help\n", COMMAND);
    return 2;
  }
  if (scene_path && atm_path) {
    fprintf(stderr, "%s: --atmosphere and --scene: give one (the scene names its atmosphere)\n", COMMAND);
    return 2;
  }
  char cache_dir[4096];
  if (cache) {
    snprintf(cache_dir, sizeof cache_dir, "%s", cache);
  } else {
    const char *slash = strrchr(out, '/');
    if (slash) snprintf(cache_dir, sizeof cache_dir, "%.*s/skyfit-cache", (int)(slash - out), out);
    else snprintf(cache_dir, sizeof cache_dir, "skyfit-cache");
  }
  sf_scene *scene = malloc(sizeof *scene);
  sf_spectral4_report *rep = malloc(sizeof *rep);
  int status = (scene && rep) ? SF_OK : sf_fail(&err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) {
    if (scene_path) status = sf_scene_load_file(scene_path, scene, &err);
    else {
      sf_scene_default(scene);
      if (atm_path) status = sf_atmosphere_load_file(atm_path, &scene->atmosphere, &err);
    }
    if (status == SF_OK)
      sf_cli_warn_atmosphere_units(COMMAND, atm_path ? atm_path : scene->atmosphere_path, &scene->atmosphere);
  }
  /* the inputs checked before the cache folder is made or any work done;
   * the message names the file they came from */
  if (status == SF_OK && (status = sf_spectral4_check_scene(scene, &opt, &err)) == SF_ERR_INPUT) {
    sf_error named = {0};
    sf_fail(&named, SF_ERR_INPUT, "%s: %s", scene_path ? scene_path : atm_path ? atm_path : "the built-in scene",
            err.message);
    err = named;
  }
  /* before the default cache folder beside W.json is made (it had made a
   * missing --out folder, the run then writing its weights there) */
  if (status == SF_OK) {
    const char *inputs[3];
    sf_cli_scene_files(scene_path, atm_path, scene, inputs);
    status = sf_cli_output_problem("--out", out, inputs, 3, &err);
  }
  if (status == SF_OK) status = sf_make_folders(cache_dir, "--cache", &err);
  /* a signal leaves no temporary of the weights or a cached table
   * (cli/interrupt_cleanup.h) */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_file(&outputs, out);
  sf_cli_outputs_add_folder(&outputs, cache_dir);
  if (status == SF_OK) sf_cli_supervise_outputs(&outputs);
  opt.cache_dir = cache_dir;
  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !quiet);
  bar.note_prefix = COMMAND;
  opt.progress = sf_progress_bar_update;
  opt.progress_ctx = &bar;
  if (!quiet) {
    opt.note = sf_progress_bar_note;
    opt.note_ctx = &bar;
  }
  cJSON *doc = NULL;
  struct timespec run_start;
  clock_gettime(CLOCK_REALTIME, &run_start);
  if (status == SF_OK) status = sf_spectral4_run(scene, &opt, rep, &doc, &err);
  sf_progress_bar_finish(&bar);
  if (status == SF_OK) status = sf_weights_write(doc, out, &err);
  cJSON_Delete(doc);
  if (status == SF_OK && !quiet) print_summary(rep, out);
  if (status == SF_OK) prune_cache(cache_dir, cache_limit_bytes, run_start, quiet);
  if (status != SF_OK) fprintf(stderr, "%s: %s\n", COMMAND, err.message);
  free(scene);
  free(rep);
  return status;
}
