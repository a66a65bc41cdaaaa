#include "fit/train.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <omp.h>

#include "fit/thread_probe.h"
#include "models/rng.h"
#include "util/atomic_file.h"
#include "util/clock.h"
#include "util/hash64.h"

/* rng stream keys of this file */
#define INIT_KEY 0x696e6974ull      /* "init" */
#define SHUFFLE_KEY 0x73687566ull   /* "shuf" */
#define CHECKPOINT_MAGIC "SKYFIT-MLP-CHECKPOINT 2\n"

void sf_train_options_default(sf_train_options *o) {
  memset(o, 0, sizeof *o);
  o->loss = SF_LOSS_MSE;
  o->loss_floor = 1e-4;
  sf_adam_options_default(&o->adam);
  o->epochs = 200;
  o->batch = 1024;
  o->restarts = 1;
  o->patience = 0;
  o->seed = 1;
  o->parallel_work = SF_TRAIN_PARALLEL_WORK;
}

void sf_mlp_init_xavier(const sf_mlp_shape *s, uint64_t seed, int restart, double *params) {
  sf_rng rng;
  sf_rng_seed(&rng, seed, INIT_KEY, (uint64_t)restart);
  for (int l = 0; l < s->n_layers; ++l) {
    int ni = s->sizes[l], no = s->sizes[l + 1];
    double a = sqrt(6.0 / (double)(ni + no));
    double *W = params + sf_mlp_weight_offset(s, l), *b = params + sf_mlp_bias_offset(s, l);
    for (int k = 0; k < ni * no; ++k) W[k] = a * (2.0 * sf_rng_uniform(&rng) - 1.0);
    for (int k = 0; k < no; ++k) b[k] = 0.0;
  }
}

/* Scratch for chunked sums: one gradient and one loss per chunk, and one
 * block workspace per thread (fit/mlp_backward.h). */
typedef struct chunk_sums {
  long chunk;   /* samples per chunk */
  long n_chunks;
  int n_params;
  int n_threads;
  double parallel_work;   /* sf_train_options.parallel_work */
  int small_threads;      /* threads for a batch below parallel_work: 1, or n_threads if measured faster */
  double *grad;   /* n_chunks x n_params */
  double *loss;   /* n_chunks */
  sf_mlp_workspace *ws;   /* n_threads */
} chunk_sums;

static int thread_count(int n_threads) { return n_threads > 0 ? n_threads : omp_get_max_threads(); }

long sf_train_chunk_size(long batch) {
  long chunk = SF_TRAIN_CHUNK;
  while ((batch + chunk - 1) / chunk > SF_TRAIN_CHUNKS_MAX) chunk *= 2;
  return chunk;
}

static int chunk_sums_init(chunk_sums *c, const sf_mlp_shape *s, long max_samples, long chunk, int n_params,
                           int n_threads) {
  memset(c, 0, sizeof *c);
  c->chunk = chunk;
  c->n_chunks = (max_samples + chunk - 1) / chunk;
  if (c->n_chunks < 1) c->n_chunks = 1;
  c->n_params = n_params;
  c->parallel_work = SF_TRAIN_PARALLEL_WORK;
  c->small_threads = 1;
  c->grad = malloc((size_t)c->n_chunks * (size_t)n_params * sizeof(double));
  c->loss = malloc((size_t)c->n_chunks * sizeof(double));
  c->ws = calloc((size_t)n_threads, sizeof *c->ws);
  if (!c->grad || !c->loss || !c->ws) return -1;
  c->n_threads = n_threads;
  for (int t = 0; t < n_threads; ++t)
    if (sf_mlp_workspace_init(&c->ws[t], s)) return -1;
  return 0;
}

static void chunk_sums_free(chunk_sums *c) {
  free(c->grad);
  free(c->loss);
  for (int t = 0; c->ws && t < c->n_threads; ++t) sf_mlp_workspace_free(&c->ws[t]);
  free(c->ws);
}

/* Sum of the loss (and, if grad, of its gradient) over samples
 * index[begin..end-1] (index NULL: begin..end-1, read from columns or rows
 * when given: the same sums), in fixed chunks added in chunk order. */
static double chunked_loss(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                           const sf_dataset *d, const sf_mlp_columns *columns, const sf_mlp_rows *rows,
                           const int *index, long begin, long end, double *grad, chunk_sums *cs) {
  long n = end - begin, chunk = cs->chunk;
  long n_chunks = (n + chunk - 1) / chunk;
  int np = cs->n_params;
  int threads = cs->n_threads;
  if (threads > n_chunks) threads = (int)(n_chunks > 0 ? n_chunks : 1);
  /* Starting and joining threads costs microseconds (much more on a loaded
   * machine, where a descheduled thread holds up the join): a small batch
   * of a small network may be faster on one (fit/train.h). The chunks,
   * hence the result, are the same. */
  if ((double)n * (double)sf_mlp_param_count(s) < cs->parallel_work && cs->small_threads < threads)
    threads = cs->small_threads;
  /* Dynamic: a thread slowed by another process (a shared machine) takes
   * fewer chunks; each chunk's sums are stored apart and added in chunk
   * order below, so the result does not depend on who computed what. A
   * thread takes a run of up to 8 chunks at a time, a small batch (fewer
   * than 4 chunks per thread) one run per thread, and one thread all of
   * them; a run is one pass of the kernel (the same sums as a pass per
   * chunk, fit/mlp_backward.h), whose shuffled rows' prefetches run on
   * into the next run's first group (the next batch's, after the last).
   * A run's first group waits on its rows: in a batch of 1024 samples on 2
   * threads, runs of 2 chunks instead of 1 made an epoch of the scattering
   * set 3-4 % faster (33.0-33.6 ms against 34.4-34.6, two runs each). */
  long grab = n_chunks;
  if (threads > 1 && n_chunks < 4L * threads) grab = (n_chunks + threads - 1) / threads;
  else if (threads > 1) grab = n_chunks / (2L * threads) < 8 ? n_chunks / (2L * threads) : 8;
  if (grab < 1) grab = 1;
  long n_runs = (n_chunks + grab - 1) / grab;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1)
  for (long run = 0; run < n_runs; ++run) {
    long c = run * grab, count = c + grab < n_chunks ? grab : n_chunks - c;
    long b = begin + c * chunk;
    long e = b + count * chunk < end ? b + count * chunk : end;
    long prefetch_end = index ? (e + SF_TRAIN_PREFETCH < d->n ? e + SF_TRAIN_PREFETCH : d->n) : 0;
    double *g = grad ? cs->grad + c * np : NULL;
    if (g) memset(g, 0, (size_t)(count * np) * sizeof(double));
    sf_mlp_loss_chunks_ws(s, params, loss, columns, rows, d->x, d->y, index, b, e, chunk, prefetch_end,
                          cs->loss + c, g, &cs->ws[omp_get_thread_num()]);
  }
  double total = 0.0;
  if (grad) memset(grad, 0, (size_t)np * sizeof(double));
  for (long c = 0; c < n_chunks; ++c) {
    total += cs->loss[c];
    if (grad) {
      const double *g = cs->grad + c * np;
      for (int k = 0; k < np; ++k) grad[k] += g[k];
    }
  }
  return total;
}

double sf_mlp_dataset_loss(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                           const sf_dataset *d, int n_threads) {
  if (d->n <= 0) return NAN;
  chunk_sums cs;
  if (chunk_sums_init(&cs, s, d->n, SF_TRAIN_CHUNK, 1, thread_count(n_threads))) {
    chunk_sums_free(&cs);
    return NAN;
  }
  double total = chunked_loss(s, params, loss, d, NULL, NULL, NULL, 0, d->n, NULL, &cs);
  chunk_sums_free(&cs);
  return total / (double)d->n;
}

/* Everything the rest of a run depends on (what a checkpoint holds). */
typedef struct train_state {
  int restart, epoch;            /* next epoch to run, 0-based within the restart */
  int since_best;                /* epochs since the restart's best */
  int epochs_run;
  double best_restart_loss;      /* criterion of the restart's kept network */
  int best_restart_epoch;
  double best_loss;              /* over finished restarts */
  int best_restart, best_epoch;
  double *params, *restart_best, *overall_best;
  sf_adam adam;
} train_state;

static uint64_t run_fingerprint(const sf_dataset *train, const sf_dataset *val, const sf_train_options *o) {
  uint64_t h = SF_FNV1A64_OFFSET;
  h = sf_fnv1a64(h, &o->shape, sizeof o->shape);
  h = sf_fnv1a64(h, &o->loss, sizeof o->loss);
  h = sf_fnv1a64(h, &o->loss_floor, sizeof o->loss_floor);
  h = sf_fnv1a64(h, &o->adam, sizeof o->adam);
  h = sf_fnv1a64(h, &o->epochs, sizeof o->epochs);
  h = sf_fnv1a64(h, &o->batch, sizeof o->batch);
  h = sf_fnv1a64(h, &o->restarts, sizeof o->restarts);
  if (o->first_restart) h = sf_fnv1a64(h, &o->first_restart, sizeof o->first_restart);
  h = sf_fnv1a64(h, &o->patience, sizeof o->patience);
  h = sf_fnv1a64(h, &o->seed, sizeof o->seed);
  const sf_dataset *sets[2] = {train, val};
  for (int k = 0; k < 2; ++k) {
    if (!sets[k] || sets[k]->n <= 0) continue;
    h = sf_fnv1a64(h, &sets[k]->n, sizeof sets[k]->n);
    h = sf_fnv1a64(h, sets[k]->x, (size_t)sets[k]->n * (size_t)sets[k]->n_in * sizeof(double));
    h = sf_fnv1a64(h, sets[k]->y, (size_t)sets[k]->n * (size_t)sets[k]->n_out * sizeof(double));
  }
  if (o->init_params)
    h = sf_fnv1a64(h, o->init_params, (size_t)sf_mlp_param_count(&o->shape) * sizeof(double));
  return h;
}

/* Binary, native byte order (a checkpoint resumes on the machine that wrote
 * it), ending in the FNV-1a hash of everything after the magic: a damaged
 * checkpoint had resumed into 2 billion epochs, a false "diverged" or other
 * weights, each silently. put/get write or read n bytes and hash them. */
static void put(FILE *out, uint64_t *hash, const void *bytes, size_t n) {
  fwrite(bytes, 1, n, out);
  *hash = sf_fnv1a64(*hash, bytes, n);
}

static int get(FILE *in, uint64_t *hash, void *bytes, size_t n) {
  if (fread(bytes, 1, n, in) != n) return 0;
  *hash = sf_fnv1a64(*hash, bytes, n);
  return 1;
}

static int write_checkpoint(const char *path, uint64_t fingerprint, const train_state *st, int np,
                            sf_error *err) {
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err)) return err->status;
  FILE *out = f.stream;
  uint64_t hash = SF_FNV1A64_OFFSET;
  fwrite(CHECKPOINT_MAGIC, 1, strlen(CHECKPOINT_MAGIC), out);
  put(out, &hash, &fingerprint, sizeof fingerprint);
  int ints[7] = {st->restart, st->epoch, st->since_best, st->epochs_run, st->best_restart_epoch,
                 st->best_restart, st->best_epoch};
  put(out, &hash, ints, sizeof ints);
  put(out, &hash, &st->adam.step, sizeof st->adam.step);
  double losses[2] = {st->best_restart_loss, st->best_loss};
  put(out, &hash, losses, sizeof losses);
  const double *arrays[5] = {st->params, st->restart_best, st->overall_best, st->adam.m, st->adam.v};
  for (int k = 0; k < 5; ++k) put(out, &hash, arrays[k], sizeof(double) * (size_t)np);
  fwrite(&hash, sizeof hash, 1, out);
  if (ferror(out)) {
    sf_atomic_abort(&f);
    return sf_fail(err, SF_ERR_INPUT, "%s: cannot write the checkpoint", path);
  }
  return sf_atomic_commit(&f, err);
}

static int read_checkpoint(const char *path, uint64_t fingerprint, train_state *st, int np, sf_error *err) {
  FILE *in = fopen(path, "rb");
  if (!in) return sf_fail(err, SF_ERR_INPUT, "%s: --resume: no checkpoint to resume from", path);
  char magic[sizeof CHECKPOINT_MAGIC];
  uint64_t fp = 0, hash = SF_FNV1A64_OFFSET, stored = 0;
  int ints[7];
  double losses[2];
  int ok = fread(magic, 1, strlen(CHECKPOINT_MAGIC), in) == strlen(CHECKPOINT_MAGIC) &&
           memcmp(magic, CHECKPOINT_MAGIC, strlen(CHECKPOINT_MAGIC)) == 0 && get(in, &hash, &fp, sizeof fp);
  if (!ok) {
    fclose(in);
    return sf_fail(err, SF_ERR_INPUT, "%s: not a skyfit MLP checkpoint (or one of an older skyfit)", path);
  }
  if (fp != fingerprint) {
    fclose(in);
    return sf_fail(err, SF_ERR_INPUT,
                   "%s: the checkpoint belongs to another run (different data, network or options)", path);
  }
  ok = get(in, &hash, ints, sizeof ints) && get(in, &hash, &st->adam.step, sizeof st->adam.step) &&
       get(in, &hash, losses, sizeof losses);
  double *arrays[5] = {st->params, st->restart_best, st->overall_best, st->adam.m, st->adam.v};
  for (int k = 0; k < 5 && ok; ++k) ok = get(in, &hash, arrays[k], sizeof(double) * (size_t)np);
  ok = ok && fread(&stored, sizeof stored, 1, in) == 1;
  int extra = ok && fgetc(in) != EOF;
  fclose(in);
  if (!ok) return sf_fail(err, SF_ERR_INPUT, "%s: checkpoint is truncated", path);
  if (extra || stored != hash)
    return sf_fail(err, SF_ERR_INPUT, "%s: checkpoint is corrupt (its checksum does not match); remove it and "
                   "train from the start", path);
  st->restart = ints[0];
  st->epoch = ints[1];
  st->since_best = ints[2];
  st->epochs_run = ints[3];
  st->best_restart_epoch = ints[4];
  st->best_restart = ints[5];
  st->best_epoch = ints[6];
  st->best_restart_loss = losses[0];
  st->best_loss = losses[1];
  return SF_OK;
}

static void start_restart(train_state *st, const sf_train_options *o, int np) {
  if (st->restart == 0 && o->init_params)
    memcpy(st->params, o->init_params, (size_t)np * sizeof(double));
  else
    sf_mlp_init_xavier(&o->shape, o->seed, st->restart, st->params);
  sf_adam_reset(&st->adam);
  st->epoch = 0;
  st->since_best = 0;
  st->best_restart_loss = INFINITY;
  st->best_restart_epoch = 0;
}

void sf_train_loss_floors(const sf_dataset *train, double loss_floor, double *delta) {
  for (int k = 0; k < train->n_out; ++k) {
    double m = 0.0;
    for (long i = 0; i < train->n; ++i) m = fmax(m, fabs(train->y[i * train->n_out + k]));
    delta[k] = loss_floor * m > 1e-300 ? loss_floor * m : 1e-300;
  }
}

/* Targets the loss can measure (SF_ERR_INPUT naming the column otherwise;
 * they had ended as "training diverged in every restart"): rel and log
 * measure against the target, so a column that is 0 everywhere has no
 * scale (its floor is the least, 1e-300); log takes log(target + floor),
 * undefined at or below -floor. */
static int check_targets(const sf_dataset *train, const sf_dataset *val, sf_mlp_loss_kind kind, const double *delta,
                         sf_error *err) {
  /* Squared errors of targets near 1e154 overflow at the first epoch: that
   * had been reported as divergence, with "try a smaller --lr". */
  for (int k = 0; kind == SF_LOSS_MSE && k < train->n_out; ++k) {
    double m = 0.0;
    for (long i = 0; i < train->n; ++i) m = fmax(m, fabs(train->y[i * train->n_out + k]));
    if (!isfinite(m * m * (double)train->n))
      return sf_fail(err, SF_ERR_INPUT,
                     "target column '%s' reaches %.3g: its squared errors overflow double over %ld samples; "
                     "scale the targets, or use --loss log or rel",
                     train->names[train->n_in + k], m, train->n);
  }
  if (kind == SF_LOSS_MSE) return SF_OK;
  const char *name = kind == SF_LOSS_REL ? "rel" : "log";
  for (int k = 0; k < train->n_out; ++k) {
    const char *column = train->names[train->n_in + k];
    if (!(delta[k] > 1e-300))
      return sf_fail(err, SF_ERR_INPUT,
                     "target column '%s' is 0 throughout: --loss %s measures errors relative to the target; "
                     "use --loss mse",
                     column, name);
    for (int part = 0; kind == SF_LOSS_LOG && part < 2; ++part) {
      const sf_dataset *d = part == 0 ? train : val;
      for (long i = 0; d && i < d->n; ++i)
        if (!(d->y[i * d->n_out + k] + delta[k] > 0.0))
          return sf_fail(err, SF_ERR_INPUT,
                         "target column '%s' holds %.6g: --loss log takes log(target + %.3g), defined for "
                         "targets above -%.3g; use --loss mse or rel",
                         column, d->y[i * d->n_out + k], delta[k], delta[k]);
    }
  }
  return SF_OK;
}

int sf_mlp_train(const sf_dataset *train, const sf_dataset *val, const sf_train_options *o,
                 sf_train_result *result, sf_error *err) {
  memset(result, 0, sizeof *result);
  int epochs_this_call = 0;
  const sf_mlp_shape *s = &o->shape;
  if (train->n_in != s->sizes[0] || train->n_out != s->sizes[s->n_layers])
    return sf_fail(err, SF_ERR_INPUT, "--layers: the data have %d inputs and %d targets, the network %d and %d",
                   train->n_in, train->n_out, s->sizes[0], s->sizes[s->n_layers]);
  if (train->n <= 0) return sf_fail(err, SF_ERR_INPUT, "no training samples");
  if (o->epochs < 1 || o->restarts < 1) return sf_fail(err, SF_ERR_INPUT, "epochs and restarts must be >= 1");
  if (o->first_restart < 0 || o->first_restart > INT_MAX - o->restarts)
    return sf_fail(err, SF_ERR_INPUT, "the first restart must be >= 0 and leave room for %d restart(s)", o->restarts);
  const int end_restart = o->first_restart + o->restarts;
  int has_val = val && val->n > 0;
  /* a validation fraction of a few rows that rounds to none had left
   * --patience silently unused */
  if (o->patience > 0 && !has_val)
    return sf_fail(err, SF_ERR_INPUT,
                   "--patience %d: early stopping watches the validation loss, and the validation set is empty "
                   "(%ld training rows; a larger --validation fraction or more data)",
                   o->patience, train->n);
  int np = sf_mlp_param_count(s);
  long batch = o->batch > 0 && o->batch < train->n ? o->batch : train->n;

  double *delta = malloc((size_t)train->n_out * sizeof(double));
  double *grad = malloc((size_t)np * sizeof(double));
  int *perm = malloc((size_t)train->n * sizeof(int));
  train_state st;
  memset(&st, 0, sizeof st);
  st.params = malloc((size_t)np * sizeof(double));
  st.restart_best = malloc((size_t)np * sizeof(double));
  st.overall_best = malloc((size_t)np * sizeof(double));
  chunk_sums cs, val_cs;
  memset(&cs, 0, sizeof cs);
  memset(&val_cs, 0, sizeof val_cs);
  /* Unit-major copies for the passes over contiguous samples: the full
   * batch (not shuffled) and the validation set, read every epoch. */
  sf_mlp_columns train_columns, val_columns;
  memset(&train_columns, 0, sizeof train_columns);
  memset(&val_columns, 0, sizeof val_columns);
  /* A packed copy for the shuffled mini-batches (fewer lines per row). */
  sf_mlp_rows train_rows;
  memset(&train_rows, 0, sizeof train_rows);
  int status = SF_OK;
  if (!delta || !grad || !perm || !st.params || !st.restart_best || !st.overall_best ||
      sf_adam_init(&st.adam, np) ||
      chunk_sums_init(&cs, s, batch, sf_train_chunk_size(batch), np, thread_count(o->n_threads)) ||
      (has_val && chunk_sums_init(&val_cs, s, val->n, SF_TRAIN_CHUNK, 1, thread_count(o->n_threads))) ||
      (batch >= train->n && sf_mlp_columns_make(&train_columns, train->x, train->y, train->n, train->n_in, train->n_out)) ||
      (batch < train->n && sf_mlp_rows_make(&train_rows, train->x, train->y, train->n, train->n_in, train->n_out)) ||
      (has_val && sf_mlp_columns_make(&val_columns, val->x, val->y, val->n, val->n_in, val->n_out)) ||
      sf_mlp_init(&result->net, s)) {
    status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
    goto done;
  }
  cs.parallel_work = val_cs.parallel_work = o->parallel_work;
  sf_train_loss_floors(train, o->loss_floor, delta);
  if ((status = check_targets(train, has_val ? val : NULL, o->loss, delta, err)) != SF_OK) goto done;
  result->n_threads = thread_count(o->n_threads);
  sf_mlp_loss loss = {o->loss, delta};
  /* Hashing the data costs about a second per 100 MB: only checkpoints need it. */
  uint64_t fingerprint = o->checkpoint_path ? run_fingerprint(train, val, o) : 0;

  st.best_loss = INFINITY;
  st.best_restart = o->first_restart;
  if (o->resume) {
    if (!o->checkpoint_path) {
      status = sf_fail(err, SF_ERR_INPUT, "--resume: no checkpoint file");
      goto done;
    }
    if ((status = read_checkpoint(o->checkpoint_path, fingerprint, &st, np, err)) != SF_OK) goto done;
  } else {
    st.restart = o->first_restart;
    start_restart(&st, o, np);
  }

  /* Batches below parallel_work: split or one thread, as measured. */
  sf_thread_probe probe;
  sf_thread_probe_init(&probe, cs.n_threads);
  int measure_threads = cs.n_threads > 1 && (double)batch * np < cs.parallel_work;
  long batches_per_epoch = (train->n + batch - 1) / batch;

  double t_start = sf_wall_seconds();
  clock_t cpu_start = clock();
  while (st.restart < end_restart) {
    int stop_restart = 0;
    while (st.epoch < o->epochs && !stop_restart) {
      if ((o->interrupt && *o->interrupt) || (o->stop_after_epochs > 0 && epochs_this_call >= o->stop_after_epochs)) {
        result->interrupted = 1;
        if (o->checkpoint_path) status = write_checkpoint(o->checkpoint_path, fingerprint, &st, np, err);
        goto done;
      }
      double lr = sf_adam_lr(&o->adam, st.epoch);
      /* A full batch needs no shuffling: its gradient is the same sum in
       * any order (and in sample order the rows are read sequentially). */
      const int *order = batch < train->n ? perm : NULL;
      if (order)
        sf_dataset_permutation(perm, train->n, o->seed, SHUFFLE_KEY, ((uint64_t)st.restart << 32) | (uint64_t)st.epoch);
      double epoch_loss = 0.0;
      /* The machine's load changes: measure again every epoch of many
       * batches, every probe.interval epochs of a few (fit/thread_probe.h). */
      int few_batches = batches_per_epoch <= 4 * SF_TRAIN_PROBE_BATCHES;
      if (measure_threads && (!few_batches || epochs_this_call >= probe.next_epoch))
        sf_thread_probe_start(&probe, epochs_this_call);
      int watch = measure_threads && few_batches && !probe.active;
      double t_epoch = watch ? sf_wall_seconds() : 0.0;
      for (long b = 0; b < train->n; b += batch) {
        long e = b + batch < train->n ? b + batch : train->n;
        double inv = 1.0 / (double)(e - b);
        int probing = sf_thread_probe_before(&probe);
        cs.small_threads = probe.threads;
        double t0 = probing ? sf_wall_seconds() : 0.0;
        epoch_loss += chunked_loss(s, st.params, &loss, train, &train_columns, &train_rows, order, b, e, grad, &cs);
        if (probing) sf_thread_probe_after(&probe, sf_wall_seconds() - t0);
        for (int k = 0; k < np; ++k) grad[k] *= inv;
        sf_adam_step(&st.adam, &o->adam, lr, st.params, grad);
      }
      if (watch) sf_thread_probe_watch(&probe, epochs_this_call, batches_per_epoch, sf_wall_seconds() - t_epoch);
      epoch_loss /= (double)train->n;
      double val_loss = has_val ? chunked_loss(s, st.params, &loss, val, &val_columns, NULL, NULL, 0, val->n, NULL, &val_cs) / (double)val->n : NAN;
      st.epoch += 1;
      st.epochs_run += 1;
      epochs_this_call += 1;
      /* Early stopping and the kept network follow the validation loss;
       * without a validation set the last network is kept. */
      if (has_val) {
        if (val_loss < st.best_restart_loss) {
          st.best_restart_loss = val_loss;
          st.best_restart_epoch = st.epoch;
          st.since_best = 0;
          memcpy(st.restart_best, st.params, (size_t)np * sizeof(double));
        } else {
          st.since_best += 1;
          if (o->patience > 0 && st.since_best >= o->patience) stop_restart = 1;
        }
      } else {
        st.best_restart_loss = isfinite(epoch_loss) ? epoch_loss : INFINITY;
        st.best_restart_epoch = st.epoch;
        memcpy(st.restart_best, st.params, (size_t)np * sizeof(double));
      }
      if (!isfinite(epoch_loss)) stop_restart = 1;   /* diverged: this restart is over */
      if (o->progress)
        o->progress(o->progress_ctx, st.restart - o->first_restart, o->restarts, st.epoch, o->epochs, epoch_loss,
                    val_loss);
    }
    /* Without a validation set a restart is judged by its kept (last)
     * network's loss over the whole training set: the last epoch's mean of
     * the batches' losses, each taken before its step, had kept the worse
     * of two restarts. One restart needs no judging (nor the pass, a third
     * of an epoch). */
    if (!has_val && o->restarts > 1 && isfinite(st.best_restart_loss))
      st.best_restart_loss = sf_mlp_dataset_loss(s, st.restart_best, &loss, train, o->n_threads);
    if (st.best_restart_loss < st.best_loss) {
      st.best_loss = st.best_restart_loss;
      st.best_restart = st.restart;
      st.best_epoch = st.best_restart_epoch;
      memcpy(st.overall_best, st.restart_best, (size_t)np * sizeof(double));
    }
    st.restart += 1;
    if (st.restart < end_restart) start_restart(&st, o, np);
  }
  if (!isfinite(st.best_loss)) {
    status = sf_fail(err, SF_ERR_INTERNAL, "training diverged in every restart (try a smaller --lr)");
    goto done;
  }
  memcpy(result->net.params, st.overall_best, (size_t)np * sizeof(double));
  result->best_restart = st.best_restart;
  result->best_epoch = st.best_epoch;
  result->epochs_run = st.epochs_run;
  result->epochs_this_call = epochs_this_call;
  result->seconds_per_epoch = epochs_this_call > 0 ? (sf_wall_seconds() - t_start) / epochs_this_call : NAN;
  result->cpu_seconds_per_epoch =
      epochs_this_call > 0 ? (double)(clock() - cpu_start) / CLOCKS_PER_SEC / epochs_this_call : NAN;
  result->train_loss = sf_mlp_dataset_loss(s, result->net.params, &loss, train, o->n_threads);
  result->validation_loss = has_val ? sf_mlp_dataset_loss(s, result->net.params, &loss, val, o->n_threads) : NAN;
  if (o->checkpoint_path && o->keep_final_checkpoint)
    status = write_checkpoint(o->checkpoint_path, fingerprint, &st, np, err);
  else if (o->checkpoint_path)
    remove(o->checkpoint_path);
done:
  if (status != SF_OK || result->interrupted) {
    if (status != SF_OK) sf_mlp_free(&result->net);
    result->epochs_run = st.epochs_run;
    result->epochs_this_call = epochs_this_call;
    result->seconds_per_epoch = result->cpu_seconds_per_epoch = NAN;
  }
  free(delta);
  free(grad);
  free(perm);
  free(st.params);
  free(st.restart_best);
  free(st.overall_best);
  sf_adam_free(&st.adam);
  chunk_sums_free(&cs);
  chunk_sums_free(&val_cs);
  sf_mlp_columns_free(&train_columns);
  sf_mlp_columns_free(&val_columns);
  sf_mlp_rows_free(&train_rows);
  return status;
}
