#include "cli/cmd_fit_mlp_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "fit/candidate_cache.h"
#include "models/atmosphere_file.h"
#include "models/weights_file.h"
#include "util/atomic_file.h"
#include "util/clock.h"
#include "util/memory_limit.h"

void sf_mlp_cli_default(sf_mlp_cli *o) {
  memset(o, 0, sizeof *o);
  sf_train_options_default(&o->train);
  o->validation_fraction = 0.1;
  sf_mlp_lm_options_default(&o->polish);
}

int sf_mlp_cli_parse_long(const char *text, long lo, long hi, long *out) {
  char *end;
  errno = 0;
  long v = strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || v < lo || v > hi) return -1;
  *out = v;
  return 0;
}

int sf_mlp_cli_parse_double(const char *text, double lo, double hi, double *out) {
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(v) || v < lo || v > hi) return -1;
  *out = v;
  return 0;
}

int sf_mlp_cli_option(sf_mlp_cli *o, const char *command, int argc, char **argv, int *i) {
  const char *a = argv[*i];
  if (strcmp(a, "--quiet") == 0) {
    o->quiet = 1;
    return 1;
  }
  if (strcmp(a, "--resume") == 0) {
    o->train.resume = 1;
    return 1;
  }
  static const char *const with_value[] = {"--layers", "--hidden", "--output", "--loss", "--loss-floor",
                                           "--epochs", "--batch", "--lr", "--lr-decay", "--restarts",
                                           "--patience", "--validation", "--seed", "--threads", "--out",
                                           "--checkpoint", "--init-weights", "--write-init",
                                           "--stop-after-epochs", "--stop-after-polish-steps", "--polish",
                                           "--polish-samples", NULL};
  int known = 0;
  for (int k = 0; with_value[k]; ++k) known |= strcmp(a, with_value[k]) == 0;
  if (!known) return 0;
  if (!sf_cli_value_after(argc, argv, *i)) {
    sf_cli_bad_option(command, a, a);
    return -1;
  }
  const char *v = argv[++*i];
  long n;
  double x;
  sf_train_options *t = &o->train;
  if (strcmp(a, "--layers") == 0) o->layers = v;
  else if (strcmp(a, "--out") == 0) o->out = v;
  else if (strcmp(a, "--checkpoint") == 0) o->checkpoint = v;
  else if (strcmp(a, "--init-weights") == 0) o->init_weights = v;
  else if (strcmp(a, "--write-init") == 0) o->write_init = v;
  else if (strcmp(a, "--hidden") == 0) {
    /* e^-x and e^-e^-x are output activations (their help and the emitters') */
    if (sf_mlp_activation_parse(v, &t->shape.hidden) || t->shape.hidden == SF_ACT_EXP_NEG ||
        t->shape.hidden == SF_ACT_EXP_NEG_EXP) {
      fprintf(stderr, "%s: --hidden: expected sigmoid, tanh, relu or linear, got '%s'\n", command, v);
      return -1;
    }
  } else if (strcmp(a, "--output") == 0) {
    if (sf_mlp_activation_parse(v, &t->shape.output)) {
      fprintf(stderr, "%s: --output: expected exp_neg, exp_neg_exp, sigmoid, linear, tanh or relu, got '%s'\n",
              command, v);
      return -1;
    }
  } else if (strcmp(a, "--loss") == 0) {
    if (sf_mlp_loss_parse(v, &t->loss)) {
      fprintf(stderr, "%s: --loss: expected mse, rel or log, got '%s'\n", command, v);
      return -1;
    }
  } else if (strcmp(a, "--loss-floor") == 0 || strcmp(a, "--lr") == 0 || strcmp(a, "--lr-decay") == 0 ||
             strcmp(a, "--validation") == 0) {
    int is_frac = strcmp(a, "--validation") == 0, is_decay = strcmp(a, "--lr-decay") == 0;
    double hi = is_frac ? 0.9 : is_decay ? 1.0 : 1e3;
    if (sf_mlp_cli_parse_double(v, is_frac ? 0.0 : 1e-300, hi, &x)) {
      fprintf(stderr, "%s: %s: expected %s, got '%s'\n", command, a,
              is_frac ? "a fraction in [0, 0.9]" : is_decay ? "a factor in (0, 1]" : "a positive number up to 1000",
              v);
      return -1;
    }
    if (strcmp(a, "--loss-floor") == 0) t->loss_floor = x;
    else if (strcmp(a, "--lr") == 0) t->adam.lr = x;
    else if (strcmp(a, "--lr-decay") == 0) t->adam.lr_decay_per_epoch = x;
    else o->validation_fraction = x;
  } else if (strcmp(a, "--seed") == 0) {
    char *end;
    errno = 0;
    unsigned long long s = strtoull(v, &end, 10);
    /* at most 2^53: the weights file records it as a JSON number (a double:
     * 2^53 + 1 had been recorded as 2^53, another run's seed) */
    if (end == v || *end != '\0' || errno == ERANGE || v[0] == '-' || s > (1ULL << 53)) {
      fprintf(stderr, "%s: --seed: expected a whole number in 0..2^53 (9007199254740992), got '%s'\n", command, v);
      return -1;
    }
    t->seed = (uint64_t)s;
  } else {
    long lo = strcmp(a, "--batch") == 0 || strcmp(a, "--patience") == 0 || strcmp(a, "--polish") == 0 ||
                      strcmp(a, "--polish-samples") == 0
                  ? 0
                  : 1;
    /* threads: each holds a workspace (10000 had taken 750 MB for a 2-8-2
     * network) */
    long hi = strcmp(a, "--threads") == 0 ? SF_MLP_CLI_MAX_THREADS : 1000000000L;
    if (sf_mlp_cli_parse_long(v, lo, hi, &n)) {
      fprintf(stderr, "%s: %s: expected a whole number in %ld..%ld, got '%s'\n", command, a, lo, hi, v);
      return -1;
    }
    if (strcmp(a, "--epochs") == 0) t->epochs = (int)n;
    else if (strcmp(a, "--batch") == 0) t->batch = n;
    else if (strcmp(a, "--restarts") == 0) t->restarts = (int)n;
    else if (strcmp(a, "--patience") == 0) t->patience = (int)n;
    else if (strcmp(a, "--threads") == 0) t->n_threads = (int)n;
    else if (strcmp(a, "--polish") == 0) o->polish.iterations = (int)n;
    else if (strcmp(a, "--polish-samples") == 0) o->polish.max_samples = n;
    else if (strcmp(a, "--stop-after-polish-steps") == 0) o->polish.stop_after_steps = (int)n;
    else t->stop_after_epochs = (int)n;
  }
  return 1;
}

int sf_mlp_cli_check_resume(const char *command, const char *checkpoint, const char *other) {
  if (!checkpoint) {
    fprintf(stderr, "%s: --resume needs --out or --checkpoint (the checkpoint to resume from)\n", command);
    return 2;
  }
  if (sf_cache_exists(checkpoint) || (other && sf_cache_exists(other))) return 0;
  fprintf(stderr, "%s: %s: --resume: no checkpoint to resume from\n", command, checkpoint);
  return 2;
}

int sf_mlp_cli_check_run(const char *command, const sf_mlp_cli *o, const char *checkpoint,
                         const char *const *inputs, int n_inputs) {
  if (o->out && sf_cli_check_output(command, "--out", o->out, inputs, n_inputs)) return 2;
  sf_error err = {0};
  if (checkpoint && sf_atomic_check(checkpoint, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return 2;
  }
  if (checkpoint && o->out && sf_cli_same_file(checkpoint, o->out)) {
    fprintf(stderr, "%s: --checkpoint %s: the same file as --out (the checkpoint goes once the weights are "
                    "written)\n", command, checkpoint);
    return 2;
  }
  for (int i = 0; checkpoint && i < n_inputs; ++i)
    if (inputs[i] && sf_cli_same_file(checkpoint, inputs[i])) {
      fprintf(stderr, "%s: --checkpoint %s: the same file as another of the run's files (%s)\n", command, checkpoint,
              inputs[i]);
      return 2;
    }
  if (o->train.patience > 0 && !(o->validation_fraction > 0.0)) {
    fprintf(stderr, "%s: --patience %d: early stopping watches the validation loss; give --validation F\n",
            command, o->train.patience);
    return 2;
  }
  if (o->polish.iterations > 0) {
    char source[256];
    size_t need = sf_mlp_lm_bytes(&o->train.shape, o->train.n_threads);
    size_t limit = sf_memory_limit_bytes(source, sizeof source);
    if (need > limit) {
      fprintf(stderr, "%s: --polish %d: a network of %d parameters needs %.3g GB for the polish's normal "
                      "equations, more than the %.3g GB available (%s); --polish 0 skips it\n",
              command, o->polish.iterations, sf_mlp_param_count(&o->train.shape), need / 1e9, limit / 1e9, source);
      return 2;
    }
  }
  return 0;
}

void sf_mlp_cli_help(FILE *out) {
  fprintf(out,
          "training options:\n"
          "  --layers A,B,...        layer sizes, inputs first, outputs last\n"
          "  --hidden ACT            hidden activation: sigmoid, tanh, relu, linear\n"
          "  --output ACT            output activation: exp_neg (e^-x), exp_neg_exp (e^-e^-x), sigmoid,\n"
          "                          linear, tanh, relu\n"
          "  --loss mse|rel|log      loss (rel/log: floor F * max|target| per output)\n"
          "  --loss-floor F          default 1e-4\n"
          "  --epochs N              epochs per restart\n"
          "  --batch N               mini-batch size (0: the whole training set)\n"
          "  --lr X, --lr-decay D    Adam learning rate, times D each epoch (defaults above)\n"
          "  --restarts N            independent restarts; the best validation loss is kept (the best\n"
          "                          training loss without a validation set)\n"
          "  --patience N            early stopping after N epochs without a better validation loss\n"
          "                          (needs a validation set)\n"
          "  --validation F          held-out fraction (default 0.1; fit mlp: 0)\n"
          "  --seed S                seed of initialisation, split and shuffling (default 1)\n"
          "  --threads N             worker threads, at most 256 (default: all cores); results do not\n"
          "                          depend on it\n"
          "  --out W.json            weights file (SPEC §8)\n"
          "  --checkpoint FILE       Ctrl-C saves here (default W.json.checkpoint)\n"
          "  --resume                continue from the checkpoint to the uninterrupted result\n"
          "  --init-weights W.json   start restart 0 from this network (same layers)\n"
          "  --write-init W.json     write the seeded initial network and stop\n"
          "  --polish N              N Levenberg-Marquardt steps after Adam (fit/mlp_lm.h; 0: none)\n"
          "  --polish-samples N      training samples used by the polish (0: all)\n"
          "  --stop-after-epochs K   behave as if interrupted after K epochs (tests)\n"
          "  --stop-after-polish-steps K  the same after K polish steps (tests)\n"
          "  --quiet                 no progress line, notes or summary (errors are still reported)\n"
          "  --help                  this text\n");
}

int sf_mlp_cli_polish(const sf_mlp_cli *o, const sf_dataset *train, const sf_dataset *validation,
                      sf_train_result *result, sf_mlp_lm_result *lm, sf_error *err) {
  memset(lm, 0, sizeof *lm);
  if (o->polish.iterations <= 0) return SF_OK;
  const sf_train_options *t = &o->train;
  double delta[SF_MLP_MAX_WIDTH];
  sf_train_loss_floors(train, t->loss_floor, delta);
  sf_mlp_loss loss = {t->loss, delta};
  sf_mlp_lm_options polish = o->polish;
  polish.n_threads = t->n_threads;
  polish.interrupt = t->interrupt;
  sf_mlp_progress progress;
  sf_mlp_progress_init(&progress, o->quiet);
  polish.progress = sf_mlp_progress_polish;
  polish.progress_ctx = &progress;
  int status = sf_mlp_lm_polish(&t->shape, result->net.params, &loss, train, validation, &polish, lm, err);
  sf_mlp_progress_finish(&progress);
  if (status || lm->interrupted) return status;
  result->train_loss = sf_mlp_dataset_loss(&t->shape, result->net.params, &loss, train, t->n_threads);
  if (validation && validation->n > 0)
    result->validation_loss = sf_mlp_dataset_loss(&t->shape, result->net.params, &loss, validation, t->n_threads);
  return SF_OK;
}

void sf_mlp_progress_init(sf_mlp_progress *p, int quiet) {
  sf_progress_bar_init(&p->bar, stderr, !quiet);
  p->start = sf_wall_seconds();
  p->last = 0.0;
  p->done_before = -1.0;
}

/* Whether to draw now (at most every 0.1 s, and the last step); sets *now. */
static int progress_due(sf_mlp_progress *p, int last_step, double *now) {
  if (!p->bar.enabled) return 0;
  *now = sf_wall_seconds();
  if (*now - p->last < 0.1 && !last_step) return 0;
  p->last = *now;
  return 1;
}

/* "  validation L", or nothing without a validation set (loss NAN). */
static void validation_text(double validation_loss, char *text, size_t size) {
  text[0] = '\0';
  if (!isnan(validation_loss)) snprintf(text, size, "  validation %.4g", validation_loss);
}

void sf_mlp_progress_update(void *ctx, int restart, int n_restarts, int epoch, int n_epochs, double train_loss,
                            double validation_loss) {
  sf_mlp_progress *p = ctx;
  double t;
  if (!progress_due(p, epoch == n_epochs, &t)) return;
  double done = ((double)restart * n_epochs + epoch) / ((double)n_restarts * n_epochs);
  /* what this call has done: a resumed run starts part way (its ETA had
   * counted the epochs before the interruption as done in no time) */
  if (p->done_before < 0.0) p->done_before = ((double)restart * n_epochs + epoch - 1) / ((double)n_restarts * n_epochs);
  double elapsed = t - p->start, done_here = done - p->done_before;
  char validation[48];
  validation_text(validation_loss, validation, sizeof validation);
  fprintf(stderr, "\r  restart %d/%d  epoch %d/%d  train %.4g%s  ETA %.0f s   ", restart + 1, n_restarts, epoch,
          n_epochs, train_loss, validation, done_here > 0.0 ? elapsed * (1.0 - done) / done_here : 0.0);
  fflush(stderr);
  p->bar.drawn = 1;
}

void sf_mlp_progress_polish(void *ctx, int step, int n_steps, double train_loss, double validation_loss) {
  sf_mlp_progress *p = ctx;
  double t;
  if (!progress_due(p, step == n_steps, &t)) return;
  char validation[48];
  validation_text(validation_loss, validation, sizeof validation);
  /* the ETA if every step is taken (the polish may stop earlier) */
  fprintf(stderr, "\r  polish step %d/%d  train %.4g%s  ETA %.0f s   ", step, n_steps, train_loss, validation,
          (t - p->start) * (n_steps - step) / step);
  fflush(stderr);
  p->bar.drawn = 1;
}

void sf_mlp_progress_finish(sf_mlp_progress *p) { sf_progress_bar_finish(&p->bar); }

/* The one piece of process-wide state: a signal handler can reach nothing else. */
static volatile sig_atomic_t interrupted_flag = 0;

static void on_interrupt(int sig) {
  (void)sig;
  interrupted_flag = 1;
}

const volatile sig_atomic_t *sf_mlp_catch_interrupt(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  /* SIGTERM and SIGHUP too (a `timeout`, a closed terminal): they had
   * ended the training with nothing kept. One the process ignores (nohup's
   * SIGHUP) stays ignored. */
  const int stops[] = {SIGINT, SIGTERM, SIGHUP};
  for (int i = 0; i < 3; ++i) {
    struct sigaction was;
    if (sigaction(stops[i], NULL, &was) == 0 && was.sa_handler != SIG_IGN) sigaction(stops[i], &sa, NULL);
  }
  return &interrupted_flag;
}

int sf_mlp_cli_read_init(const char *command, const char *path, const sf_mlp_shape *shape, double *params) {
  sf_weights w;
  sf_error err = {0};
  if (sf_weights_load_file(path, NULL, &w, &err)) {
    fprintf(stderr, "%s: --init-weights: %s\n", command, err.message);
    return err.status ? err.status : 2;
  }
  sf_mlp net;
  int status = sf_mlp_from_weights(&w, &net, &err);
  sf_weights_free(&w);
  if (status) {
    fprintf(stderr, "%s: --init-weights: %s\n", command, err.message);
    return status;
  }
  int same = net.shape.n_layers == shape->n_layers;
  for (int l = 0; same && l <= shape->n_layers; ++l) same = net.shape.sizes[l] == shape->sizes[l];
  if (!same) {
    fprintf(stderr, "%s: --init-weights: %s: its layers differ from --layers\n", command, path);
    sf_mlp_free(&net);
    return 2;
  }
  memcpy(params, net.params, (size_t)net.n_params * sizeof(double));
  sf_mlp_free(&net);
  return 0;
}

int sf_mlp_cli_write_init(const char *command, const char *path, const sf_mlp_shape *shape, uint64_t seed) {
  sf_mlp net;
  if (sf_mlp_init(&net, shape)) return 1;
  sf_mlp_init_xavier(shape, seed, 0, net.params);
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  sf_scene_domain dom = {0, 0, -1, 1, -1, 1};
  cJSON *doc = sf_weights_new("mlp", "values", &atm, &dom);
  for (int k = 0; k < shape->sizes[0]; ++k) {
    char name[16];
    snprintf(name, sizeof name, "x%d", k);
    sf_weights_add_input(doc, name, 0.0, 1.0);
  }
  sf_error err = {0};
  int status = 0;
  if (!doc || sf_mlp_add_to_weights(doc, &net)) status = 1;
  else {
    cJSON_AddNumberToObject(sf_weights_training(doc), "seed", (double)seed);
    cJSON_AddStringToObject(sf_weights_training(doc), "note", "initial network (Xavier-uniform, restart 0)");
    if (sf_weights_write(doc, path, &err)) {
      fprintf(stderr, "%s: --write-init: %s\n", command, err.message);
      status = err.status ? err.status : 1;
    }
  }
  cJSON_Delete(doc);
  sf_mlp_free(&net);
  return status;
}
