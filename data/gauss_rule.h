/* Gauss-Legendre rules on [0, 1] with their "partial" weights: the weights
 * of the integral from 0 up to each node (spectral integration through the
 * interpolating polynomial). The table integrals use them to get, from the
 * same density samples, both a ray's total optical depth and the optical
 * depth up to every node (the view transmittance at the node). */
#ifndef SKYFIT_DATA_GAUSS_RULE_H
#define SKYFIT_DATA_GAUSS_RULE_H

#define SF_GAUSS_MAX_NODES 24

typedef struct sf_gauss_rule {
  int n;
  double x[SF_GAUSS_MAX_NODES];   /* nodes in (0, 1), ascending */
  double w[SF_GAUSS_MAX_NODES];   /* weights, sum 1 */
  /* partial[k][j]: weight of f(x_j) in the integral of f over [0, x_k]; exact
   * for polynomials of degree < n. */
  double partial[SF_GAUSS_MAX_NODES][SF_GAUSS_MAX_NODES];
  /* to_legendre[m][j]: coefficient of P_m(2x - 1) contributed by f(x_j) in
   * the interpolating polynomial, (2m+1)/2 w_j P_m(x_j) on [-1, 1]. */
  double to_legendre[SF_GAUSS_MAX_NODES][SF_GAUSS_MAX_NODES];
  /* Legendre recurrence P_{m+1} = rec_a[m] y P_m - rec_b[m] P_{m-1} and
   * rec_c[m] = 1 / (2m + 1), so that evaluations need no division. */
  double rec_a[SF_GAUSS_MAX_NODES], rec_b[SF_GAUSS_MAX_NODES], rec_c[SF_GAUSS_MAX_NODES];
} sf_gauss_rule;

/* Fills an n-point rule, 1 <= n <= SF_GAUSS_MAX_NODES. Returns 0, or -1 for
 * an unsupported n (rule untouched). */
int sf_gauss_rule_init(sf_gauss_rule *rule, int n);

/* Integral over [0, x] (x in [0, 1]) of the polynomial with Legendre
 * coefficients coef[0..n-1] (from to_legendre, in the variable 2x - 1). */
double sf_gauss_legendre_integral(const double *coef, int n, double x);

#endif
