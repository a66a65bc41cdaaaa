/* The errors `skyfit build` measured for each fitted model
 * (fit/candidate_metrics.h: against the reference, over the scene's domain
 * or the part of it where the model applies) written into the model's
 * weights file as metrics.build_error, the figures its header comment
 * states. `skyfit codegen` from the same file then states them too: it
 * had stated a network's training loss on its transformed targets (1.1e-7
 * on T^(1/4) for an RMSE of 7e-4). */
#ifndef SKYFIT_FIT_BUILD_WEIGHTS_ERRORS_H
#define SKYFIT_FIT_BUILD_WEIGHTS_ERRORS_H

#include "codegen/report.h"
#include "util/error.h"

/* For every model of rep with a weights file and measured errors: adds
 * (or replaces) metrics.build_error = {"rmse", "max_abs", "mean_rel",
 * "rel_rmse", "values", "over"} and rewrites the file atomically. */
int sf_build_record_errors(const sf_report *rep, sf_error *err);

#endif
