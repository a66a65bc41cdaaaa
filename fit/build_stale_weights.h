/* DIR/weights of `skyfit build` holds the weights file of every model the
 * run fitted (fit/build_pipeline.h). A file an earlier run left there for
 * a model this run did not fit (another scene's Hosek fit, another seed's
 * restart mlp-scattering-3) would pass for one of this run's, so after a
 * successful run it is removed. Only the names a build writes are touched:
 * "<model>.json" for a registered model (fit/candidate_registry.h),
 * "<model>-<n>.json" for a restartable one and "spectral4.json"; any other
 * file in the folder stays. */
#ifndef SKYFIT_FIT_BUILD_STALE_WEIGHTS_H
#define SKYFIT_FIT_BUILD_STALE_WEIGHTS_H

#include "util/error.h"

/* 1 if file (a name, no folder) is one a build writes into DIR/weights. */
int sf_build_weights_name(const char *file);

/* Removes from work_dir every file named as sf_build_weights_name says
 * whose path is not among written[0..n_written-1] (paths as the build
 * wrote them: work_dir "/" name). *n_removed counts the files removed; on
 * a failure the rest are still tried and err names the first. A missing
 * work_dir holds nothing stale (SF_OK: a run that fitted nothing makes
 * none). */
int sf_build_remove_stale_weights(const char *work_dir, const char *const *written, int n_written,
                                  int *n_removed, sf_error *err);

#endif
