#include "fit/thread_probe.h"

#include <math.h>
#include <string.h>

#include "util/sort_doubles.h"

void sf_thread_probe_init(sf_thread_probe *p, int n_threads) {
  memset(p, 0, sizeof *p);
  p->n_threads = n_threads;
  p->threads = 1;
  p->interval = SF_TRAIN_PROBE_EPOCHS;
}

void sf_thread_probe_start(sf_thread_probe *p, int epoch) {
  p->active = 1;
  p->k = 0;
  p->start_epoch = epoch;
  p->next_epoch = epoch + p->interval;
}

int sf_thread_probe_before(sf_thread_probe *p) {
  if (!p->active) return 0;
  if (p->k < 2 * SF_TRAIN_PROBE_BATCHES) {
    p->threads = p->k % 2 ? p->n_threads : 1;
    return 1;
  }
  double one = sf_median_doubles(p->seconds[0], SF_TRAIN_PROBE_BATCHES);
  double split = sf_median_doubles(p->seconds[1], SF_TRAIN_PROBE_BATCHES);
  p->threads = split < one ? p->n_threads : 1;
  p->chosen_seconds = fmin(one, split);
  int clear_cut = 3.0 * fmax(one, split) >= 4.0 * fmin(one, split);
  if (!clear_cut) p->interval = SF_TRAIN_PROBE_EPOCHS;
  else if (2 * p->interval <= SF_TRAIN_PROBE_EPOCHS_MAX) p->interval *= 2;
  p->next_epoch = p->start_epoch + p->interval;
  p->active = 0;
  return 0;
}

void sf_thread_probe_after(sf_thread_probe *p, double seconds) {
  p->seconds[p->k % 2][p->k / 2] = seconds;
  int first_split = p->k == 1 && !(p->chosen_seconds > 0.0);
  if (p->k % 2 && !first_split && seconds > 3.0 * p->seconds[0][p->k / 2]) {
    p->threads = 1;
    p->active = 0;
    p->chosen_seconds = p->seconds[0][p->k / 2];
    p->interval = SF_TRAIN_PROBE_EPOCHS;
    p->next_epoch = p->start_epoch + p->interval;
  }
  p->k += 1;
}

void sf_thread_probe_watch(sf_thread_probe *p, int epoch, long n_batches, double seconds) {
  if (p->active || !(p->chosen_seconds > 0.0)) return;
  p->slow_epochs = seconds > 2.0 * p->chosen_seconds * (double)n_batches ? p->slow_epochs + 1 : 0;
  if (p->slow_epochs < 3) return;
  p->slow_epochs = 0;
  p->interval = SF_TRAIN_PROBE_EPOCHS;
  p->next_epoch = epoch + 1;
}
