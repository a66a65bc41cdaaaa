/* Hosek-Wilkie's dependence on sun elevation (../shared/data/hosek2012.md
 * steps 1-2): a quintic Bezier curve over x = (elevation / (pi/2))^(1/3)
 * with 6 control points P0 (horizon, x = 0) .. P5 (zenith, x = 1):
 *   B(x) = sum_j C(5, j) (1 - x)^(5 - j) x^j P_j,  C(5, j) = 1 5 10 10 5 1.
 * The cube root spends more of the curve on low suns. Used by the published
 * dataset and by our fitted Perez and Hosek models alike. */
#ifndef SKYFIT_MODELS_HOSEK_BEZIER_H
#define SKYFIT_MODELS_HOSEK_BEZIER_H

#define SF_BEZIER_POINTS 6

/* x for a sun elevation in radians, clamped into [0, pi/2]. */
double sf_bezier_x_of_elevation(double elevation_rad);
/* The six Bernstein weights at x. */
void sf_bezier_weights(double x, double w[SF_BEZIER_POINTS]);
/* B(x) of control points p[j * stride], j = 0..5. */
double sf_bezier_eval(const double *p, int stride, double x);

#endif
