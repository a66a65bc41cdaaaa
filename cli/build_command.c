#include "cli/build_command.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/atmosphere_warnings.h"
#include "cli/cache_limit_option.h"
#include "cli/cmd_fit_mlp_options.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "cli/size_pair_option.h"
#include "fit/build_pipeline.h"
#include "fit/build_staging.h"
#include "fit/candidate_fitted.h"
#include "fit/candidate_registry.h"
#include "fit/output_norm.h"
#include "codegen/codegen_file.h"
#include "models/scene_file.h"
#include "util/atomic_file.h"
#include "util/cache_prune.h"

#define MIB (1024LL * 1024)

#define QUICK_TIMING_POINTS 100000

static void usage(FILE *out, const char *command, int emit) {
  fprintf(out,
          "usage: %s [SCENE.json] [--out DIR] [options]\n"
          "\n"
          "%s"
          "Samples the reference tables for the scene's atmosphere (cached in DIR/cache), %s"
          "measures every model against the reference over the scene's domain (RMSE, max abs, mean\n"
          "relative error; cost in ns per evaluation and as a ratio to the 16-step naive raymarch),\n"
          "renders the standard views of seed 000 §11.4 and writes DIR/report.html, report.md,\n"
          "metrics.json, views/*.png, views/*-error.exr and plots/*.svg. Without SCENE.json: the built-in\n"
          "atmosphere and scene (ground to space, sun -10..90 deg, RGB).\n"
          "\n"
          "options:\n"
          "  --out DIR            output folder (default skyfit-out), created if missing\n"
          "%s"
          "  --resolution T,S     table sample counts (default 256x64,32x128x32x8)\n"
          "  --views WxH          size of the standard views (default 192x108)\n"
          "  --no-views           skip the standard views\n"
          "  --samples N          in-domain samples for the errors (default 20000)\n"
          "  --timing-points N    inputs per timing run (default 1000000)\n"
          "  --repetitions N      timing runs, the median is reported (default 3)\n"
          "  --seed N             seed of the samples and fits (default 1)\n"
          "  --mlp-epochs T,S     epochs of the transmittance and scattering networks (default %d,%d;\n"
          "                       `skyfit fit mlp-*` trains longer)\n"
          "  --mlp-samples N      training samples of each scattering network (default 0: every grid\n"
          "                       point in the domain)\n"
          "  --mlp-normalise N    brightness (default) or none: the sky network learns its targets\n"
          "                       divided by a fitted, capped brightness of (altitude, sun elevation):\n"
          "                       the dawn views several times better (README)\n"
          "  --mlp-normalise-cap C  that brightness capped C (natural log) below the brightest\n"
          "                       situation's (default %g), or none\n"
          "  --mlp-loss-floor F   0 (default): the sky network trains on the MSE of its targets; F in\n"
          "                       1e-12..1: on their relative error, each residual over |target| + F\n"
          "                       x the largest target (dark skies weigh more; README)\n"
          "  --mlp-restarts N     networks trained per quantity at most (default %d; 1 with --quick):\n"
          "                       while no model meets the budget, the seed's next restart is trained\n"
          "                       (named mlp-*-2, -3, ...), measured and the selection made again;\n"
          "                       by default only while the networks miss it by %gx at most (the\n"
          "                       seeds' spread), given explicitly whatever the miss\n"
          "  --exclude LIST       models left out, comma-separated: not fitted, measured or selected\n"
          "                       (e.g. flat-sky,naive-sky: the single-scattering skies; hosek to skip\n"
          "                       its fit); any fitted model or analytic baseline but naive16\n"
          "  --quick              smaller fits and %d timing points unless given (for tests)\n"
          "  --threads N          worker threads (default: all cores)\n"
          "  --cache-limit N      after a successful run, keep DIR/cache under N MiB (default %lld),\n"
          "                       removing the tables, fits and timings unused the longest (never\n"
          "                       this run's); none: no limit\n"
          "  --quiet              no progress or notes\n"
          "  --help               this text\n",
          command,
          emit ? "The whole pipeline (SPEC §5, §11): sample, fit, select, emit, report.\n"
               : "The report stage on its own (SPEC §12): like `skyfit build` without emitting code.\n",
          emit ? "fits\nevery model valid in the scene's domain, selects per quantity the cheapest that meets\n"
                 "the budget among those it can emit, emits GLSL and C for it (to --header-c F and\n"
                 "--header-glsl F, else the scene's outputs, else DIR/sky.h and DIR/sky.glsl; besides\n"
                 "the models' own functions, skyfit_transmittance(h_km, mu) and skyfit_sky_radiance(h_km,\n"
                 "mu, mu_s, nu) call the selected ones, so a renderer's code outlives a new selection;\n"
                 "--prefix P names them P_... instead, for two scenes' headers in one program),\n"
               : "builds\nthe candidates,\n",
          emit ? "  --header-c F         the C header (default: the scene's outputs.c, else DIR/sky.h)\n"
                 "  --header-glsl F      the GLSL file (default: the scene's outputs.glsl, else DIR/sky.glsl)\n"
                 "  --prefix P           emitted names begin with P_ instead of skyfit_ (types and macros too)\n"
               : "",
          SF_BUILD_MLP_TRANSMITTANCE_EPOCHS, SF_BUILD_MLP_SCATTERING_EPOCHS, SF_OUTPUT_NORM_CAP_BELOW,
          SF_BUILD_MLP_RESTARTS, SF_BUILD_RESTART_MAX_MISS, QUICK_TIMING_POINTS, SF_CACHE_LIMIT_DEFAULT_BYTES / MIB);
}

static void print_note(void *ctx, const char *message) {
  sf_progress_bar *bar = ctx;
  if (!bar) return;
  sf_progress_bar_finish(bar);
  fprintf(stderr, "%s\n", message);
}

static int parse_count(const char *command, const char *opt, const char *text, long lo, long hi, long *out) {
  char *end;
  long v = strtol(text, &end, 10);
  if (*text == '\0' || *end != '\0' || v < lo || v > hi) {
    fprintf(stderr, "%s: %s: expected an integer in %ld..%ld, got '%s'\n", command, opt, lo, hi, text);
    return -1;
  }
  *out = v;
  return 0;
}

/* What header k (0: C, 1: GLSL) would overwrite: an input of the run, a
 * file the build publishes itself (fit/build_staging.h), the other header;
 * or the folder of the build's it would lie in, at any depth (OUT's
 * published folders, which a build replaces whole, and cache/: *in_folder
 * set to 1), or one of those folders itself (*in_folder 2). NULL if none;
 * own holds OUT's paths. */
static const char *header_clash_of(const char *const paths[2], int k, const char *const inputs[3],
                                   const char *out_dir, char own[][SF_REPORT_PATH_LEN + 64], int *in_folder) {
  *in_folder = 0;
  const char *clash = sf_cli_same_as_any(paths[k], inputs, 3);
  if (clash) return clash;
  const char *files[SF_BUILD_OUT_FILES], *folders[SF_BUILD_OUT_FOLDERS + 1];
  for (int i = 0; i < SF_BUILD_OUT_FILES; ++i) {
    snprintf(own[i], sizeof own[i], "%s/%s", out_dir, sf_build_out_files[i]);
    files[i] = own[i];
  }
  for (int i = 0; i <= SF_BUILD_OUT_FOLDERS; ++i) {
    char *path = own[SF_BUILD_OUT_FILES + i];
    snprintf(path, sizeof own[0], "%s/%s", out_dir, i < SF_BUILD_OUT_FOLDERS ? sf_build_out_folders[i] : "cache");
    folders[i] = path;
  }
  if ((clash = sf_cli_same_as_any(paths[k], files, SF_BUILD_OUT_FILES)) != NULL) return clash;
  if (k == 1 && sf_cli_same_file(paths[0], paths[1])) return "the C header";
  /* one of those folders itself (`--header-c OUT/views` had written the
   * header, then failed to publish the run with exit 2) */
  if ((clash = sf_cli_same_as_any(paths[k], folders, SF_BUILD_OUT_FOLDERS + 1)) != NULL) {
    *in_folder = 2;
    return clash;
  }
  clash = sf_cli_inside_any(paths[k], folders, SF_BUILD_OUT_FOLDERS + 1);
  *in_folder = clash != NULL;
  return clash;
}

/* The headers replace none of the run's inputs and none of the files the
 * build writes itself (SPEC §11: bad input exits 2 and writes nothing):
 * `--header-c scene.json` had overwritten the scene, a scene's outputs.c
 * naming its atmosphere file the atmosphere, and `--header-c
 * OUT/report.md` had lost the header under the report, each with exit 0.
 * Returns 0, or 2 with a message. */
static int header_clash(const char *command, const char *scene_path, const sf_scene *scene,
                        const sf_build_options *o) {
  char c_path[SF_REPORT_PATH_LEN], glsl_path[SF_REPORT_PATH_LEN];
  sf_error err = {0};
  if (sf_build_header_paths(scene, o, c_path, glsl_path, sizeof c_path, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return 2;
  }
  const char *paths[2] = {c_path, glsl_path};
  const char *inputs[3];
  sf_cli_scene_files(scene_path, NULL, scene, inputs);
  /* a path from the scene's outputs is named with the scene's file, as its
   * other keys are ("S.json: outputs.cpp: unknown key"); it had named the
   * key alone */
  char scene_key[2][SF_REPORT_PATH_LEN + 40];
  snprintf(scene_key[0], sizeof scene_key[0], "%s: the scene's outputs.c", scene_path ? scene_path : "(scene)");
  snprintf(scene_key[1], sizeof scene_key[1], "%s: the scene's outputs.glsl", scene_path ? scene_path : "(scene)");
  const char *option[2] = {"the C header", "the GLSL file"};
  if (scene->output_c[0]) option[0] = scene_key[0];
  if (o->header_c) option[0] = "--header-c";
  if (scene->output_glsl[0]) option[1] = scene_key[1];
  if (o->header_glsl) option[1] = "--header-glsl";
  for (int k = 0; k < 2; ++k) {
    char own[SF_BUILD_OUT_FILES + SF_BUILD_OUT_FOLDERS + 1][SF_REPORT_PATH_LEN + 64];
    int in_folder;
    const char *clash = header_clash_of(paths, k, inputs, o->out_dir, own, &in_folder);
    struct stat st;
    /* found here, before the work, naming the option (it had been found
     * after the fits, as ".: is a folder") */
    if (!clash && stat(paths[k], &st) == 0 && S_ISDIR(st.st_mode)) {
      fprintf(stderr, "%s: %s %s: is a folder; give the header's file path\n", command, option[k], paths[k]);
      return 2;
    }
    /* its folder must exist (OUT, which the build makes, aside): it had
     * been found after the work, the message naming neither option nor key */
    char folder[SF_REPORT_PATH_LEN];
    snprintf(folder, sizeof folder, "%s", paths[k]);
    char *slash = strrchr(folder, '/');
    if (!clash && slash) {
      slash[slash == folder] = '\0';
      if (!sf_cli_same_file(folder, o->out_dir) && !(stat(folder, &st) == 0 && S_ISDIR(st.st_mode))) {
        fprintf(stderr, "%s: %s %s: its folder %s does not exist\n", command, option[k], paths[k], folder);
        return 2;
      }
    }
    if (!clash) continue;
    if (in_folder == 2)
      fprintf(stderr, "%s: %s %s: is a folder the build makes itself (%s); give another path\n", command, option[k],
              paths[k], clash);
    else
      fprintf(stderr, "%s: %s %s: %s %s, which the build %s; give another path\n", command, option[k], paths[k],
              in_folder ? "lies in" : "is the same file as", clash, in_folder ? "writes itself" : "would overwrite");
    return 2;
  }
  return 0;
}

/* What an interrupted build leaves in OUT and beside its headers
 * (cli/interrupt_cleanup.h): its staging folder and its temporaries. */
typedef struct build_leftovers {
  const char *out_dir;
  char headers[2][SF_REPORT_PATH_LEN];   /* "" where none is written */
} build_leftovers;

static void remove_build_leftovers(void *ctx) {
  const build_leftovers *l = ctx;
  char path[SF_REPORT_PATH_LEN + 32];
  sf_build_staging_remove_stale(l->out_dir);
  sf_atomic_remove_stale_in(l->out_dir);
  for (int i = 0; i < SF_CACHE_FOLDERS; ++i) {
    const char *sub = sf_cache_folders[i].sub;
    snprintf(path, sizeof path, "%s/cache%s%s", l->out_dir, sub[0] ? "/" : "", sub);
    sf_atomic_remove_stale_in(path);
  }
  for (int k = 0; k < 2; ++k)
    if (l->headers[k][0]) sf_atomic_remove_stale(l->headers[k]);
}

int sf_cli_build_or_report(int argc, char **argv, int emit, const char *command) {
  sf_build_options o;
  sf_build_options_default(&o);
  o.emit = emit;
  o.out_dir = "skyfit-out";
  const char *scene_path = NULL;
  int quiet = 0, timing_points_given = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *v = sf_cli_value_after(argc, argv, i), *missing = NULL;
    long n;
    sf_error perr = {0};
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout, command, emit);
      return 0;
    } else if (!strcmp(a, "--quiet")) {
      quiet = 1;
    } else if (!strcmp(a, "--quick")) {
      o.quick = 1;
    } else if (!strcmp(a, "--no-views")) {
      o.report.render_views = 0;
    } else if (sf_cli_valued(a, "--out", v, &missing)) {
      o.out_dir = argv[++i];
    } else if (emit && sf_cli_valued(a, "--header-c", v, &missing)) {
      o.header_c = argv[++i];
    } else if (emit && sf_cli_valued(a, "--header-glsl", v, &missing)) {
      o.header_glsl = argv[++i];
    } else if (emit && sf_cli_valued(a, "--prefix", v, &missing)) {
      if (sf_codegen_prefix_check(argv[++i], &perr) != SF_OK) {
        fprintf(stderr, "%s: --prefix: %s\n", command, perr.message);
        return 2;
      }
      o.prefix = argv[i];
    } else if (sf_cli_valued(a, "--resolution", v, &missing)) {
      if (sf_table_resolution_parse(argv[++i], &o.tables.res, &perr) != SF_OK) {
        fprintf(stderr, "%s: %s\n", command, perr.message);
        return 2;
      }
    } else if (sf_cli_valued(a, "--views", v, &missing)) {
      int w, h;
      ++i;
      if (sf_cli_parse_size_pair(v, 1, 8192, &w, &h)) {
        fprintf(stderr, "%s: --views: expected WxH (1..8192 each), got '%s'\n", command, v);
        return 2;
      }
      o.report.view_width = w;
      o.report.view_height = h;
    } else if (sf_cli_valued(a, "--samples", v, &missing)) {
      if (parse_count(command, a, argv[++i], 1, 100000000, &n)) return 2;
      o.report.domain_samples = (size_t)n;
    } else if (sf_cli_valued(a, "--timing-points", v, &missing)) {
      if (parse_count(command, a, argv[++i], 1, 100000000, &n)) return 2;
      o.report.timing_points = (size_t)n;
      timing_points_given = 1;
    } else if (sf_cli_valued(a, "--repetitions", v, &missing)) {
      if (parse_count(command, a, argv[++i], 1, 1000, &n)) return 2;
      o.report.timing_repetitions = (int)n;
    } else if (sf_cli_valued(a, "--seed", v, &missing)) {
      if (parse_count(command, a, argv[++i], 0, 2147483647L, &n)) return 2;
      o.report.seed = (unsigned long long)n;
    } else if (sf_cli_valued(a, "--mlp-epochs", v, &missing)) {
      int t, sc;
      char extra;
      ++i;
      if (sscanf(v, "%d,%d%c", &t, &sc, &extra) != 2 || t < 1 || sc < 1 || t > 1000000 || sc > 1000000) {
        fprintf(stderr, "%s: --mlp-epochs: expected T,S (two whole numbers >= 1), got '%s'\n", command, v);
        return 2;
      }
      o.mlp_transmittance_epochs = t;
      o.mlp_scattering_epochs = sc;
    } else if (sf_cli_valued(a, "--mlp-samples", v, &missing)) {
      if (parse_count(command, a, argv[++i], 0, 1000000000L, &n)) return 2;
      o.mlp_scattering_samples = n == 0 ? -1 : n;
    } else if (sf_cli_valued(a, "--mlp-restarts", v, &missing)) {
      if (parse_count(command, a, argv[++i], 1, 100, &n)) return 2;
      o.mlp_restarts = (int)n;
    } else if (sf_cli_valued(a, "--mlp-normalise", v, &missing)) {
      ++i;
      if (strcmp(v, "none") != 0 && strcmp(v, "brightness") != 0) {
        fprintf(stderr, "%s: --mlp-normalise: expected none or brightness, got '%s'\n", command, v);
        return 2;
      }
      o.mlp_scattering_normalise = strcmp(v, "brightness") == 0;
    } else if (sf_cli_valued(a, "--mlp-normalise-cap", v, &missing)) {
      ++i;
      if (strcmp(v, "none") == 0)
        o.mlp_scattering_normalise_cap = INFINITY;
      else if (sf_mlp_cli_parse_double(v, 0.0, HUGE_VAL, &o.mlp_scattering_normalise_cap)) {
        fprintf(stderr, "%s: --mlp-normalise-cap: expected a number >= 0 or none, got '%s'\n", command, v);
        return 2;
      }
    } else if (sf_cli_valued(a, "--mlp-loss-floor", v, &missing)) {
      ++i;
      /* a floor of F x a target's largest must stay a number the relative
       * loss can divide by (fit/train.c gives 1e-300 at least) */
      if (sf_mlp_cli_parse_double(v, 0.0, 1.0, &o.mlp_scattering_loss_floor) ||
          (o.mlp_scattering_loss_floor > 0.0 && o.mlp_scattering_loss_floor < 1e-12)) {
        fprintf(stderr, "%s: --mlp-loss-floor: expected 0 or a number in 1e-12..1, got '%s'\n", command, v);
        return 2;
      }
    } else if (sf_cli_valued(a, "--exclude", v, &missing)) {
      char why[1024];
      if (sf_candidate_exclude_check(argv[++i], why, sizeof why) != 0) {
        fprintf(stderr, "%s: --exclude: %s\n", command, why);
        return 2;
      }
      o.exclude = argv[i];
    } else if (sf_cli_valued(a, "--cache-limit", v, &missing)) {
      if (sf_cli_parse_cache_limit(command, argv[++i], &o.cache_limit_bytes)) return 2;
    } else if (sf_cli_valued(a, "--threads", v, &missing)) {
      if (parse_count(command, a, argv[++i], 1, 1024, &n)) return 2;
      o.report.run.n_threads = (int)n;
      o.tables.run.n_threads = (int)n;
    } else if (a[0] != '-' && !scene_path) {
      scene_path = a;
    } else if (a[0] != '-') {
      fprintf(stderr, "%s: one scene file only: '%s' after '%s'\n", command, a, scene_path);
      return 2;
    } else {
      return sf_cli_bad_option(command, a, missing);
    }
  }
  /* --quick times on a tenth of the inputs unless told: the full million
   * three times had been two thirds of a quick build (43 of 66 s) */
  if (o.quick && !timing_points_given) o.report.timing_points = QUICK_TIMING_POINTS;
  sf_scene *scene = malloc(sizeof *scene);
  if (!scene) {
    fprintf(stderr, "%s: out of memory\n", command);
    return 1;
  }
  sf_error err = {0};
  if (scene_path) {
    if (sf_scene_load_file(scene_path, scene, &err) != SF_OK) {
      fprintf(stderr, "%s: %s\n", command, err.message);
      free(scene);
      return err.status == SF_ERR_INTERNAL ? 1 : 2;
    }
  } else {
    sf_scene_default(scene);
  }
  sf_cli_warn_atmosphere_units(command, scene->atmosphere_path, &scene->atmosphere);
  sf_scene_domain domain;
  if (sf_scene_get_domain(scene, &domain, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    free(scene);
    return 2;
  }
  if (emit && header_clash(command, scene_path, scene, &o)) {
    free(scene);
    return 2;
  }
  build_leftovers leftovers = {o.out_dir, {"", ""}};
  if (emit) sf_build_header_paths(scene, &o, leftovers.headers[0], leftovers.headers[1], sizeof leftovers.headers[0], &err);
  sf_cli_supervise(remove_build_leftovers, &leftovers);
  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !quiet);
  o.tables.run.progress = sf_progress_bar_update;
  o.tables.run.progress_ctx = &bar;
  o.report.run.progress = sf_progress_bar_update;
  o.report.run.progress_ctx = &bar;
  if (!quiet) {
    o.note = print_note;
    o.note_ctx = &bar;
  }
  sf_build_result res;
  int status = sf_build_run(scene, &o, &res, &err);
  sf_progress_bar_finish(&bar);
  if (status != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    free(scene);
    return status == SF_ERR_INPUT ? 2 : 1;
  }
  printf("%s: scene '%s': tables %d/%d from the cache (%.1f s), candidates %.1f s, report %.1f s, total %.1f s "
         "wall; CPU %.1f + %.1f + %.1f s\n",
         command, scene->name, res.tables_from_cache, res.tables_total, res.seconds_tables, res.seconds_fit,
         res.seconds_report, res.seconds_total, res.cpu_seconds_tables, res.cpu_seconds_fit, res.cpu_seconds_report);
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (!res.asked[q]) continue;
    if (res.chosen[q][0])
      printf("%s: %s: chose %s%s\n", command, sf_candidate_quantity_name((sf_candidate_quantity)q), res.chosen[q],
             res.meets_budget[q] ? " (meets the budget)" : " (NO model meets the budget: best available)");
    else
      printf("%s: %s: no model available%s\n", command, sf_candidate_quantity_name((sf_candidate_quantity)q),
             q == SF_CANDIDATE_SKY_RADIANCE && sf_atmosphere_scattering_count(&scene->atmosphere) == 0
                 ? " (no constituent of the atmosphere scatters light: its sky is black)"
                 : " (the report says why)");
  }
  sf_cli_print_cache_pruned(command, &res.cache, o.cache_limit_bytes);
  if (res.cache_problem[0]) fprintf(stderr, "%s: warning: %s\n", command, res.cache_problem);
  if (res.weights_removed > 0)
    printf("%s: weights: removed %d file(s) an earlier run left for models this run did not fit\n", command,
           res.weights_removed);
  if (res.weights_problem[0]) fprintf(stderr, "%s: warning: %s\n", command, res.weights_problem);
  if (res.views_removed > 0)
    printf("%s: views: removed %d picture(s) or plot(s) an earlier run left that this report does not show\n", command,
           res.views_removed);
  if (res.views_problem[0]) fprintf(stderr, "%s: warning: %s\n", command, res.views_problem);
  if (res.header_c[0]) printf("%s: headers: %s %s\n", command, res.header_c, res.header_glsl);
  else if (emit) printf("%s: headers: none emitted (see the report)\n", command);
  printf("%s: report: %s\n", command, res.report_html);
  free(scene);
  return 0;
}
