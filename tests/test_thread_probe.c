/* The split-or-one-thread choice of training's small batches
 * (fit/thread_probe.h) on made-up batch times:
 * - a probe alternates one thread and split, SF_TRAIN_PROBE_BATCHES
 *   batches each, and picks the faster median;
 * - the call's first split batch, slow because it starts the threads, does
 *   not end the probe; a later probe's 3x slower split batch does, on one
 *   thread;
 * - clear-cut probes double the interval between probes up to
 *   SF_TRAIN_PROBE_EPOCHS_MAX, a close one resets it;
 * - 3 slow epochs in a row (not 2, not 3 with a normal one between) make
 *   the next epoch probe. */
#include <stdio.h>

#include "check.h"
#include "fit/thread_probe.h"

/* A whole probe from epoch: one-thread batches take one, split ones split
 * (the first split batch first_split); returns the threads chosen. */
static int run_probe(sf_thread_probe *p, int epoch, double one, double split, double first_split) {
  sf_thread_probe_start(p, epoch);
  for (int k = 0; k < 2 * SF_TRAIN_PROBE_BATCHES; ++k) {
    if (!sf_thread_probe_before(p)) return p->threads;   /* ended early */
    CHECK(p->threads == (k % 2 ? p->n_threads : 1));
    sf_thread_probe_after(p, k % 2 ? (k == 1 ? first_split : split) : one);
  }
  CHECK(sf_thread_probe_before(p) == 0);   /* the decision, untimed */
  CHECK(!p->active);
  return p->threads;
}

int main(void) {
  sf_thread_probe p;
  sf_thread_probe_init(&p, 2);
  CHECK(p.threads == 1 && p.next_epoch == 0 && sf_thread_probe_before(&p) == 0);

  printf("-- the first probe: a cold first split batch (4x) does not end it\n");
  CHECK(run_probe(&p, 0, 120e-6, 65e-6, 480e-6) == 2);
  CHECK(p.chosen_seconds == 65e-6);
  CHECK(p.interval == 2 * SF_TRAIN_PROBE_EPOCHS && p.next_epoch == 2 * SF_TRAIN_PROBE_EPOCHS);

  printf("-- clear-cut probes double the interval up to the maximum\n");
  int epoch = p.next_epoch, expect = 2 * SF_TRAIN_PROBE_EPOCHS;
  for (int q = 0; q < 8; ++q) {
    CHECK(run_probe(&p, epoch, 120e-6, 65e-6, 65e-6) == 2);
    expect = 2 * expect <= SF_TRAIN_PROBE_EPOCHS_MAX ? 2 * expect : expect;
    CHECK(p.interval == expect && p.next_epoch == epoch + expect);
    epoch = p.next_epoch;
  }
  CHECK(p.interval == SF_TRAIN_PROBE_EPOCHS_MAX);

  printf("-- a close probe resets it, and picks the faster way\n");
  CHECK(run_probe(&p, epoch, 100e-6, 110e-6, 110e-6) == 1);
  CHECK(p.interval == SF_TRAIN_PROBE_EPOCHS && p.next_epoch == epoch + SF_TRAIN_PROBE_EPOCHS);

  printf("-- after the first probe, a 3x slower split batch ends a probe on one thread\n");
  epoch = p.next_epoch;
  CHECK(run_probe(&p, epoch, 100e-6, 50e-6, 400e-6) == 1);
  CHECK(!p.active && p.k == 2 && p.chosen_seconds == 100e-6);
  CHECK(p.next_epoch == epoch + SF_TRAIN_PROBE_EPOCHS);

  printf("-- slow epochs: 3 in a row probe the next epoch\n");
  sf_thread_probe_init(&p, 2);
  CHECK(run_probe(&p, 0, 120e-6, 65e-6, 65e-6) == 2);
  const int planned = p.next_epoch;
  const long batches = 16;
  const double normal = 70e-6 * batches, slow = 140e-6 * batches;   /* 2x65 us = 130 us per batch is the line */
  sf_thread_probe_watch(&p, 10, batches, slow);
  sf_thread_probe_watch(&p, 11, batches, slow);
  sf_thread_probe_watch(&p, 12, batches, normal);
  sf_thread_probe_watch(&p, 13, batches, slow);
  sf_thread_probe_watch(&p, 14, batches, slow);
  CHECK(p.next_epoch == planned);   /* never 3 in a row */
  sf_thread_probe_watch(&p, 15, batches, slow);
  CHECK(p.next_epoch == 16 && p.interval == SF_TRAIN_PROBE_EPOCHS);
  return check_summary();
}
