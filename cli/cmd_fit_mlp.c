/* skyfit fit mlp-transmittance | mlp-scattering | mlp: the neural sky
 * (SPEC §7.4-7.5, seed 000 §9.6) trained in C with hand-written Adam, and a
 * plain trainer on any CSV for comparisons with other trainers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/atmosphere_warnings.h"
#include "cli/cmd_fit_mlp_options.h"
#include "cli/fit_commands.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/table_options.h"
#include "data/sky_lookup.h"
#include "fit/candidate_cache.h"
#include "fit/dataset_csv.h"
#include "fit/dataset_sky.h"
#include "fit/mlp_sky_metrics.h"
#include "fit/output_norm.h"
#include "fit/target_root.h"
#include "fit/train_losses_json.h"
#include "models/atmosphere_file.h"
#include "models/mlp_sky.h"
#include "models/scene_file.h"
#include "models/views_standard.h"

static void sky_usage(FILE *out, int scattering) {
  fprintf(out,
          "usage: skyfit fit %s --out W.json [options]\n"
          "\n"
          "%s\n"
          "The data are the reference tables' grid points inside the scene's domain.\n"
          "\n"
          "options:\n"
          "  --scene S.json          scene (SPEC §5; default: the built-in scene)\n"
          "  --tables DIR            table cache folder (skyfit sample); default: computed in memory\n"
          "%s"
          "  --dump-dataset F.csv    write the data set (normalised inputs, then the targets, as\n"
          "                          the tables give them) and stop unless --out is given too\n",
          scattering ? "mlp-scattering" : "mlp-transmittance",
          scattering ? "Trains the scattering network: (sqrt h, mu, mu_s, nu) normalised -> scattered light\n"
                       "along the ray, exp(-x) outputs (models/mlp_sky.h). Defaults: --layers 4,8,8,9\n"
                       "--target separate --loss mse --epochs 60 --batch 1024 --lr 0.01 --lr-decay 0.95\n"
                       "--polish 100 --polish-samples 10000 --normalise brightness --normalise-cap 1.5."
                     : "Trains the transmittance network: Bruneton's (x_r, x_mu) normalised -> transmittance per channel\n"
                       "of the ray to the top boundary, exp(-exp(-x)) output (--output exp_neg_exp); rays hitting the ground are evaluated\n"
                       "reversed (eq. 43). Defaults: --layers 2,16,16,3 --loss mse --epochs 500 --batch 256\n"
                       "--lr 0.01 --lr-decay 0.995 --polish 400 (the seed's 2-4-3: --layers 2,4,3).",
          scattering ? "  --target T              separate (single per constituent without phase, then\n"
                       "                          multiple; default) or radiance (phase included, as the seed)\n"
                       "  --split S               horizon (default: one network for rays to the sky, one for\n"
                       "                          rays to the ground, trained one after the other; the\n"
                       "                          second checkpoints to FILE.ground) or none (one network)\n"
                       "  --normalise N           brightness (default) or none: the sky network (the only one\n"
                       "                          with --split none) learns its targets divided by a fitted\n"
                       "                          brightness of (altitude, sun elevation) (fit/output_norm.h):\n"
                       "                          the dawn views several times better (README)\n"
                       "  --normalise-cap C       the brightness capped C (natural log) below the brightest\n"
                       "                          situation's, so the brighter ones keep their raw weights\n"
                       "                          (default 1.5), or none\n"
                     : "  --input-map M           bruneton (Bruneton's horizon-aware x_r, x_mu, models/mlp_sky.h;\n"
                       "                          default) or sqrt_h_mu (sqrt h, mu as seed 000 §9.1)\n"
                       "  --target-root K         train on T^(1/K), then turn the network into T's exactly\n"
                       "                          (fit/target_root.h; default 1): K = 4 cuts the error of\n"
                       "                          rays to the ground near the horizon several-fold, as\n"
                       "                          skyfit build does, at a higher error on the grid points\n");
  fprintf(out, scattering ? "  --resolution, --orders, --stop-fraction, --atmosphere   as for skyfit sample (tables)\n"
                         : "  --resolution, --atmosphere   as for skyfit sample (the transmittance table alone: no\n"
                           "                               --orders or --stop-fraction)\n");
  sf_mlp_cli_help(out);
}

typedef struct sky_job {
  int scattering;
  const char *scene_path, *tables_dir, *dump_path;
  sf_mlp_target target;
  sf_mlp_input_map input_map;   /* transmittance network */
  int target_root;              /* transmittance: trained on T^(1/target_root) (fit/target_root.h) */
  int split;                    /* scattering: the horizon split (models/mlp_sky.h) */
  int normalise;                /* scattering: the sky network's brightness normalisation */
  double normalise_cap;         /* its cap below the brightest (fit/output_norm.h); INFINITY: none */
  sf_mlp_cli mlp;
  sf_table_cli tables;
} sky_job;

static void print_note(void *ctx, const char *message) {
  (void)ctx;
  fprintf(stderr, "skyfit fit: %s\n", message);
}

static cJSON *error_json(const sf_mlp_error *e, const sf_atmosphere *atm) {
  cJSON *o = cJSON_CreateObject();
  cJSON *rmse = cJSON_AddObjectToObject(o, "rmse");
  cJSON *max_abs = cJSON_AddObjectToObject(o, "max_abs");
  for (int c = 0; c < e->n_channels; ++c) {
    cJSON_AddNumberToObject(rmse, atm->channel_names[c], e->rmse[c]);
    cJSON_AddNumberToObject(max_abs, atm->channel_names[c], e->max_abs[c]);
  }
  cJSON_AddNumberToObject(o, "rmse_all", e->rmse_all);
  cJSON_AddNumberToObject(o, "max_abs_all", e->max_abs_all);
  cJSON_AddNumberToObject(o, "mean_reference", e->mean_abs_reference);
  cJSON_AddNumberToObject(o, "points", (double)e->n);
  return o;
}

/* An option of two values, on and "none": *out = 1 for on, 0 for none;
 * -1 (said) for anything else. */
static int parse_switch(const char *command, const char *option, const char *value, const char *on, int *out) {
  if (strcmp(value, on) != 0 && strcmp(value, "none") != 0) {
    fprintf(stderr, "%s: %s: expected %s or none, got '%s'\n", command, option, on, value);
    return -1;
  }
  *out = strcmp(value, on) == 0;
  return 0;
}

/* One network of the command: held-out split, Adam (checkpointing to
 * checkpoint, resuming from it if resume), then the polish. Returns SF_OK,
 * -1 when interrupted (checkpoint written, said), or an error status. */
static int train_network(sky_job *job, const char *command, const sf_dataset *data, const char *checkpoint,
                         int resume, sf_dataset *train, sf_dataset *val, sf_train_result *result,
                         sf_mlp_lm_result *lm, sf_error *err) {
  sf_train_options *t = &job->mlp.train;
  memset(result, 0, sizeof *result);
  memset(lm, 0, sizeof *lm);
  if (sf_dataset_split(data, job->mlp.validation_fraction, t->seed, train, val, err)) return err->status;
  t->checkpoint_path = checkpoint;
  t->resume = resume;
  /* Ctrl-C in the polish keeps the trained state: --resume polishes again */
  t->keep_final_checkpoint = job->mlp.polish.iterations > 0;
  sf_mlp_progress progress;
  sf_mlp_progress_init(&progress, job->mlp.quiet);
  t->progress = sf_mlp_progress_update;
  t->progress_ctx = &progress;
  int status = sf_mlp_train(train, val, t, result, err);
  sf_mlp_progress_finish(&progress);
  if (status) return status;
  if (result->interrupted) {
    fprintf(stderr, "%s: interrupted after %d epochs; checkpoint %s; continue with --resume\n", command,
            result->epochs_run, checkpoint);
    sf_mlp_free(&result->net);
    return -1;
  }
  if (sf_mlp_cli_polish(&job->mlp, train, val, result, lm, err)) {
    sf_mlp_free(&result->net);
    return err->status;
  }
  if (lm->interrupted) {
    fprintf(stderr, "%s: interrupted in the polish after %d of %d steps; checkpoint %s (training done); "
            "continue with --resume\n", command, lm->iterations, job->mlp.polish.iterations, checkpoint);
    sf_mlp_free(&result->net);
    return -1;
  }
  return SF_OK;
}

static int run_sky(int argc, char **argv, int scattering) {
  const char *command = scattering ? "skyfit fit mlp-scattering" : "skyfit fit mlp-transmittance";
  sky_job job;
  memset(&job, 0, sizeof job);
  job.scattering = scattering;
  job.target = scattering ? SF_MLP_TARGET_SEPARATE : SF_MLP_TARGET_TRANSMITTANCE_TOP;
  /* Bruneton's inputs: lower held-out, full-ray and view errors than
   * (sqrt h, mu) at equal budget (bench/mlp_accuracy.sh, issue 6) */
  job.input_map = SF_MLP_INPUTS_BRUNETON;
  job.target_root = 1;
  job.split = scattering;
  job.normalise = scattering;   /* brightness (fit/output_norm.h; README) */
  job.normalise_cap = SF_OUTPUT_NORM_CAP_BELOW;
  sf_mlp_cli_default(&job.mlp);
  sf_table_cli_default(&job.tables);
  sf_train_options *t = &job.mlp.train;
  t->shape.hidden = SF_ACT_SIGMOID;
  /* transmittance: e^-e^-x, the optical depth e^-z (seed 000 eq. 41) */
  t->shape.output = scattering ? SF_ACT_EXP_NEG : SF_ACT_EXP_NEG_EXP;
  /* Defaults measured in bench/mlp_accuracy.sh (issue: neural sky): the
   * relative loss leaves the scattering network far from the data in RMSE
   * at every sun elevation, MSE does not; the transmittance network
   * reaches ten times lower RMSE with two hidden layers of 8 and a
   * Levenberg-Marquardt polish (fit/mlp_lm.h) than 2-4-3 with Adam alone,
   * two of 16 with a longer polish 4-8x lower again (fit/mlp_lm.h), and
   * the exp_neg_exp output halves its error on full rays and views against
   * exp_neg. Both networks' sizes and polish: fit/mlp_lm.h. */
  t->loss = SF_LOSS_MSE;
  t->epochs = scattering ? 60 : 500;
  t->batch = scattering ? 1024 : 256;
  t->adam.lr_decay_per_epoch = scattering ? 0.95 : 0.995;
  job.mlp.polish.iterations = scattering ? SF_MLP_SCATTERING_POLISH : SF_MLP_TRANSMITTANCE_POLISH;
  if (scattering) job.mlp.polish.max_samples = SF_MLP_SCATTERING_POLISH_SAMPLES;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      sky_usage(stdout, scattering);
      return 0;
    }
    int r = sf_mlp_cli_option(&job.mlp, command, argc, argv, &i);
    if (r == 0) {
      r = sf_table_cli_option(&job.tables, command, argc, argv, &i);
      /* the transmittance network reads the transmittance table alone:
       * the scattering orders would be accepted and ignored */
      if (r > 0 && !scattering && (strcmp(a, "--orders") == 0 || strcmp(a, "--stop-fraction") == 0)) {
        fprintf(stderr, "%s: %s: the transmittance network takes the transmittance table alone, which has no "
                "scattering orders\n", command, a);
        return 2;
      }
      /* the data sets read the tables on Bruneton's grid (below): leenman
       * had been accepted and ignored, its tables in --tables recomputed */
      if (r > 0 && strcmp(a, "--parameterization") == 0 && job.tables.set.kind != SF_PARAM_BRUNETON) {
        fprintf(stderr, "%s: --parameterization: the networks train on the tables of the bruneton "
                "parameterization only\n", command);
        return 2;
      }
    }
    if (r < 0) return 2;
    if (r > 0) continue;
    int has_value = sf_cli_value_after(argc, argv, i) != NULL;
    if ((strcmp(a, "--tables") == 0 || strcmp(a, "--dump-dataset") == 0 ||
         (scattering && (strcmp(a, "--target") == 0 || strcmp(a, "--split") == 0 ||
                         strcmp(a, "--normalise") == 0 || strcmp(a, "--normalise-cap") == 0)) ||
         (!scattering && (strcmp(a, "--input-map") == 0 || strcmp(a, "--target-root") == 0))) &&
        !has_value) {
      sf_cli_bad_option(command, a, a);
      return 2;
    }
    if (strcmp(a, "--tables") == 0) job.tables_dir = argv[++i];
    else if (strcmp(a, "--dump-dataset") == 0) job.dump_path = argv[++i];
    else if (!scattering && strcmp(a, "--input-map") == 0) {
      const char *v = argv[++i];
      if (sf_mlp_input_map_parse(v, &job.input_map)) {
        fprintf(stderr, "%s: --input-map: expected sqrt_h_mu or bruneton, got '%s'\n", command, v);
        return 2;
      }
    } else if (!scattering && strcmp(a, "--target-root") == 0) {
      const char *v = argv[++i];
      long k;
      if (sf_mlp_cli_parse_long(v, 1, SF_TARGET_ROOT_MAX, &k)) {
        fprintf(stderr, "%s: --target-root: expected an integer in 1..%d, got '%s'\n", command, SF_TARGET_ROOT_MAX, v);
        return 2;
      }
      job.target_root = (int)k;
    } else if (scattering && strcmp(a, "--split") == 0) {
      if (parse_switch(command, a, argv[++i], "horizon", &job.split)) return 2;
    } else if (scattering && strcmp(a, "--normalise") == 0) {
      if (parse_switch(command, a, argv[++i], "brightness", &job.normalise)) return 2;
    } else if (scattering && strcmp(a, "--normalise-cap") == 0) {
      const char *v = argv[++i];
      if (strcmp(v, "none") == 0)
        job.normalise_cap = INFINITY;
      else if (sf_mlp_cli_parse_double(v, 0.0, HUGE_VAL, &job.normalise_cap)) {
        fprintf(stderr, "%s: --normalise-cap: expected a number >= 0 or none, got '%s'\n", command, v);
        return 2;
      }
    } else if (scattering && strcmp(a, "--target") == 0) {
      const char *v = argv[++i];
      if (sf_mlp_target_parse(v, &job.target) || job.target == SF_MLP_TARGET_TRANSMITTANCE_TOP) {
        fprintf(stderr, "%s: --target: expected separate or radiance, got '%s'\n", command, v);
        return 2;
      }
    } else {
      fprintf(stderr, "%s: unknown option '%s' (see --help)\n", command, a);
      return 2;
    }
  }
  /* --scene is a table option (cli/table_options.h): its domain restricts the data */
  job.scene_path = job.tables.scene_path;
  if (!job.mlp.out && !job.dump_path && !job.mlp.write_init) {
    fprintf(stderr, "%s: --out W.json (or --dump-dataset / --write-init) is required\n", command);
    return 2;
  }
  sf_error err = {0};
  sf_scene *scene = malloc(sizeof *scene);
  sf_atmosphere *atm = malloc(sizeof *atm);
  if (!scene || !atm) {
    free(scene);
    free(atm);
    return 1;
  }
  int status = 0;
  sf_table_set set;
  memset(&set, 0, sizeof set);
  sf_dataset data, train, val, ground, train_g, val_g, val_all;
  memset(&data, 0, sizeof data);
  memset(&train, 0, sizeof train);
  memset(&val, 0, sizeof val);
  memset(&ground, 0, sizeof ground);
  memset(&train_g, 0, sizeof train_g);
  memset(&val_g, 0, sizeof val_g);
  memset(&val_all, 0, sizeof val_all);
  sf_train_result result, result_g;
  memset(&result, 0, sizeof result);
  memset(&result_g, 0, sizeof result_g);
  sf_mlp_lm_result lm, lm_g;
  sf_mlp_sky model;
  memset(&model, 0, sizeof model);
  double *init = NULL;
  cJSON *doc = NULL;
  if (job.scene_path) {
    if (sf_scene_load_file(job.scene_path, scene, &err)) goto fail;
  } else {
    sf_scene_default(scene);
  }
  *atm = scene->atmosphere;
  if (job.tables.atmosphere_path && sf_atmosphere_load_file(job.tables.atmosphere_path, atm, &err)) goto fail;
  scene->atmosphere = *atm;
  sf_cli_warn_atmosphere_units(command, job.tables.atmosphere_path ? job.tables.atmosphere_path
                                                                   : scene->atmosphere_path, atm);
  sf_scene_domain dom;
  if (sf_scene_get_domain(scene, &dom, &err)) goto fail;
  /* the run's files, which none of its outputs may overwrite (the scene's
   * own atmosphere file included) */
  const char *run_files[5];
  sf_cli_scene_files(job.scene_path, job.tables.atmosphere_path, scene, run_files);
  run_files[3] = job.mlp.init_weights;
  run_files[4] = job.dump_path;
  if (job.mlp.write_init &&
      (status = sf_cli_check_output(command, "--write-init", job.mlp.write_init, run_files, 4)))
    goto done;
  if (job.dump_path && (status = sf_cli_check_output(command, "--dump-dataset", job.dump_path, run_files, 4)))
    goto done;

  /* network shape */
  int nch = atm->n_channels;
  int n_single_guess = sf_atmosphere_scattering_count(atm);
  if (job.mlp.layers) {
    if (sf_mlp_shape_parse_layers(job.mlp.layers, &t->shape, &err)) goto fail;
  } else {
    int n_out = !scattering ? nch : (job.target == SF_MLP_TARGET_SEPARATE ? (n_single_guess + 1) * nch : nch);
    char text[64];
    if (scattering) snprintf(text, sizeof text, "4,8,8,%d", n_out);
    else snprintf(text, sizeof text, "2,%s,%d", SF_MLP_TRANSMITTANCE_HIDDEN, n_out);
    if (sf_mlp_shape_parse_layers(text, &t->shape, &err)) {
      err = (sf_error){0};   /* the parser's message names a --layers not given */
      sf_fail(&err, SF_ERR_INPUT, "the network would have %d outputs (%d channels%s), more than the %d units a "
              "layer may have: give the atmosphere fewer channels%s", n_out, nch,
              n_out > nch ? " times the constituents that scatter and the multiple scattering" : "",
              SF_MLP_MAX_WIDTH, n_out > nch ? ", or train on --target radiance" : "");
      goto fail;
    }
  }
  if (sf_target_root_check(job.target_root, &t->shape, &err)) goto fail;
  if (job.mlp.write_init) {
    status = sf_mlp_cli_write_init(command, job.mlp.write_init, &t->shape, t->seed);
    goto done;
  }

  char checkpoint[4200] = "", checkpoint_g[4300];
  if (job.mlp.out) snprintf(checkpoint, sizeof checkpoint, "%s.checkpoint", job.mlp.out);
  const char *ckpt = job.mlp.checkpoint ? job.mlp.checkpoint : checkpoint;
  snprintf(checkpoint_g, sizeof checkpoint_g, "%s.ground", ckpt);
  /* --resume without a checkpoint fails now, not after the tables (minutes
   * when they are not cached); the scattering split's ground network has
   * its own (below). */
  if (job.mlp.out && t->resume &&
      (status = sf_mlp_cli_check_resume(command, ckpt, scattering ? checkpoint_g : NULL)))
    goto done;
  if (job.mlp.out) {
    if ((status = sf_mlp_cli_check_run(command, &job.mlp, ckpt, run_files, 5)) ||
        (scattering && (status = sf_mlp_cli_check_run(command, &job.mlp, checkpoint_g, run_files, 5))))
      goto done;
  }

  /* a signal leaves no temporary of the weights, a checkpoint, the dump or
   * a table (cli/interrupt_cleanup.h); Ctrl-C still checkpoints, in the
   * child that trains */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_file(&outputs, job.mlp.out);
  sf_cli_outputs_add_file(&outputs, job.mlp.out ? ckpt : NULL);
  sf_cli_outputs_add_file(&outputs, job.mlp.out && scattering ? checkpoint_g : NULL);
  sf_cli_outputs_add_file(&outputs, job.dump_path);
  sf_cli_outputs_add_folder(&outputs, job.tables_dir);
  sf_cli_supervise_outputs(&outputs);

  /* tables */
  sf_table_set_options *so = &job.tables.set;
  so->kind = SF_PARAM_BRUNETON;
  so->cache_dir = job.tables_dir;
  /* The transmittance network reads the transmittance table alone: the
   * scattering tables took 34 s of a 1-epoch fit that needs 0.05 s of tables. */
  so->transmittance_only = !scattering;
  if (t->n_threads > 0) so->run.n_threads = t->n_threads;
  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !job.mlp.quiet);
  so->run.progress = sf_progress_bar_update;
  so->run.progress_ctx = &bar;
  so->note = job.mlp.quiet ? NULL : print_note;
  if (sf_table_set_check(atm, so, &err) || sf_table_set_make(&set, atm, so, &err)) goto fail;
  sf_progress_bar_finish(&bar);

  int n_single = 0, constituent[SF_MAX_CONSTITUENTS];
  if (scattering ? sf_dataset_scattering(&set, atm, &dom, job.target, &data, &n_single, constituent, &err)
                 : sf_dataset_transmittance_mapped(&set, atm, &dom, job.input_map, &data, &err))
    goto fail;
  /* the set trained on, hence the one dumped */
  if (sf_dataset_targets_root(&data, job.target_root, &err)) goto fail;
  if (job.dump_path) {
    if (sf_dataset_write_csv(&data, job.dump_path, t->n_threads, &err)) goto fail;
    if (!job.mlp.quiet)
      fprintf(stderr, "%s: wrote %ld samples (%d inputs, %d targets) to %s\n", command, data.n, data.n_in,
              data.n_out, job.dump_path);
    if (!job.mlp.out) goto done;
  }
  /* the horizon split (models/mlp_sky.h): data becomes the sky half */
  if (scattering && job.split) {
    sf_dataset sky;
    if (sf_dataset_scattering_halves(&set, atm, &dom, job.target, &sky, &ground, &n_single, constituent, &err))
      goto fail;
    if (ground.n == 0) {   /* a half too small to train on */
      if (!job.mlp.quiet)
        fprintf(stderr, "%s: fewer than %d rays to the sky or to the ground (of length > 0) in the domain: "
                "one network (--split none)\n", command, SF_MLP_SPLIT_MIN_SAMPLES);
      sf_dataset_free(&sky);
      job.split = 0;
    } else {
      sf_dataset_free(&data);
      data = sky;
    }
  }
  int split = scattering && job.split;
  /* The sky network's targets divided by their brightness (fit/output_norm.h);
   * the ground network measured worse with it (orbit and space views), so
   * it keeps its raw targets. */
  sf_mlp_output_norm norm;
  memset(&norm, 0, sizeof norm);
  if (scattering && job.normalise) {
    char why[512];
    if (sf_output_norm_prepare(&data, job.normalise_cap, &norm, why, sizeof why, &err)) goto fail;
    if (why[0] && !job.mlp.quiet)
      fprintf(stderr, "%s: training the sky network on raw targets: %s\n", command, why);
  }

  int np = sf_mlp_param_count(&t->shape);
  if (job.mlp.init_weights) {
    init = malloc((size_t)np * sizeof(double));
    if (!init) goto fail;
    if ((status = sf_mlp_cli_read_init(command, job.mlp.init_weights, &t->shape, init))) goto done;
    t->init_params = init;
  }
  t->interrupt = sf_mlp_catch_interrupt();
  /* --resume with the split: each network resumes from its own checkpoint
   * if it has one; a network that had finished before the interruption
   * (no checkpoint left) trains again, to the same bytes. */
  int resume = t->resume, resume_sky = resume, resume_ground = 0;
  if (split && resume) {
    resume_ground = sf_cache_exists(checkpoint_g);
    resume_sky = sf_cache_exists(ckpt) || !resume_ground;   /* neither: the usual "no checkpoint" error */
  }
  if (split && !job.mlp.quiet) fprintf(stderr, "%s: network 1 of 2: rays to the sky\n", command);
  int ts = train_network(&job, command, &data, ckpt, resume_sky, &train, &val, &result, &lm, &err);
  if (ts == -1) {
    status = 130;
    goto done;
  }
  if (ts) goto fail;
  if (norm.active) sf_output_norm_restore(&norm, &val);   /* the model's metrics are in radiance */
  /* ... and in transmittance */
  sf_mlp_from_target_root(&t->shape, result.net.params, job.target_root);
  sf_dataset_targets_power(&val, job.target_root);
  if (split) {
    if (!job.mlp.quiet) fprintf(stderr, "%s: network 2 of 2: rays to the ground\n", command);
    /* the test hook counts the command's epochs: the rest go to this
     * network (at least one: 0 would mean no hook) */
    if (t->stop_after_epochs > 0)
      t->stop_after_epochs = t->stop_after_epochs > result.epochs_this_call + 1
                                 ? t->stop_after_epochs - result.epochs_this_call : 1;
    ts = train_network(&job, command, &ground, checkpoint_g, resume_ground, &train_g, &val_g, &result_g, &lm_g, &err);
    if (ts == -1) {
      sf_mlp_free(&result.net);
      status = 130;
      goto done;
    }
    if (ts) {
      sf_mlp_free(&result.net);
      goto fail;
    }
  }
  double offset[4], scale[4];
  for (int k = 0; k < data.n_in; ++k) {
    offset[k] = data.input_offset[k];
    scale[k] = data.input_scale[k];
  }
  if (sf_mlp_sky_make(&model, &result.net, job.target, atm, offset, scale, n_single, constituent, &err)) {
    sf_mlp_free(&result_g.net);
    goto fail;
  }
  model.input_map = scattering ? SF_MLP_INPUTS_SQRT_H_MU : job.input_map;
  if (split && sf_mlp_sky_set_ground_net(&model, &result_g.net, &err)) goto fail;
  if (norm.active && sf_mlp_sky_set_output_norm(&model, 0, &norm, &err)) goto fail;
  /* the model's errors on both validation sets (the losses stay per
   * network: fit/train_losses_json.h) */
  const sf_dataset *val_model = &val;
  if (split) {
    if (sf_dataset_concat(&val, &val_g, &val_all, &err)) goto fail;
    val_model = &val_all;
  }

  /* weights file */
  doc = sf_weights_new(scattering ? "mlp-scattering" : "mlp-transmittance",
                       scattering ? "sky_radiance" : "transmittance", atm, &dom);
  if (!doc) goto fail;
  for (int k = 0; k < data.n_in; ++k) sf_weights_add_input(doc, data.names[k], offset[k], scale[k]);
  cJSON *training = sf_weights_training(doc);
  cJSON_AddStringToObject(training, "target", sf_mlp_target_name(job.target));
  if (job.target == SF_MLP_TARGET_SEPARATE) {
    cJSON *comps = cJSON_AddArrayToObject(training, "components");
    for (int k = 0; k < n_single; ++k)
      cJSON_AddItemToArray(comps, cJSON_CreateString(atm->constituents[constituent[k]].name));
    cJSON_AddItemToArray(comps, cJSON_CreateString("multiple"));
  }
  if (sf_mlp_add_to_weights(doc, &model.net)) goto fail;
  if (split && sf_mlp_add_params_to_weights(doc, &model.net_ground, "ground_")) goto fail;
  if (sf_mlp_sky_add_norms_to_weights(doc, &model)) goto fail;
  if (scattering) cJSON_AddStringToObject(training, "split", split ? "horizon" : "none");
  if (scattering) cJSON_AddStringToObject(training, "normalise", norm.active ? "brightness" : "none");
  cJSON_AddNumberToObject(training, "seed", (double)t->seed);
  cJSON_AddNumberToObject(training, "epochs", t->epochs);
  cJSON_AddNumberToObject(training, "epochs_run", result.epochs_run);
  cJSON_AddStringToObject(training, "loss", sf_mlp_loss_name(t->loss));
  if (job.target_root > 1) cJSON_AddNumberToObject(training, "target_root", job.target_root);
  cJSON_AddNumberToObject(training, "loss_floor", t->loss_floor);
  cJSON_AddNumberToObject(training, "batch", (double)t->batch);
  cJSON_AddNumberToObject(training, "lr", t->adam.lr);
  cJSON_AddNumberToObject(training, "lr_decay_per_epoch", t->adam.lr_decay_per_epoch);
  cJSON_AddNumberToObject(training, "restarts", t->restarts);
  cJSON_AddNumberToObject(training, "polish_iterations", job.mlp.polish.iterations);
  if (job.mlp.polish.iterations > 0) {
    cJSON_AddNumberToObject(training, "polish_samples", (double)job.mlp.polish.max_samples);
    cJSON_AddNumberToObject(training, "polish_accepted", lm.accepted);
  }
  cJSON_AddNumberToObject(training, "patience", t->patience);
  cJSON_AddNumberToObject(training, "best_restart", result.best_restart);
  cJSON_AddNumberToObject(training, "best_epoch", result.best_epoch);
  cJSON_AddNumberToObject(training, "training_samples", (double)train.n);
  cJSON_AddNumberToObject(training, "validation_samples", (double)val.n);
  if (split) {   /* the figures above are the sky network's */
    cJSON *g = cJSON_AddObjectToObject(training, "ground_network");
    cJSON_AddNumberToObject(g, "epochs_run", result_g.epochs_run);
    if (job.mlp.polish.iterations > 0) cJSON_AddNumberToObject(g, "polish_accepted", lm_g.accepted);
    cJSON_AddNumberToObject(g, "best_restart", result_g.best_restart);
    cJSON_AddNumberToObject(g, "best_epoch", result_g.best_epoch);
    cJSON_AddNumberToObject(g, "training_samples", (double)train_g.n);
    cJSON_AddNumberToObject(g, "validation_samples", (double)val_g.n);
  }
  cJSON *metrics = sf_weights_metrics(doc);
  if (sf_train_losses_to_json(metrics, &result, norm.active, job.target_root, split ? &result_g : NULL)) goto fail;
  sf_mlp_error e;
  double val_rmse = NAN, val_max_abs = NAN;   /* for the summary line */
  if (val_model->n > 0) {
    sf_mlp_error_validation(&model, val_model, &e);
    cJSON_AddItemToObject(metrics, "validation", error_json(&e, atm));
    cJSON_AddNumberToObject(metrics, "rmse", e.rmse_all);
    cJSON_AddNumberToObject(metrics, "max_abs", e.max_abs_all);
    val_rmse = e.rmse_all;
    val_max_abs = e.max_abs_all;
  }
  if (!scattering) {
    sf_mlp_error_transmittance(&model, atm, &dom, 20000, t->seed + 1, 0, &e);
    cJSON_AddItemToObject(metrics, "full_ray_random", error_json(&e, atm));
    sf_mlp_error_transmittance(&model, atm, &dom, 20000, t->seed + 1, 1, &e);
    cJSON_AddItemToObject(metrics, "full_ray_random_float32", error_json(&e, atm));
    /* seed 000 App. D: the standard transmittance views, every pixel */
    sf_mlp_error ev[8];
    const sf_view_def *views;
    int nv = sf_standard_transmittance_views(&views);
    nv = sf_mlp_error_transmittance_views(&model, atm, SF_VIEW_DEFAULT_WIDTH, SF_VIEW_DEFAULT_HEIGHT, ev,
                                          nv < 8 ? nv : 8);
    cJSON *vo = cJSON_AddObjectToObject(metrics, "views_rmse");
    for (int v = 0; v < nv; ++v) cJSON_AddNumberToObject(vo, views[v].name, ev[v].rmse_all);
  } else {
    sf_sky_tables sky;
    sf_sky_tables_of_set(&sky, atm, &set);
    static const struct { const char *name; double deg; } suns[] = {{"noon", 90.0}, {"sunrise", 6.0}, {"dawn", -6.0}};
    for (int k = 0; k < 3; ++k) {
      double mu_s = sin(suns[k].deg * 3.14159265358979323846 / 180.0);
      if (mu_s < dom.mu_s_min - 1e-12 || mu_s > dom.mu_s_max + 1e-12) continue;
      sf_mlp_error_radiance(&model, &sky, &dom, suns[k].deg, 20000, t->seed + 1, &e);
      char key[32];
      snprintf(key, sizeof key, "radiance_%s", suns[k].name);
      cJSON_AddItemToObject(metrics, key, error_json(&e, atm));
    }
    /* seed 000 App. B: the standard radiance views, every pixel */
    sf_mlp_error ev[16];
    const sf_view_def *views;
    int nv = sf_standard_radiance_views(&views);
    nv = sf_mlp_error_radiance_views(&model, &sky, atm, SF_VIEW_DEFAULT_WIDTH, SF_VIEW_DEFAULT_HEIGHT, ev,
                                     nv < 16 ? nv : 16);
    cJSON *vo = cJSON_AddObjectToObject(metrics, "views_rmse");
    for (int v = 0; v < nv; ++v) cJSON_AddNumberToObject(vo, views[v].name, ev[v].rmse_all);
  }
  /* Timing stays out of the file: the same run must write the same bytes. */
  if (sf_weights_write(doc, job.mlp.out, &err)) goto fail;
  remove(ckpt);   /* the trained states kept for an interrupted polish */
  if (split) remove(checkpoint_g);
  if (!job.mlp.quiet) {
    /* one line: the whole metrics object (60 lines) is in the file */
    char timing[96] = "no epoch run: resumed a finished training", summary[96] = "";
    /* a split run resumed after its sky network trains the ground one only */
    if (isfinite(result.seconds_per_epoch) && split && isfinite(result_g.seconds_per_epoch))
      snprintf(timing, sizeof timing, "%.4g s per epoch (sky network), %.4g (ground)", result.seconds_per_epoch,
               result_g.seconds_per_epoch);
    else if (isfinite(result.seconds_per_epoch))
      snprintf(timing, sizeof timing, "%.4g s per epoch", result.seconds_per_epoch);
    else if (split && isfinite(result_g.seconds_per_epoch))
      snprintf(timing, sizeof timing, "%.4g s per epoch (ground network; the sky network's training resumed "
               "finished)", result_g.seconds_per_epoch);
    if (val_model->n > 0)
      snprintf(summary, sizeof summary, "; validation RMSE %.3g, max error %.3g", val_rmse, val_max_abs);
    fprintf(stderr, "%s: wrote %s (%s)%s; all metrics under \"metrics\" there\n", command, job.mlp.out, timing,
            summary);
  }
  goto done;
fail:
  if (err.status == SF_OK) sf_fail(&err, SF_ERR_INTERNAL, "out of memory");
  fprintf(stderr, "%s: %s\n", command, err.message);
  status = err.status;
done:
  cJSON_Delete(doc);
  sf_mlp_sky_free(&model);
  sf_dataset_free(&data);
  sf_dataset_free(&train);
  sf_dataset_free(&val);
  sf_dataset_free(&ground);
  sf_dataset_free(&train_g);
  sf_dataset_free(&val_g);
  sf_dataset_free(&val_all);
  sf_table_set_free(&set);
  free(init);
  free(scene);
  free(atm);
  return status;
}

int sf_cmd_fit_mlp_transmittance(int argc, char **argv) { return run_sky(argc, argv, 0); }
int sf_cmd_fit_mlp_scattering(int argc, char **argv) { return run_sky(argc, argv, 1); }

static void plain_usage(FILE *out) {
  fprintf(out,
          "usage: skyfit fit mlp --data F.csv --inputs N --layers A,B,... [options]\n"
          "\n"
          "Trains a network on any CSV (header row; the first N columns are inputs, the rest\n"
          "targets), e.g. one written by --dump-dataset, and prints the final training loss\n"
          "(over the whole set) and seconds per epoch as JSON on stdout (null when the run ran\n"
          "no epoch: --resume of a training that had finished). No validation split\n"
          "unless --validation is given. Defaults: --hidden sigmoid --output exp_neg --loss mse\n"
          "--batch 1024 --epochs 10 --lr 0.01 --lr-decay 1.\n"
          "\n"
          "  --data F.csv, --inputs N  the data (required, with --layers)\n");
  sf_mlp_cli_help(out);
}

int sf_cmd_fit_mlp(int argc, char **argv) {
  const char *command = "skyfit fit mlp";
  sf_mlp_cli o;
  sf_mlp_cli_default(&o);
  o.validation_fraction = 0.0;
  sf_train_options *t = &o.train;
  t->shape.hidden = SF_ACT_SIGMOID;
  t->shape.output = SF_ACT_EXP_NEG;
  t->epochs = 10;
  const char *data_path = NULL;
  long n_inputs = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      plain_usage(stdout);
      return 0;
    }
    int r = sf_mlp_cli_option(&o, command, argc, argv, &i);
    if (r < 0) return 2;
    if (r > 0) continue;
    if ((strcmp(a, "--data") == 0 || strcmp(a, "--inputs") == 0) && !sf_cli_value_after(argc, argv, i)) {
      sf_cli_bad_option(command, a, a);
      return 2;
    }
    if (strcmp(a, "--data") == 0) data_path = argv[++i];
    else if (strcmp(a, "--inputs") == 0) {
      char *end;
      n_inputs = strtol(argv[++i], &end, 10);
      if (*end != '\0' || n_inputs < 1 || n_inputs >= SF_DATASET_MAX_COLUMNS) {
        fprintf(stderr, "%s: --inputs: expected a whole number in 1..%d (the data hold at most %d columns), got '%s'\n",
                command, SF_DATASET_MAX_COLUMNS - 1, SF_DATASET_MAX_COLUMNS, argv[i]);
        return 2;
      }
    } else {
      fprintf(stderr, "%s: unknown option '%s' (see --help)\n", command, a);
      return 2;
    }
  }
  if (!data_path || n_inputs < 1 || !o.layers) {
    fprintf(stderr, "%s: --data, --inputs and --layers are required\n", command);
    return 2;
  }
  sf_error err = {0};
  if (sf_mlp_shape_parse_layers(o.layers, &t->shape, &err)) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return 2;
  }
  const char *inputs[2] = {data_path, o.init_weights};
  if (o.write_init) {
    if (sf_cli_check_output(command, "--write-init", o.write_init, inputs, 2)) return 2;
    return sf_mlp_cli_write_init(command, o.write_init, &t->shape, t->seed);
  }
  char checkpoint[4200];
  if (o.out) snprintf(checkpoint, sizeof checkpoint, "%s.checkpoint", o.out);
  t->checkpoint_path = o.checkpoint ? o.checkpoint : (o.out ? checkpoint : NULL);
  /* before the CSV is read (seconds for a million rows) */
  if (t->resume && sf_mlp_cli_check_resume(command, t->checkpoint_path, NULL)) return 2;
  if (sf_mlp_cli_check_run(command, &o, t->checkpoint_path, inputs, 2)) return 2;
  sf_cli_outputs outputs = {0};   /* as above */
  sf_cli_outputs_add_file(&outputs, o.out);
  sf_cli_outputs_add_file(&outputs, t->checkpoint_path);
  sf_cli_supervise_outputs(&outputs);
  sf_dataset data, train, val;
  memset(&train, 0, sizeof train);
  memset(&val, 0, sizeof val);
  if (sf_dataset_read_csv(data_path, (int)n_inputs, t->n_threads, &data, &err)) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return err.status;
  }
  int status = 0;
  double *init = NULL;
  cJSON *doc = NULL;
  sf_train_result result;
  memset(&result, 0, sizeof result);
  if (sf_dataset_split(&data, o.validation_fraction, t->seed, &train, &val, &err)) goto fail;
  if (o.init_weights) {
    init = malloc((size_t)sf_mlp_param_count(&t->shape) * sizeof(double));
    if (!init) goto fail;
    if ((status = sf_mlp_cli_read_init(command, o.init_weights, &t->shape, init))) goto done;
    t->init_params = init;
  }
  t->interrupt = sf_mlp_catch_interrupt();
  /* Ctrl-C in the polish keeps the trained state: --resume polishes again */
  t->keep_final_checkpoint = o.polish.iterations > 0;
  sf_mlp_progress progress;
  sf_mlp_progress_init(&progress, o.quiet);
  t->progress = sf_mlp_progress_update;
  t->progress_ctx = &progress;
  int train_status = sf_mlp_train(&train, &val, t, &result, &err);
  sf_mlp_progress_finish(&progress);
  if (train_status) goto fail;
  if (result.interrupted) {
    fprintf(stderr, "%s: interrupted after %d epochs%s%s\n", command, result.epochs_run,
            t->checkpoint_path ? "; checkpoint " : "; nothing saved (--out or --checkpoint keeps a checkpoint)",
            t->checkpoint_path ? t->checkpoint_path : "");
    status = 130;
    goto done;
  }
  sf_mlp_lm_result lm;
  if (sf_mlp_cli_polish(&o, &train, &val, &result, &lm, &err)) goto fail;
  if (lm.interrupted) {
    fprintf(stderr, "%s: interrupted in the polish after %d of %d steps%s%s\n", command, lm.iterations,
            o.polish.iterations, t->checkpoint_path ? "; checkpoint (training done) " : "",
            t->checkpoint_path ? t->checkpoint_path : "");
    status = 130;
    goto done;
  }
  if (o.polish.iterations > 0 && !o.quiet) {
    char validation[96] = "";   /* none without a validation set */
    if (!isnan(lm.initial_validation))
      snprintf(validation, sizeof validation, ", validation %.6g -> %.6g", lm.initial_validation,
               lm.final_validation);
    fprintf(stderr, "%s: polish: %d steps, %d accepted; training loss %.6g -> %.6g%s\n", command, lm.iterations,
            lm.accepted, lm.initial_loss, lm.final_loss, validation);
  }
  /* The final training MSE over the whole training set, whatever the loss. */
  sf_mlp_loss mse = {SF_LOSS_MSE, NULL};
  double train_mse = sf_mlp_dataset_loss(&t->shape, result.net.params, &mse, &train, t->n_threads);
  if (o.out) {
    sf_atmosphere atm;
    sf_atmosphere_default(&atm);
    sf_scene_domain dom = {0, 0, -1, 1, -1, 1};
    doc = sf_weights_new("mlp", "values", &atm, &dom);
    if (!doc) goto fail;
    for (int k = 0; k < data.n_in; ++k) sf_weights_add_input(doc, data.names[k], 0.0, 1.0);
    if (sf_mlp_add_to_weights(doc, &result.net)) goto fail;
    cJSON_AddNumberToObject(sf_weights_training(doc), "seed", (double)t->seed);
    cJSON_AddNumberToObject(sf_weights_training(doc), "epochs", t->epochs);
    cJSON_AddStringToObject(sf_weights_training(doc), "loss", sf_mlp_loss_name(t->loss));
    /* the MSE of targets beyond 1e154 overflows whatever the loss trained
     * on: left out, not a refused file that lost the network */
    if (isfinite(train_mse)) cJSON_AddNumberToObject(sf_weights_metrics(doc), "train_mse", train_mse);
    if (sf_weights_write(doc, o.out, &err)) goto fail;
  }
  if (t->checkpoint_path) remove(t->checkpoint_path);   /* kept for an interrupted polish */
  /* null, not 0, when this call ran no epoch (it resumed a finished run) */
  /* and null, not inf (no JSON), for a loss that overflows */
  char wall[32] = "null", cpu[32] = "null", mse_text[32] = "null", loss_text[32] = "null";
  if (isfinite(result.seconds_per_epoch)) snprintf(wall, sizeof wall, "%.6g", result.seconds_per_epoch);
  if (isfinite(result.cpu_seconds_per_epoch)) snprintf(cpu, sizeof cpu, "%.6g", result.cpu_seconds_per_epoch);
  if (isfinite(train_mse)) snprintf(mse_text, sizeof mse_text, "%.9g", train_mse);
  if (isfinite(result.train_loss)) snprintf(loss_text, sizeof loss_text, "%.9g", result.train_loss);
  printf("{\"final_train_mse\": %s, \"final_train_loss\": %s, \"seconds_per_epoch\": %s, "
         "\"cpu_seconds_per_epoch\": %s, \"epochs\": %d, \"epochs_this_run\": %d, \"samples\": %ld, "
         "\"batch\": %ld, \"threads\": %d}\n",
         mse_text, loss_text, wall, cpu, result.epochs_run, result.epochs_this_call, train.n, t->batch,
         result.n_threads);
  if (sf_cli_stdout_written(command)) status = SF_ERR_INTERNAL;   /* the figures are this output */
  goto done;
fail:
  if (err.status == SF_OK) sf_fail(&err, SF_ERR_INTERNAL, "out of memory");
  fprintf(stderr, "%s: %s\n", command, err.message);
  status = err.status;
done:
  cJSON_Delete(doc);
  sf_mlp_free(&result.net);
  free(init);
  sf_dataset_free(&data);
  sf_dataset_free(&train);
  sf_dataset_free(&val);
  return status;
}
