/* The options, progress line and Ctrl-C handling shared by `skyfit fit
 * mlp-transmittance | mlp-scattering | mlp` (SPEC §7.4-7.5, §11). */
#ifndef SKYFIT_CLI_CMD_FIT_MLP_OPTIONS_H
#define SKYFIT_CLI_CMD_FIT_MLP_OPTIONS_H

#include <signal.h>
#include <stdio.h>

#include "cli/progress_bar.h"
#include "fit/mlp_lm.h"
#include "fit/train.h"

typedef struct sf_mlp_cli {
  sf_train_options train;
  const char *layers;          /* NULL: the command's default */
  double validation_fraction;
  const char *out;             /* weights file */
  const char *checkpoint;      /* NULL: OUT.checkpoint */
  const char *init_weights;    /* initial network (a weights file) */
  const char *write_init;      /* write the seeded initial network and stop */
  int quiet;
  sf_mlp_lm_options polish;    /* --polish N, --polish-samples N (fit/mlp_lm.h) */
} sf_mlp_cli;

void sf_mlp_cli_default(sf_mlp_cli *o);
/* Consumes one shared option at argv[*i] (and its value): 1; not one: 0;
 * bad value: -1 after printing "<command>: <problem>". */
int sf_mlp_cli_option(sf_mlp_cli *o, const char *command, int argc, char **argv, int *i);
void sf_mlp_cli_help(FILE *out);
/* For --resume, before any long work: 0 if checkpoint (or other, when not
 * NULL) exists; else says so (or that there is no checkpoint path, when
 * checkpoint is NULL) and returns the exit code 2. */
int sf_mlp_cli_check_resume(const char *command, const char *checkpoint, const char *other);

/* Worker threads --threads takes at most. */
#define SF_MLP_CLI_MAX_THREADS 256

/* Before any long work (SPEC §11: a bad path exits 2 at once, nothing
 * written): --out and the checkpoint can be written; the checkpoint is
 * neither --out nor any of the inputs[0..n_inputs-1] (the files the run
 * reads; it had overwritten a --data CSV, and been deleted as --out after
 * the weights were written there); --patience has a validation set to
 * watch; the polish's normal equations fit in memory (fit/mlp_lm.h).
 * Says what is wrong and returns the exit code 2, else 0. */
int sf_mlp_cli_check_run(const char *command, const sf_mlp_cli *o, const char *checkpoint,
                         const char *const *inputs, int n_inputs);

/* The whole of text as a finite number in [lo, hi]: 0; else -1. */
int sf_mlp_cli_parse_double(const char *text, double lo, double hi, double *out);
/* The whole of text as an integer in [lo, hi]: 0; else -1. */
int sf_mlp_cli_parse_long(const char *text, long lo, long hi, long *out);

/* Levenberg-Marquardt polish of a trained network (fit/mlp_lm.h) with the
 * training loss (delta_k = loss_floor * max |y_k| of train, as fit/train.h);
 * then recomputes result->train_loss and validation_loss. Nothing when
 * o->polish.iterations is 0. Stops at o->train.interrupt (lm->interrupted:
 * the network is not to be written); a progress line unless o->quiet. */
int sf_mlp_cli_polish(const sf_mlp_cli *o, const sf_dataset *train, const sf_dataset *validation,
                      sf_train_result *result, sf_mlp_lm_result *lm, sf_error *err);

/* The progress line on a terminal: restart, epoch, train and validation
 * loss, ETA. */
typedef struct sf_mlp_progress {
  sf_progress_bar bar;
  double start, last;
  double done_before;   /* the share done before this call's first epoch (a resumed run); -1 until known */
} sf_mlp_progress;
void sf_mlp_progress_init(sf_mlp_progress *p, int quiet);
void sf_mlp_progress_update(void *ctx, int restart, int n_restarts, int epoch, int n_epochs, double train_loss,
                            double validation_loss);
void sf_mlp_progress_finish(sf_mlp_progress *p);
/* The polish's line: step, training and best validation loss, ETA
 * (sf_mlp_lm_progress_fn; ctx an sf_mlp_progress). */
void sf_mlp_progress_polish(void *ctx, int step, int n_steps, double train_loss, double validation_loss);

/* Installs a SIGINT, SIGTERM and SIGHUP handler (where the signal is not
 * ignored) that sets the returned flag (training then
 * stops after the epoch and writes its checkpoint; the polish stops before
 * its next step, and the trained state stays in the checkpoint). */
const volatile sig_atomic_t *sf_mlp_catch_interrupt(void);

/* Reads the initial network for --init-weights into params (n values), or
 * writes the seeded initial network of restart 0 for --write-init.
 * Returns an exit code (0 ok). */
int sf_mlp_cli_read_init(const char *command, const char *path, const sf_mlp_shape *shape, double *params);
int sf_mlp_cli_write_init(const char *command, const char *path, const sf_mlp_shape *shape, uint64_t seed);

#endif
