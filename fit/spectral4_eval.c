#include "fit/spectral4_eval.h"

#include <math.h>
#include <stdlib.h>

#include "models/color_space.h"
#include "models/spectral_reference.h"
#include "util/sort_doubles.h"

void sf_color_method_apply(const sf_color_method *m, const sf_cmf *cmf, int n, const double *lambda_nm,
                           const double *L, double rgb[3]) {
  if (m->kind == SF_COLOR_PLAIN_RGB) {
    for (int c = 0; c < 3; ++c) rgb[c] = m->rgb_scale * sf_spectrum_at(n, lambda_nm, L, m->rgb_nm[c]);
    return;
  }
  double xyz[3] = {0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    double bar[3], l = sf_spectrum_at(n, lambda_nm, L, m->four.lambda_nm[i]);
    sf_cmf_at(cmf, m->four.lambda_nm[i], bar);
    for (int c = 0; c < 3; ++c) xyz[c] += m->four.weight_nm[i] * bar[c] * l;   /* seed 003 eq. 5.12 */
  }
  sf_xyz_to_linear_srgb(xyz, rgb);
}

void sf_delta_e_summarise(double *values, size_t n, sf_delta_e_stats *out) {
  out->n = n;
  out->mean = out->p99 = out->max = 0.0;
  if (n == 0) return;
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) sum += values[i];
  sf_sort_doubles(values, n);
  size_t rank = (size_t)ceil(0.99 * (double)n);   /* nearest rank, 1-based */
  if (rank < 1) rank = 1;
  out->mean = sum / (double)n;
  out->p99 = values[rank - 1];
  out->max = values[n - 1];
}
