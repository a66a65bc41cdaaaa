/* Whether training's small batches run split among threads or on one
 * (fit/train.h, SF_TRAIN_PARALLEL_WORK), decided by timing both ways.
 * Only the speed depends on the choice, never the result: a batch's
 * chunks are summed in a fixed order whoever computes them.
 *
 * A probe times 2 SF_TRAIN_PROBE_BATCHES batches, alternating (one thread
 * first); the batches after it run the way whose median was faster (the
 * median: a batch may be lucky or unlucky on a shared machine). A split
 * batch 3x slower than the one-thread batch before it ends the probe at
 * once on one thread: another process holds a core, and each split batch
 * then costs milliseconds. Not so the call's first split batch, which
 * starts the threads and meets their workspaces cold: it took 3x a
 * one-thread batch of the transmittance set, full or of 1024 samples, and
 * ended the first probe on one thread for SF_TRAIN_PROBE_EPOCHS epochs
 * (that set's batch-1024 epochs on 2 threads took 209-251 µs before this
 * exemption and 163-256 µs with it, 5 alternating runs each).
 *
 * Training probes every epoch of many batches. With few batches per epoch
 * (a full batch: one) it probes every `interval` epochs: after a clear-cut
 * probe (the loser's median at least 4/3 of the winner's) the interval
 * doubles, up to SF_TRAIN_PROBE_EPOCHS_MAX, else it goes back to
 * SF_TRAIN_PROBE_EPOCHS; and 3 epochs in a row whose batches took more
 * than twice the winner's median (the load changed) make the next epoch
 * probe. Each probe runs SF_TRAIN_PROBE_BATCHES batches the slower way:
 * probing every 50 epochs made full-batch epochs of the transmittance set
 * on 2 threads 8 % slower (75.4 against 69.6 µs, medians of 8 alternating
 * runs). */
#ifndef SKYFIT_FIT_THREAD_PROBE_H
#define SKYFIT_FIT_THREAD_PROBE_H

#define SF_TRAIN_PROBE_BATCHES 4
#define SF_TRAIN_PROBE_EPOCHS 50
#define SF_TRAIN_PROBE_EPOCHS_MAX 800

typedef struct sf_thread_probe {
  int n_threads;
  int threads;   /* the next batch's: 1 or n_threads */
  int active;
  int k;         /* batches of the probe timed so far */
  double seconds[2][SF_TRAIN_PROBE_BATCHES];   /* one thread, split */
  int start_epoch, interval, next_epoch;       /* in epochs of the call */
  double chosen_seconds;   /* the last probe's winning median; 0 before any */
  int slow_epochs;         /* in a row (sf_thread_probe_watch) */
} sf_thread_probe;

/* One thread until a probe says otherwise; the first probe at epoch 0. */
void sf_thread_probe_init(sf_thread_probe *p, int n_threads);
/* A probe from this epoch on; sets next_epoch (an epoch of few batches
 * starts one when it has reached next_epoch). */
void sf_thread_probe_start(sf_thread_probe *p, int epoch);
/* Before a batch: sets p->threads; 1 if the batch is to be timed and its
 * seconds given to sf_thread_probe_after. */
int sf_thread_probe_before(sf_thread_probe *p);
void sf_thread_probe_after(sf_thread_probe *p, double seconds);
/* After an epoch of n_batches that took seconds and was not probed. */
void sf_thread_probe_watch(sf_thread_probe *p, int epoch, long n_batches, double seconds);

#endif
