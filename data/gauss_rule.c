#include "data/gauss_rule.h"

#include <math.h>

#include "util/constants.h"

/* Legendre polynomials P_0..P_max at x by the three-term recurrence. */
static void legendre_all(double x, int max, double *p) {
  p[0] = 1.0;
  if (max >= 1) p[1] = x;
  for (int m = 2; m <= max; ++m) p[m] = ((2 * m - 1) * x * p[m - 1] - (m - 1) * p[m - 2]) / m;
}

int sf_gauss_rule_init(sf_gauss_rule *rule, int n) {
  if (n < 1 || n > SF_GAUSS_MAX_NODES) return -1;
  double xs[SF_GAUSS_MAX_NODES], ws[SF_GAUSS_MAX_NODES];   /* on [-1, 1] */
  for (int k = 0; k < n; ++k) {
    /* Newton on P_n from the classical asymptotic guess; the k-th root
     * counted from +1, stored ascending. */
    double x = cos(SF_PI * (k + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int m = 2; m <= n; ++m) {
        double p2 = ((2 * m - 1) * x * p1 - (m - 1) * p0) / m;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) { p1 = x; p0 = 1.0; }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      double step = p1 / dp;
      x -= step;
      if (fabs(step) <= 1e-16) break;
    }
    /* Weight 2 / ((1 - x^2) P_n'(x)^2) at the converged root. */
    double p0 = 1.0, p1 = x;
    for (int m = 2; m <= n; ++m) {
      double p2 = ((2 * m - 1) * x * p1 - (m - 1) * p0) / m;
      p0 = p1;
      p1 = p2;
    }
    if (n == 1) { p1 = x; p0 = 1.0; }
    dp = n * (x * p1 - p0) / (x * x - 1.0);
    xs[n - 1 - k] = x;
    ws[n - 1 - k] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  rule->n = n;
  for (int m = 0; m < SF_GAUSS_MAX_NODES; ++m) {
    rule->rec_a[m] = (2.0 * m + 1.0) / (m + 1.0);
    rule->rec_b[m] = m / (m + 1.0);
    rule->rec_c[m] = 1.0 / (2.0 * m + 1.0);
  }
  for (int k = 0; k < n; ++k) {
    rule->x[k] = 0.5 * (xs[k] + 1.0);
    rule->w[k] = 0.5 * ws[k];
  }
  for (int j = 0; j < n; ++j) {
    double pj0[SF_GAUSS_MAX_NODES + 1];
    legendre_all(xs[j], n, pj0);
    for (int m = 0; m < n; ++m) rule->to_legendre[m][j] = 0.5 * (2 * m + 1) * ws[j] * pj0[m];
  }
  /* The Lagrange basis polynomial of node j has Legendre coefficients
   * (2m+1)/2 w_j P_m(x_j) (discrete orthogonality of the Gauss rule), and
   * the integral of P_m from -1 to x is (P_{m+1}(x) - P_{m-1}(x)) / (2m+1). */
  double pj[SF_GAUSS_MAX_NODES + 1], pk[SF_GAUSS_MAX_NODES + 1];
  for (int k = 0; k < n; ++k) {
    legendre_all(xs[k], n, pk);
    for (int j = 0; j < n; ++j) {
      legendre_all(xs[j], n, pj);
      double s = 0.5 * (xs[k] + 1.0);
      for (int m = 1; m < n; ++m) s += 0.5 * pj[m] * (pk[m + 1] - pk[m - 1]);
      rule->partial[k][j] = 0.5 * ws[j] * s;   /* [-1,1] -> [0,1] halves it */
    }
  }
  return 0;
}

double sf_gauss_legendre_integral(const double *coef, int n, double x) {
  /* On [-1, 1]: the integral of P_0 from -1 to y is y + 1, of P_m it is
   * (P_{m+1}(y) - P_{m-1}(y)) / (2m + 1); the change of variable halves it. */
  double y = 2.0 * x - 1.0;
  double p_prev = 1.0, p = y;   /* P_{m-1}, P_m */
  double s = coef[0] * (y + 1.0);
  for (int m = 1; m < n; ++m) {
    double p_next = ((2 * m + 1) * y * p - m * p_prev) / (m + 1);
    s += coef[m] * (p_next - p_prev) / (2 * m + 1);
    p_prev = p;
    p = p_next;
  }
  return 0.5 * s;
}
