/* Fit of the sigmoid-polynomial transmittance (SPEC §7.1, seed 000 §9.5,
 * models/sigmoid_transmittance.h) per constituent and channel over a
 * scene's (h, mu) domain.
 *
 * Reference: the exact per-constituent optical depth (models/optical_depth.h,
 * adaptive quadrature to 1e-11) of the ray from (h, mu) to its end (ground
 * or top), T_ck = exp(-extinction_ck depth_c), on an n_h x n_mu grid
 * spanning the domain's box (end points included). The exact integrals are
 * cheap at this size, so no table interpolation error enters the fit.
 *
 * Start: the weighted linear least-squares fit of logit(T) with weights
 * T(1 - T) (the linearisation of the sigmoid), then Ceres on the residuals
 * T_model - T_ref with analytic Jacobians. */
#ifndef SKYFIT_FIT_FIT_SIGMOID_H
#define SKYFIT_FIT_FIT_SIGMOID_H

#include "fit/ceres_shim.h"
#include "models/scene_file.h"
#include "models/sigmoid_transmittance.h"
#include "util/error.h"

typedef struct sf_sigmoid_fit_options {
  int n_h, n_mu;           /* default 48 x 96 */
  sf_lsq_options lsq;
  void (*progress)(void *ctx, const char *stage, double fraction);
  void *progress_ctx;
} sf_sigmoid_fit_options;

void sf_sigmoid_fit_options_default(sf_sigmoid_fit_options *o);

/* Per constituent c and channel k. */
typedef struct sf_sigmoid_fit_entry {
  double rmse, max_abs, worst_h_km, worst_mu;
  double start_cost, final_cost;
  int iterations;
  int transparent;          /* zero extinction: not fitted */
} sf_sigmoid_fit_entry;

typedef struct sf_sigmoid_fit_report {
  int n_points;
  sf_sigmoid_fit_entry entry[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];
  /* the total transmittance (product over constituents), all channels */
  double rmse, max_abs, worst_h_km, worst_mu;
  int worst_channel;
  double seconds;
} sf_sigmoid_fit_report;

/* rep is large: allocate it. */
int sf_fit_sigmoid(const sf_atmosphere *atm, const sf_scene_domain *domain,
                   const sf_sigmoid_fit_options *o, sf_sigmoid_model *out,
                   sf_sigmoid_fit_report *rep, sf_error *err);

#endif
