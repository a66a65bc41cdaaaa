/* Runs independent rows of work on several threads (OpenMP, dynamic
 * schedule). Each row writes only its own outputs, so results do not
 * depend on the number of threads or on the schedule. */
#ifndef SKYFIT_DATA_PARALLEL_ROWS_H
#define SKYFIT_DATA_PARALLEL_ROWS_H

#include "data/precompute_options.h"

/* thread is in [0, sf_parallel_threads(opt)): an index for per-thread
 * scratch space. */
typedef void (*sf_row_fn)(void *ctx, int thread, long row);

/* Threads that sf_parallel_rows will use with these options. */
int sf_parallel_threads(const sf_precompute_options *opt);

/* fn(ctx, thread, row) for every row in [0, n_rows); reports progress of
 * stage through opt->progress (from one thread). opt may be NULL. */
void sf_parallel_rows(long n_rows, const sf_precompute_options *opt, const char *stage, sf_row_fn fn,
                      void *ctx);

#endif
