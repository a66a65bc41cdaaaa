#include "data/parallel_rows.h"

#include <stddef.h>

#ifdef _OPENMP
#include <omp.h>
#endif

int sf_parallel_threads(const sf_precompute_options *opt) {
#ifdef _OPENMP
  int n = opt && opt->n_threads > 0 ? opt->n_threads : omp_get_max_threads();
  return n > 0 ? n : 1;
#else
  (void)opt;
  return 1;
#endif
}

void sf_parallel_rows(long n_rows, const sf_precompute_options *opt, const char *stage, sf_row_fn fn,
                      void *ctx) {
  sf_progress_fn progress = opt ? opt->progress : NULL;
  void *progress_ctx = opt ? opt->progress_ctx : NULL;
  if (progress) progress(progress_ctx, stage, 0.0);
  long done = 0;
  int threads = sf_parallel_threads(opt);
  (void)threads;
#pragma omp parallel num_threads(threads)
  {
    int thread = 0;
#ifdef _OPENMP
    thread = omp_get_thread_num();
#endif
#pragma omp for schedule(dynamic, 1)
    for (long row = 0; row < n_rows; ++row) {
      fn(ctx, thread, row);
      long now;
#pragma omp atomic capture
      now = ++done;
      if (progress && thread == 0) progress(progress_ctx, stage, (double)now / (double)n_rows);
    }
  }
  if (progress) progress(progress_ctx, stage, 1.0);
}
