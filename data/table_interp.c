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
