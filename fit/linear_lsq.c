#include "fit/linear_lsq.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sf_linear_lsq(int m, int n, const double *A, const double *b, const double *w, double *x) {
  if (m < n || n <= 0 || n > 64) return -1;
  double *R = malloc(sizeof *R * (size_t)m * (size_t)(n + 1));
  if (!R) return -1;
  /* Augmented [wA | wb], Householder on the first n columns. */
  for (int i = 0; i < m; ++i) {
    double wi = w ? w[i] : 1.0;
    for (int j = 0; j < n; ++j) R[i * (n + 1) + j] = wi * A[i * n + j];
    R[i * (n + 1) + n] = wi * b[i];
  }
  double scale_max = 0.0;
  int status = 0;
  for (int k = 0; k < n && status == 0; ++k) {
    double norm = 0.0;
    for (int i = k; i < m; ++i) norm = hypot(norm, R[i * (n + 1) + k]);
    if (k == 0) scale_max = norm;
    if (norm <= 1e-14 * scale_max || norm == 0.0) {
      status = -1;
      break;
    }
    double alpha = R[k * (n + 1) + k] > 0 ? -norm : norm;
    /* v = x - alpha e1, stored in place; beta = 2 / |v|^2 */
    R[k * (n + 1) + k] -= alpha;
    double vnorm2 = 0.0;
    for (int i = k; i < m; ++i) vnorm2 += R[i * (n + 1) + k] * R[i * (n + 1) + k];
    for (int j = k + 1; j <= n; ++j) {
      double dot = 0.0;
      for (int i = k; i < m; ++i) dot += R[i * (n + 1) + k] * R[i * (n + 1) + j];
      double f = 2.0 * dot / vnorm2;
      for (int i = k; i < m; ++i) R[i * (n + 1) + j] -= f * R[i * (n + 1) + k];
    }
    R[k * (n + 1) + k] = alpha;
  }
  if (status == 0)
    for (int k = n - 1; k >= 0; --k) {
      double s = R[k * (n + 1) + n];
      for (int j = k + 1; j < n; ++j) s -= R[k * (n + 1) + j] * x[j];
      x[k] = s / R[k * (n + 1) + k];
    }
  free(R);
  return status;
}
