/* Error and cost of a candidate over the scene domain (SPEC §12):
 *  - samples: seeded, uniform in the domain box of models/scene_file.h
 *    (h, mu, mu_s uniform; nu from a uniform azimuth between view and sun,
 *    nu = mu mu_s + sqrt((1 - mu^2)(1 - mu_s^2)) cos(phi), so every nu is
 *    one the geometry allows);
 *  - errors against the reference values over every sample and channel:
 *    RMSE (seed 000 eq. 61), max absolute, mean relative |m - t| / max(|t|,
 *    floor) with floor = 1e-3 x the reference's RMS (a reference of exactly
 *    0 divides by the floor, not by 0; see sf_error_metrics), and the
 *    relative RMSE = RMSE / RMS(reference), the quantity of the scene's
 *    sky-radiance budget ("sky_radiance_rel_rmse");
 *  - cost: median over repetitions of (wall time / points) of evaluating
 *    every point of a set of in-domain inputs on one thread, through the
 *    candidate's float32 batch evaluation (or its double evaluation when it
 *    has none: precision 64). Timings are noisy on a loaded machine; the
 *    ratio to the naive raymarch timed in the same run is the figure to
 *    compare. */
#ifndef SKYFIT_FIT_CANDIDATE_METRICS_H
#define SKYFIT_FIT_CANDIDATE_METRICS_H

#include <stddef.h>
#include <stdint.h>

#include "data/precompute_options.h"
#include "fit/candidate.h"
#include "util/error.h"

typedef struct sf_domain_samples {
  sf_candidate_quantity quantity;
  int n_inputs;
  size_t n;
  double *inputs;   /* n * n_inputs */
} sf_domain_samples;

int sf_domain_samples_make(const sf_scene_domain *d, sf_candidate_quantity q, size_t n, uint64_t seed,
                           sf_domain_samples *out, sf_error *err);
void sf_domain_samples_free(sf_domain_samples *s);

/* values[n * c->n_channels] = c at every sample (threads; same result for
 * any thread count). */
void sf_candidate_values(const sf_candidate *c, const sf_domain_samples *s, double *values,
                         const sf_precompute_options *run);

/* The floor does not keep near-zero references from dominating the mean
 * relative error: over the default sky domain a quarter of the reference
 * values lie below it (rays up from 50-100 km, suns below the horizon),
 * and for the default build's sky network they made three quarters of
 * its mean relative error of 1.05-1.29, where its relative RMSE is 0.042.
 * So the metrics say how many values lie below the floor and what share of
 * mean_rel they make, and the report says so where that share is over
 * SF_METRICS_FLOOR_SHARE_NOTE. */
#define SF_METRICS_FLOOR_SHARE_NOTE 0.5
typedef struct sf_error_metrics {
  double rmse, max_abs, mean_rel, rel_rmse;
  double reference_rms;
  size_t n_values;
  size_t n_below_floor;        /* values whose |reference| < the floor */
  double mean_rel_floor_share; /* share of mean_rel they make, 0..1 */
} sf_error_metrics;

/* Over n_values pairs. Non-finite model values count as an error of
 * +infinity would: they make the result non-finite, and are reported by
 * n_non_finite instead (the figures then use the finite ones). So are
 * values beyond +-SF_METRICS_MAX_VALUE (a model that blew up; their squares
 * would overflow the sums). */
#define SF_METRICS_MAX_VALUE 1e100
void sf_error_metrics_compute(const double *model, const double *reference, size_t n_values,
                              sf_error_metrics *out, size_t *n_non_finite);

typedef struct sf_cost {
  double ns_median, ns_min, ns_max;   /* per evaluation */
  int repetitions;
  size_t n_points;
  int precision_bits;                 /* 32: float32 batch; 64: double eval */
} sf_cost;

/* One timed pass of c over the inputs of s (converted to float for the
 * float32 path, outside the timing): ns per evaluation in *ns. */
int sf_candidate_time_pass(const sf_candidate *c, const sf_domain_samples *s, double *ns, sf_error *err);
/* The cost of c from its passes' times ns[0..passes) (sorted in place). */
void sf_cost_from_passes(const sf_candidate *c, const sf_domain_samples *s, double *ns, int passes, sf_cost *out);

#endif
