/* The Gram matrix of a channel's global sky fit (fit/fit_sky_elevation.h,
 * step 3): every Bezier control point of a Perez or Hosek form against the
 * radiance samples of every sun elevation, handed to Ceres as a Gram block
 * (fit/ceres_shim.h, sf_lsq_add_gram_residuals).
 *
 * At elevation e with Bernstein weights b_e (models/hosek_bezier.h) the
 * coefficients are c_e = sum_j b_ej P_j and the scale s_e = sum_j b_ej Q_j,
 * so a sample's Jacobian row over (P, Q) is b_e (x) v, v its one-sky row
 * (d r / d c, d r / d s) at (c_e, s_e). Hence
 *
 *   [J r]^T [J r] = sum_e (b_e b_e^T) (x) G_e     (for the parameter part;
 *                                                  b_e alone against r)
 *
 * with G_e the one-sky Gram matrix of elevation e (fit/fit_sky_config.h):
 * a pass over the samples per elevation, whatever the number of control
 * points.
 *
 * Why not hand Ceres the rows: Ceres forms J^T J (and QR) with Eigen, whose
 * products split a long sum over the rows in pieces sized by the CPU's L1
 * cache (queried at run time), so the same fit gave other bits on a CPU
 * with another L1 (the default weights' Hosek and Preetham files differed
 * between an Intel Xeon, 48 KB L1, and AMD EPYCs, 32 KB: from the 16th
 * digit, up to 1e-3 relative in Hosek's blue channel, whose C and D nearly
 * cancel). Here every sum runs in a fixed order (the one-sky kernels' lanes,
 * then the elevations in order), and Ceres sees 6 (n_coeffs + 1) + 1 rows:
 * too short a sum for Eigen to split on any CPU (its pieces hold at least
 * 500 terms with a 32 KB L1). */
#ifndef SKYFIT_FIT_SKY_BEZIER_GRAM_H
#define SKYFIT_FIT_SKY_BEZIER_GRAM_H

#include "fit/fit_sky_config.h"
#include "models/hosek_bezier.h"

/* fit/fit_sky_elevation.h's step 3: 3 suns per step between at most 64
 * fit suns, 3 * 63 + 1 */
#define SF_SKY_BEZIER_MAX_ELEVATIONS 190
/* parameters of the global fit: control points of the coefficients, then
 * of the scale */
#define SF_SKY_BEZIER_MAX_PARAMS (SF_BEZIER_POINTS * (SF_HOSEK_N_COEFFS + 1))

typedef struct sf_sky_bezier_gram {
  sf_sky_form form;
  int n_elevations;
  sf_sky_fit_prepared *elevation[SF_SKY_BEZIER_MAX_ELEVATIONS];
  double bernstein[SF_SKY_BEZIER_MAX_ELEVATIONS][SF_BEZIER_POINTS];
} sf_sky_bezier_gram;

/* Prepares elevations data[0..n_elevations) (one channel each, all of
 * form), Bernstein weights bernstein[e] of elevation e. Returns 0, or -1
 * when out of memory or n_elevations is out of 1..SF_SKY_BEZIER_MAX_ELEVATIONS
 * (nothing to free then). */
int sf_sky_bezier_gram_init(sf_sky_bezier_gram *g, sf_sky_form form, int n_elevations,
                            const sf_sky_fit_data *data,
                            const double (*bernstein)[SF_BEZIER_POINTS]);
void sf_sky_bezier_gram_free(sf_sky_bezier_gram *g);

/* At control points P[j n_coeffs + i] (coefficient i) and Q[j] (scale):
 * *sum_squares = |r|^2 over all elevations' residuals and, when gram is
 * not NULL, the (p + 1)^2 row-major [J r]^T [J r] (both triangles), p = 6
 * (n_coeffs + 1), columns P then Q then r. */
void sf_sky_bezier_gram_eval(const sf_sky_bezier_gram *g, const double *P, const double *Q,
                             double *sum_squares, double *gram);

#endif
