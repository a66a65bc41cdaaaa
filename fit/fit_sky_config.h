/* Least-squares fit of one sky configuration (one sun elevation, one
 * channel) of the Perez or Hosek form (models/hosek_sky_model.h) to sky
 * radiance samples, through Ceres (fit/ceres_shim.h) with analytic
 * Jacobians (SPEC §7.2):
 *
 *   residual_i = weight (S F(c; theta_i, gamma_i) - L_i)
 *
 * c the 5 (A..E) or 9 (A..I) coefficients, S the radiance scale (Perez K,
 * Hosek R). Hosek's S is degenerate with its linear coefficients C, D, F,
 * G, I, so Hosek fits hold S fixed (fix_scale); Perez's K is free.
 *
 * Bounds: S >= 0 always. SF_SKY_BOUNDS_PHYSICAL adds Hosek H in [0, 0.999]
 * (a forward-scattering Mie anisotropy) and B <= 0 for both forms
 * (exp(B / cos theta), exp(B / (cos theta + 0.01)) stay bounded towards the
 * horizon; without it a Bezier curve through fitted B values can blow up
 * between the elevations it was fitted at). The published Hosek dataset
 * itself has H outside [0, 1) in 71 and B > 0 in 37 of its 360 control
 * points: fits meant to reproduce it use SF_SKY_BOUNDS_SCALE_ONLY.
 * Hosek's linear coefficients C, D, F, I are bounded to
 * +-SF_HOSEK_LINEAR_MAX (the published control points lie within +-49):
 * unbounded, fits drove E to 0 and C, D to -+1e4 (C + D e^(E gamma) as a
 * slope in gamma), a cancellation float32 shaders cannot hold (the emitted
 * C differed from the double model by 6.8e-3 of its value). */
#ifndef SKYFIT_FIT_FIT_SKY_CONFIG_H
#define SKYFIT_FIT_FIT_SKY_CONFIG_H

#include "fit/ceres_shim.h"
#include "models/hosek_sky_model.h"
#include "util/error.h"

typedef enum sf_sky_bounds { SF_SKY_BOUNDS_PHYSICAL = 0, SF_SKY_BOUNDS_SCALE_ONLY = 1 } sf_sky_bounds;

#define SF_HOSEK_H_MAX 0.999
#define SF_HOSEK_LINEAR_MAX 100.0

typedef struct sf_sky_fit_data {
  sf_sky_form form;
  int n;
  const double *cos_theta, *gamma, *cos_gamma;
  const double *radiance;    /* radiance[i * stride] */
  int stride;
  double weight;
} sf_sky_fit_data;

/* The solver settings of the sky fits (measured by bench/ceres_vs_scipy.sh):
 * sf_lsq_options_default with the choices below. */
void sf_sky_fit_options_default(sf_lsq_options *o);

/* Bounds of coefficient i (i == n_coeffs: the scale). */
void sf_sky_coeff_bounds(sf_sky_form form, sf_sky_bounds bounds, int i, double *lower,
                         double *upper);
/* Clamps coefficients and scale into their bounds (a start must be inside). */
void sf_sky_clamp_to_bounds(sf_sky_form form, sf_sky_bounds bounds, double *coeffs, double *scale);

/* 1/2 sum residual^2 at (coeffs, scale). */
double sf_sky_fit_cost(const sf_sky_fit_data *d, const double *coeffs, double scale);

/* The fit's residuals r_i (above) at (coeffs, scale): *sum_squares =
 * sum r_i^2 and, when gram is not NULL, the (n_coeffs + 2)^2 row-major
 * Gram matrix [J r]^T [J r] with J's columns d r / d coeffs, then
 * d r / d scale (what Ceres is given, fit/ceres_shim.h). Returns 0, or -1
 * when out of memory. */
int sf_sky_fit_gram(const sf_sky_fit_data *d, const double *coeffs, double scale,
                    double *sum_squares, double *gram);

/* sf_sky_fit_gram for many evaluations on the same samples: the
 * coefficient-free part of every sample computed once (copied: d need not
 * outlive it). The same numbers as sf_sky_fit_gram. NULL when out of
 * memory. */
typedef struct sf_sky_fit_prepared sf_sky_fit_prepared;
sf_sky_fit_prepared *sf_sky_fit_prepare(const sf_sky_fit_data *d);
void sf_sky_fit_prepared_gram(const sf_sky_fit_prepared *p, const double *coeffs, double scale,
                              double *sum_squares, double *gram);
void sf_sky_fit_prepared_free(sf_sky_fit_prepared *p);

/* Solves in place from the start in coeffs/scale (clamped into the bounds
 * first). Returns 0 when usable (SF_ERR_INTERNAL with Ceres' message
 * otherwise). */
int sf_fit_sky_config(const sf_sky_fit_data *d, sf_sky_bounds bounds, int fix_scale,
                      const sf_lsq_options *o, double *coeffs, double *scale,
                      sf_lsq_summary *summary, sf_error *err);

/* Multi-start: row starts[s] holds the coefficients, then the scale at
 * index n_coeffs (rows are sized for Hosek, the larger form, whatever the
 * form). Fits from each, keeps the lowest final cost (ties: the earlier start).
 * final_costs (may be NULL) receives each start's final cost (INFINITY for
 * an unusable solve). *winner is the winning start's index. */
int sf_fit_sky_multistart(const sf_sky_fit_data *d, sf_sky_bounds bounds, int fix_scale,
                          const sf_lsq_options *o, int n_starts,
                          const double (*starts)[SF_HOSEK_N_COEFFS + 1],
                          double *coeffs, double *scale, int *winner, sf_lsq_summary *summary,
                          double *final_costs, sf_error *err);

#endif
