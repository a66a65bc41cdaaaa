/* Training a network (SPEC §7.5): Xavier-initialised restarts, seeded
 * shuffled mini-batches, hand-written Adam (fit/adam.h), early stopping on
 * the validation loss, the best restart kept, checkpoints.
 *
 * Determinism: everything random is drawn from streams named by (seed,
 * restart, epoch) (models/rng.h), so nothing depends on what ran before; a
 * batch gradient is summed over fixed chunks of SF_TRAIN_CHUNK samples
 * (more in a large batch: sf_train_chunk_size), each chunk in sample order,
 * the chunk sums added in chunk order - the result is byte-identical for
 * any thread count. A full batch is not shuffled (its gradient is the same
 * sum in any order); a batch with little work runs split or on one thread,
 * whichever measured faster (parallel_work).
 *
 * Checkpoints: when *interrupt becomes nonzero (a SIGINT handler sets it) or
 * after stop_after_epochs epochs (for tests), training stops at the end of
 * the current epoch and writes everything the rest of the run depends on
 * (parameters, Adam moments and step, best-so-far networks and losses,
 * counters) to checkpoint_path; a run started with resume = 1 reads it and
 * continues to exactly the result of an uninterrupted run. */
#ifndef SKYFIT_FIT_TRAIN_H
#define SKYFIT_FIT_TRAIN_H

#include <signal.h>
#include <stdint.h>

#include "fit/adam.h"
#include "fit/dataset.h"
#include "fit/mlp_backward.h"
#include "models/mlp.h"

#define SF_TRAIN_CHUNK 256
/* A batch of more than SF_TRAIN_CHUNKS_MAX chunks of SF_TRAIN_CHUNK takes
 * chunks of twice the size, as often as needed (sf_train_chunk_size). Each
 * chunk ends by folding its gradient's 8 lanes per parameter into its sum
 * and zeroing them, and the chunks' sums are then added on one thread: in
 * chunks of 256 that was 3-4 % of a full-batch epoch of the 967,680-sample
 * scattering set on one thread and 12 % on two (bench/mlp_vs_torch.md).
 * The size depends on the batch alone, never on the threads, so the sums
 * stay the same for any thread count; 1024 chunks still share well among
 * many threads; every batch of up to 262,144 samples (the builds' 256 and
 * 1024 among them) keeps chunks of 256 and its bits. */
#define SF_TRAIN_CHUNKS_MAX 1024
/* Shuffled samples of the next pass whose rows a pass asks for early: as
 * far ahead as the kernel asks within a pass. */
#define SF_TRAIN_PREFETCH SF_MLP_PREFETCH_AHEAD
/* A batch is always split among threads when samples x parameters reaches
 * this. Below, splitting may cost more than it saves: measured on a shared
 * 2-core machine, a batch of 1024 samples of the 193-parameter scattering
 * network (~0.1 ms of work) split in 2 ran an epoch 40x SLOWER (6.7 s
 * instead of 0.17 s) whenever another process held the second core (every
 * fork/join then waits for the descheduled thread), and 1.3-1.9x faster
 * when the core was free. So batches below it are timed both ways and
 * run the way that was faster (fit/thread_probe.h): measured again at the
 * start of every epoch of more than 4 SF_TRAIN_PROBE_BATCHES batches, else
 * every few tens to hundreds of epochs (a full batch: the first epochs are
 * the probe). */
#define SF_TRAIN_PARALLEL_WORK 1048576.0

/* validation_loss is NAN without a validation set. */
typedef void (*sf_train_progress_fn)(void *ctx, int restart, int n_restarts, int epoch, int n_epochs,
                                     double train_loss, double validation_loss);

typedef struct sf_train_options {
  sf_mlp_shape shape;
  sf_mlp_loss_kind loss;
  double loss_floor;        /* rel/log: delta_k = loss_floor * max |y_k| of the training set */
  sf_adam_options adam;
  int epochs;               /* per restart */
  long batch;               /* samples per step; 0 = the whole training set */
  int restarts;             /* >= 1; the one with the lowest validation loss is kept */
  int first_restart;        /* >= 0: the restarts run are first_restart .. first_restart +
                               restarts - 1 (each its own streams, so restart r is the same
                               network whichever call trains it; skyfit build's restart after a
                               missed budget); default 0 */
  int patience;             /* epochs without a better validation loss before stopping; 0 = never */
  uint64_t seed;
  int n_threads;            /* <= 0: OpenMP's default */
  double parallel_work;     /* a batch (or the validation set) with at least this many samples x
                               parameters is split among the threads; a smaller training batch is
                               split if that measured faster, a smaller validation set runs on one
                               thread; 0: always split; default SF_TRAIN_PARALLEL_WORK */
  const double *init_params;   /* optional initial network of restart 0 (n_params values; only
                                  when first_restart is 0) */
  const char *checkpoint_path; /* NULL: no checkpoints */
  int resume;               /* continue from checkpoint_path */
  int keep_final_checkpoint;   /* at the end, the finished state to checkpoint_path instead of
                                  removing it: a step after training (the polish) may then be
                                  interrupted, and --resume runs no epoch again; the caller
                                  removes it */
  int stop_after_epochs;    /* > 0: behave as interrupted after this many epochs in this call */
  const volatile sig_atomic_t *interrupt;   /* may be NULL */
  sf_train_progress_fn progress;            /* may be NULL */
  void *progress_ctx;
} sf_train_options;

void sf_train_options_default(sf_train_options *o);

typedef struct sf_train_result {
  sf_mlp net;               /* the kept network (owned; sf_mlp_free) */
  double train_loss;        /* its loss on the whole training set */
  double validation_loss;   /* its loss on the validation set (NAN if none) */
  int best_restart, best_epoch;   /* where it came from (epochs 1-based) */
  int epochs_run;           /* over all restarts, this call and resumed ones */
  int epochs_this_call;     /* of those, run by this call */
  /* NAN when this call ran no epoch (a resumed run that had finished),
   * interrupted (see interrupted) or failed */
  double seconds_per_epoch; /* wall clock, in this call */
  double cpu_seconds_per_epoch;   /* process CPU time (all threads), in this call */
  int n_threads;                  /* worker threads used (o->n_threads, or all cores for 0) */
  int interrupted;          /* 1: stopped early, checkpoint written */
} sf_train_result;

/* Samples per chunk of a batch's gradient sum (SF_TRAIN_CHUNKS_MAX). */
long sf_train_chunk_size(long batch);

/* Xavier/Glorot-uniform weights U(-a, a), a = sqrt(6 / (fan_in + fan_out)),
 * zero biases, from the stream (seed, restart). */
void sf_mlp_init_xavier(const sf_mlp_shape *shape, uint64_t seed, int restart, double *params);

/* The rel/log losses' floors (fit/mlp_backward.h): delta[k] = loss_floor *
 * max |y_k| over train, at least 1e-300; delta holds train->n_out. */
void sf_train_loss_floors(const sf_dataset *train, double loss_floor, double *delta);

/* Trains on train, stopping early and choosing among restarts on validation
 * (NULL or empty: no early stopping, the last network of the best final
 * training loss is kept). */
int sf_mlp_train(const sf_dataset *train, const sf_dataset *validation, const sf_train_options *o,
                 sf_train_result *result, sf_error *err);

/* Loss of a network on a whole dataset (mean over samples), summed in fixed
 * chunks as in training. */
double sf_mlp_dataset_loss(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                           const sf_dataset *d, int n_threads);

#endif
