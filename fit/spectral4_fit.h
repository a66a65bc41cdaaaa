/* The 4-wavelength spectral weights (SPEC §7.3, seed 003 §5.4): four
 * wavelengths l_i and weights w_i (nm, the widths of eq. 5.10's Riemann
 * partitions) such that
 *   XYZ ~ sum_i w_i cmf(l_i) L(l_i)      (eq. 5.12)
 * reproduces the full-spectrum colour; fitted by minimising eq. 5.13, the
 * mean squared error of the linear sRGB colour over (viewer, view, sun)
 * samples, with a coarse grid search followed by Nelder-Mead (NLopt
 * NLOPT_LN_NELDERMEAD).
 *
 * L(l) at any wavelength is the spectral reference interpolated linearly in
 * wavelength between its 5 nm samples (the sky spectrum is smooth on that
 * scale). The loss is then a quadratic form in the per-sample spectra, so it
 * is computed exactly from three sums accumulated once over the samples
 * (sf_spectral4_kernel): K = sum_s w_s L_s L_s^T (n x n), P = sum_s w_s L_s
 * y_s^T (n x 3) and yy = sum_s w_s |y_s|², y_s the reference colour:
 *   3 W loss = yy - 2 sum_i w_i c_i.P(l_i) + sum_ij w_i w_j (c_i.c_j) K(l_i, l_j)
 * with c_i = M_srgb cmf(l_i) and P(l), K(l, l') read with the same linear
 * interpolation weights. This is eq. 5.13 itself, rearranged; an evaluation
 * costs ~100 operations instead of a pass over the samples.
 *
 * The grid search runs over wavelength quadruples l1 < l2 < l3 < l4 on a
 * grid; for each, the weights minimising the loss are the solution of a 4x4
 * linear least-squares system (the loss is quadratic in w), so the grid
 * covers all eight parameters. Nelder-Mead then refines all eight from
 * each of the best few grid local minima (quadruples no grid neighbour
 * beats), the best result kept. */
#ifndef SKYFIT_FIT_SPECTRAL4_FIT_H
#define SKYFIT_FIT_SPECTRAL4_FIT_H

#include <stddef.h>

#include "models/atmosphere.h"
#include "models/spectral_data.h"
#include "util/error.h"

typedef struct sf_spectral4_kernel {
  int n;                                 /* reference channels */
  double lambda_nm[SF_MAX_CHANNELS];     /* evenly spaced */
  double *K;                             /* n x n, row-major */
  double P[SF_MAX_CHANNELS][3];
  double yy, weight_sum;
  size_t n_samples;
  const sf_cmf *cmf;                     /* not owned */
} sf_spectral4_kernel;

int sf_spectral4_kernel_init(sf_spectral4_kernel *k, int n, const double *lambda_nm, const sf_cmf *cmf,
                             sf_error *err);
void sf_spectral4_kernel_free(sf_spectral4_kernel *k);
/* One sample: its spectrum L[0..n) and reference linear sRGB y, weight w. */
void sf_spectral4_kernel_add(sf_spectral4_kernel *k, const double *L, const double y[3], double w);

/* c = M_srgb cmf(lambda): the linear sRGB of unit radiance at lambda per nm. */
void sf_spectral4_rgb_of_wavelength(const sf_cmf *cmf, double lambda_nm, double c[3]);

typedef struct sf_spectral4_params {
  double lambda_nm[4];
  double weight_nm[4];
} sf_spectral4_params;

/* Eq. 5.13: mean over samples and the 3 channels of the squared error. */
double sf_spectral4_loss(const sf_spectral4_kernel *k, const sf_spectral4_params *p);
/* The weights minimising the loss for p->lambda_nm (4x4 least squares);
 * returns the loss. */
double sf_spectral4_optimal_weights(const sf_spectral4_kernel *k, sf_spectral4_params *p);
/* Baseline of seed 003 §6: L(680), L(550), L(440) used directly as linear
 * sRGB times one scale (the least-squares one, as seed 003 "multiplies by a
 * factor to match the absolute luminance"); returns the loss, sets *scale. */
double sf_spectral4_rgb_baseline(const sf_spectral4_kernel *k, const double lambda_rgb_nm[3], double *scale);

typedef struct sf_spectral4_fit_options {
  double grid_min_nm, grid_max_nm, grid_step_nm;   /* the quadruple grid */
  int max_evaluations;                             /* Nelder-Mead */
  double ftol_rel, xtol_rel;
  double initial_step_nm;                          /* Nelder-Mead's first simplex, wavelengths */
  double initial_step_fraction;                    /* ... and weights (fraction of each) */
  int restarts;    /* Nelder-Mead restarted from its result (a fresh simplex) while
                      that lowers the loss, at most this many times: the
                      usual remedy for a simplex that collapsed early */
  int starts;      /* Nelder-Mead (with its restarts) from this many grid local
                      minima, the best first ... */
  int shortlist;   /* ... found among this many best grid quadruples */
} sf_spectral4_fit_options;

/* grid 380-780 nm at 10 nm; 20000 evaluations per run; ftol_rel 1e-10;
 * xtol_rel 1e-7; steps 5 nm and 10 %; 4 restarts; 8 starts from a
 * shortlist of 1024. */
void sf_spectral4_fit_options_default(sf_spectral4_fit_options *o);

typedef struct sf_spectral4_fit_result {
  sf_spectral4_params grid_best, best;   /* best sorted by wavelength */
  double grid_loss, loss;
  long grid_candidates;
  int evaluations;                        /* Nelder-Mead objective calls, all starts */
  int starts;                             /* Nelder-Mead starts run */
  int nlopt_status;
  double grid_seconds, nelder_mead_seconds;
} sf_spectral4_fit_result;

/* Nelder-Mead (NLopt) over the 8 parameters from start; wavelengths bounded
 * to the kernel's range; restarted as o->restarts says. *evaluations counts
 * every objective call of every run. */
int sf_spectral4_nelder_mead(const sf_spectral4_kernel *k, const sf_spectral4_params *start,
                             const sf_spectral4_fit_options *o, sf_spectral4_params *best, double *loss,
                             int *evaluations, int *status, sf_error *err);

/* Grid search, then Nelder-Mead from the grid's best local minima;
 * grid_best and grid_loss are the grid's best quadruple. */
int sf_spectral4_fit(const sf_spectral4_kernel *k, const sf_spectral4_fit_options *o, sf_spectral4_fit_result *r,
                     sf_error *err);

#endif
