/* How the table computations run: threads and progress reports. The thread
 * count never changes a value (every table entry is computed on its own,
 * and sums over entries are taken in a fixed order). */
#ifndef SKYFIT_DATA_PRECOMPUTE_OPTIONS_H
#define SKYFIT_DATA_PRECOMPUTE_OPTIONS_H

/* Called from one thread only, with the stage name and the fraction of the
 * stage done, in [0, 1]. */
typedef void (*sf_progress_fn)(void *ctx, const char *stage, double fraction);

typedef struct sf_precompute_options {
  int n_threads;              /* <= 0: OpenMP's default */
  sf_progress_fn progress;    /* may be NULL */
  void *progress_ctx;
} sf_precompute_options;

#endif
