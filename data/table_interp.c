#include "data/table_interp.h"

#include <math.h>

sf_grid_view sf_grid_view_of(const sf_table *t) {
  sf_grid_view g;
  g.data = t->data;
  for (int k = 0; k < 4; ++k) g.size[k] = k < t->desc.n_axes ? t->desc.axes[k].size : 1;
  g.n_values = t->desc.n_channels;
  return g;
}

void sf_grid_corners(const sf_grid_view *g, const double *pos, long offsets[16], double weights[16]) {
  long lo[4], step[4];
  double f[4];
  long stride = 1;
  for (int k = 0; k < 4; ++k) {
    int n = g->size[k];
    double p = pos[k];
    if (!(p > 0.0)) p = 0.0;   /* also maps NaN to 0 */
    if (p > n - 1) p = n - 1;
    long i = (long)p;
    if (i > n - 2) i = n - 2 > 0 ? n - 2 : 0;
    f[k] = n > 1 ? p - (double)i : 0.0;
    lo[k] = i * stride;
    step[k] = n > 1 ? stride : 0;
    stride *= n;
  }
  for (int c = 0; c < 16; ++c) {
    long off = 0;
    double w = 1.0;
    for (int k = 0; k < 4; ++k) {
      int upper = (c >> k) & 1;
      off += lo[k] + (upper ? step[k] : 0);
      w *= upper ? f[k] : 1.0 - f[k];
    }
    offsets[c] = off;
    weights[c] = w;
  }
}

void sf_grid_interp(const sf_grid_view *g, const double *pos, double *out) {
  long offsets[16];
  double weights[16];
  sf_grid_corners(g, pos, offsets, weights);
  int nv = g->n_values;
  for (int v = 0; v < nv; ++v) out[v] = 0.0;
  for (int c = 0; c < 16; ++c) {
    if (weights[c] == 0.0) continue;
    const float *src = g->data + offsets[c] * nv;
    for (int v = 0; v < nv; ++v) out[v] += weights[c] * src[v];
  }
}

void sf_grid_interp_geometric(const sf_grid_view *g, int axis, const double *pos, double *out) {
  long offsets[16];
  double weights[16];
  sf_grid_corners(g, pos, offsets, weights);
  int nv = g->n_values, bit = 1 << axis;
  /* the weight of a corner pair along axis, and the fraction between them */
  for (int v = 0; v < nv; ++v) out[v] = 0.0;
  for (int c = 0; c < 16; ++c) {
    if (c & bit) continue;
    double w_lo = weights[c], w_hi = weights[c | bit], w = w_lo + w_hi;
    if (w == 0.0) continue;
    double f = w_hi / w;
    const float *lo = g->data + offsets[c] * nv, *hi = g->data + offsets[c | bit] * nv;
    for (int v = 0; v < nv; ++v) {
      double a = lo[v], b = hi[v];
      out[v] += w * (a > 0.0 && b > 0.0 && f > 0.0 && f < 1.0 ? a * pow(b / a, f) : (1.0 - f) * a + f * b);
    }
  }
}
