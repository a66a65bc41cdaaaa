/* skyfit fit sigmoid: the sigmoid-polynomial transmittance (SPEC §7.1, seed
 * 000 §9.5) per constituent and channel over a scene's (h, mu) domain,
 * fitted (fit/fit_sigmoid.h) to the exact reference optical depth. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli/atmosphere_warnings.h"
#include "cli/fit_commands.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "cli/size_pair_option.h"
#include "fit/fit_sigmoid.h"
#include "fit/fit_weights_doc.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"
#include "models/weights_file.h"

#define COMMAND "skyfit fit sigmoid"

static void usage(FILE *out) {
  fprintf(out,
          "usage: skyfit fit sigmoid [--scene S.json | --atmosphere A.json] --out W.json [options]\n"
          "       skyfit fit sigmoid --check W.json\n"
          "\n"
          "Fits T = 1/(1 + exp(-a1 - a2 h - a3 cos(theta) - a4 cos^2(theta))) per constituent and\n"
          "channel to the transmittance of rays to the top boundary (looking up or level, as seed 000\n"
          "§9.5; a ray to the ground is two such rays by eq. 43, reversed), over the scene's (h, mu)\n"
          "domain (default: the built-in scene). The reference is the exact optical depth (adaptive\n"
          "quadrature) on a grid, not a table, so no interpolation error enters; --tables is\n"
          "therefore not used by this model. Writes the weights file (SPEC §8) with the RMSE and the\n"
          "largest error of full rays (to the ground or the top) over the domain, the latter also\n"
          "just above and below the horizon, and where it is worst.\n"
          "\n"
          "options:\n"
          "  --out W.json            weights file to write (atomically)\n"
          "  --scene S.json          scene (SPEC §5): atmosphere and (h, mu) domain\n"
          "  --atmosphere A.json     atmosphere (with the built-in scene's domain)\n"
          "  --grid NHxNMU           reference grid (default 48x96)\n"
          "  --check W.json          validate a sigmoid weights file; exit 2 if invalid\n"
          "  --quiet                 no progress or summary\n"
          "  --help                  this text\n");
}

static int check_weights(const char *path) {
  sf_sigmoid_model *m = malloc(sizeof *m);
  sf_error err = {0};
  if (!m) return 1;
  int rc = sf_sigmoid_model_load(path, m, NULL, &err);
  if (rc == SF_OK) printf("%s: valid sigmoid weights, %d constituents x %d channels\n", path,
                          m->n_constituents, m->n_channels);
  else fprintf(stderr, "%s: %s\n", COMMAND, err.message);
  free(m);
  return rc;
}

int sf_cmd_fit_sigmoid(int argc, char **argv) {
  const char *out = NULL, *scene_path = NULL, *atm_path = NULL, *check = NULL;
  int quiet = 0, grid_given = 0;
  sf_sigmoid_fit_options opt;
  sf_sigmoid_fit_options_default(&opt);
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *v = sf_cli_value_after(argc, argv, i), *missing = NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (strcmp(a, "--tables") == 0) {
      fprintf(stderr, "%s: --tables: the sigmoid fit uses the exact optical depth, not tables\n", COMMAND);
      return 2;
    } else if (sf_cli_valued(a, "--out", v, &missing)) {
      out = argv[++i];
    } else if (sf_cli_valued(a, "--scene", v, &missing)) {
      scene_path = argv[++i];
    } else if (sf_cli_valued(a, "--atmosphere", v, &missing)) {
      atm_path = argv[++i];
    } else if (sf_cli_valued(a, "--check", v, &missing)) {
      check = argv[++i];
    } else if (sf_cli_valued(a, "--grid", v, &missing)) {
      if (sf_cli_parse_size_pair(argv[++i], 2, 2000, &opt.n_h, &opt.n_mu)) {
        fprintf(stderr, "%s: --grid: expected NHxNMU with 2..2000 each, got '%s'\n", COMMAND, argv[i]);
        return 2;
      }
      grid_given = 1;
    } else {
      return sf_cli_bad_option(COMMAND, a, missing);
    }
  }
  if (check && (out || scene_path || atm_path || grid_given)) {   /* they had been accepted and ignored */
    fprintf(stderr, "%s: --check validates a weights file; --out, --scene, --atmosphere and --grid do not apply\n",
            COMMAND);
    return 2;
  }
  if (check) return check_weights(check);
  if (!out) {
    fprintf(stderr, "%s: --out W.json is required; see --help\n", COMMAND);
    return 2;
  }
  if (scene_path && atm_path) {
    fprintf(stderr, "%s: --atmosphere and --scene: give one (the scene names its atmosphere)\n", COMMAND);
    return 2;
  }
  sf_error err = {0};
  sf_scene *scene = malloc(sizeof *scene);
  sf_sigmoid_model *model = malloc(sizeof *model);
  sf_sigmoid_fit_report *rep = malloc(sizeof *rep);
  int status = (scene && model && rep) ? SF_OK : sf_fail(&err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) {
    if (scene_path) status = sf_scene_load_file(scene_path, scene, &err);
    else {
      sf_scene_default(scene);
      if (atm_path) status = sf_atmosphere_load_file(atm_path, &scene->atmosphere, &err);
    }
    if (status == SF_OK)
      sf_cli_warn_atmosphere_units(COMMAND, atm_path ? atm_path : scene->atmosphere_path, &scene->atmosphere);
  }
  sf_scene_domain domain;
  if (status == SF_OK) status = sf_scene_get_domain(scene, &domain, &err);
  if (status == SF_OK) {
    const char *inputs[3];
    sf_cli_scene_files(scene_path, atm_path, scene, inputs);
    status = sf_cli_output_problem("--out", out, inputs, 3, &err);
  }
  /* a signal leaves no temporary of the weights (cli/interrupt_cleanup.h) */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_file(&outputs, out);
  if (status == SF_OK) sf_cli_supervise_outputs(&outputs);
  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !quiet);
  opt.progress = sf_progress_bar_update;
  opt.progress_ctx = &bar;
  if (status == SF_OK) status = sf_fit_sigmoid(&scene->atmosphere, &domain, &opt, model, rep, &err);
  sf_progress_bar_finish(&bar);
  const sf_atmosphere *atm = &scene->atmosphere;
  if (status == SF_OK) status = sf_sigmoid_weights_write(atm, &domain, &opt, model, rep, out, &err);
  if (status == SF_OK && !quiet) {
    for (int c = 0; c < model->n_constituents; ++c)
      for (int k = 0; k < model->n_channels; ++k) {
        const sf_sigmoid_fit_entry *e = &rep->entry[c][k];
        fprintf(stderr, "%s: %s %s: rmse %.4g, max %.4g at h %.4g km mu %.4g (cost %.3g -> %.3g, %d iterations)\n",
                COMMAND, atm->constituents[c].name, atm->channel_names[k], e->rmse, e->max_abs,
                e->worst_h_km, e->worst_mu, e->start_cost, e->final_cost, e->iterations);
      }
    fprintf(stderr, "%s: to-top rays (fitted, h %.4g..%.4g km, mu %.4g..%.4g): rmse %.4g, max %.4g at h %.4g km mu %.4g channel %s\n",
            COMMAND, rep->fit_h_min_km, rep->fit_h_max_km, rep->fit_mu_min, rep->fit_mu_max, rep->top.rmse,
            rep->top.max_abs, rep->top.worst_h_km, rep->top.worst_mu, atm->channel_names[rep->top.worst_channel]);
    fprintf(stderr, "%s: full rays over the domain: rmse %.4g (ground-hitting %.4g, sky %.4g), max %.4g at h %.4g km mu %.4g channel %s; wrote %s (%.2f s)\n",
            COMMAND, rep->rmse, rep->full_ground.rmse, rep->full_sky.rmse, rep->max_abs, rep->worst_h_km,
            rep->worst_mu, atm->channel_names[rep->worst_channel], out, rep->seconds);
  }
  if (status != SF_OK) fprintf(stderr, "%s: %s\n", COMMAND, err.message);
  free(scene);
  free(model);
  free(rep);
  return status;
}
