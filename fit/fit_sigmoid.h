/* Fit of the sigmoid-polynomial transmittance (SPEC §7.1, seed 000 §9.5,
 * models/sigmoid_transmittance.h) per constituent and channel.
 *
 * What is fitted: T_top, the transmittance of rays to the TOP boundary,
 * on the rays the full-ray rule (models/sigmoid_transmittance.h: rays
 * looking down are reversed, eq. 43 and the tangent-point split) asks for,
 * which all look up or horizontally:
 *   h in [h_lo, H]: H the atmosphere's top, where the domain's segments
 *     end (eq. 43 forward takes T_top at a segment's end, anywhere along
 *     a ray that leaves through the top); h_lo = 0 when the domain has
 *     rays looking down (their ground points and tangent points go down
 *     to 0), else the domain's h_min;
 *   mu in [lo, hi]: with rays looking down lo = 0, hi = max(mu_max,
 *     -mu_min) (the reversed viewer ray looks along -mu); else the
 *     domain's [mu_min, mu_max]; hi then raised to the cosine at which a
 *     ray from h_lo along hi leaves the top (a scene's domains have
 *     hi = 1 already).
 * Reference: the exact per-constituent optical depth (models/optical_depth.h)
 * of each to-top ray, T_ck = exp(-extinction_ck depth_c), on an n_h x n_mu
 * grid (end points included).
 *
 * Start: weighted linear least squares on logit(T) with weights T(1 - T)
 * (the linearisation of the sigmoid), then Ceres (one residual block
 * holding all residuals, analytic Jacobian) on T_model - T_ref.
 *
 * Evaluation (the report): the to-top fit on its grid, and full rays (to
 * the ground or the top, models/sigmoid_transmittance.h) on the domain's
 * n_h x n_mu (h, mu) box against the exact optical depth; the maximum of
 * the full-ray error also visits the tangent sweep of the ground
 * (models/tangent_sweep.h: the horizon, where the model errs most), the
 * RMSE only the box. */
#ifndef SKYFIT_FIT_FIT_SIGMOID_H
#define SKYFIT_FIT_FIT_SIGMOID_H

#include "fit/ceres_shim.h"
#include "models/scene_file.h"
#include "models/sigmoid_transmittance.h"
#include "util/error.h"

typedef struct sf_sigmoid_fit_options {
  int n_h, n_mu;           /* default 48 x 96 (both grids) */
  sf_lsq_options lsq;
  void (*progress)(void *ctx, const char *stage, double fraction);
  void *progress_ctx;
} sf_sigmoid_fit_options;

void sf_sigmoid_fit_options_default(sf_sigmoid_fit_options *o);

/* Per constituent c and channel k: the to-top fit. */
typedef struct sf_sigmoid_fit_entry {
  double rmse, max_abs, worst_h_km, worst_mu;
  double start_cost, final_cost;
  int iterations;
  int transparent;          /* zero extinction: not fitted */
} sf_sigmoid_fit_entry;

/* Error of the total transmittance (product over constituents), all channels. */
typedef struct sf_sigmoid_error {
  int n_points;
  double rmse, max_abs, worst_h_km, worst_mu;
  int worst_channel;
} sf_sigmoid_error;

typedef struct sf_sigmoid_fit_report {
  int n_points;             /* to-top fit points */
  sf_sigmoid_fit_entry entry[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];
  double fit_h_min_km, fit_h_max_km, fit_mu_min, fit_mu_max;   /* the to-top region fitted */
  sf_sigmoid_error top;     /* to-top rays, the fit grid */
  sf_sigmoid_error full;    /* full rays over the domain box */
  sf_sigmoid_error full_ground, full_sky;   /* its rays that hit the ground / do not */
  /* = full, kept for callers of the earlier report */
  double rmse, max_abs, worst_h_km, worst_mu;
  int worst_channel;
  double seconds;
} sf_sigmoid_fit_report;

/* rep is large: allocate it. */
int sf_fit_sigmoid(const sf_atmosphere *atm, const sf_scene_domain *domain,
                   const sf_sigmoid_fit_options *o, sf_sigmoid_model *out,
                   sf_sigmoid_fit_report *rep, sf_error *err);

#endif
