/* Small dense linear least squares min_x sum_i w_i^2 (A_i x - b_i)^2 by
 * Householder QR (no normal equations, so the conditioning is that of A,
 * not its square). Used for starting points (sigmoid logit fit) and for the
 * Bezier control points fitted to per-elevation values. */
#ifndef SKYFIT_FIT_LINEAR_LSQ_H
#define SKYFIT_FIT_LINEAR_LSQ_H

/* A is m x n row-major (m >= n, n <= 64), b has m entries, w m weights
 * (NULL: all 1). A and b are not modified. Returns 0, or -1 if A (after
 * weighting) is rank deficient or m < n. */
int sf_linear_lsq(int m, int n, const double *A, const double *b, const double *w, double *x);

#endif
