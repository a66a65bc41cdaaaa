/* Multilinear interpolation in a float grid laid out as data/table.h lays
 * out a table (values of a sample contiguous, axes[0] next, ...). Positions
 * are fractional indices (data/table_params.h), clamped into each axis. */
#ifndef SKYFIT_DATA_TABLE_INTERP_H
#define SKYFIT_DATA_TABLE_INTERP_H

#include "data/table.h"

typedef struct sf_grid_view {
  const float *data;
  int size[4];        /* axes; missing axes have size 1 */
  int n_values;       /* values per sample */
} sf_grid_view;

/* A view of a table's data. */
sf_grid_view sf_grid_view_of(const sf_table *t);

/* out[0..n_values-1] = the values interpolated at pos[0..3]. */
void sf_grid_interp(const sf_grid_view *g, const double *pos, double *out);

/* Multilinear, except along `axis`, where each pair of corners is
 * interpolated geometrically (linearly in the logarithm) when both are > 0.
 * Exact for values that fall exponentially along that axis, as scattered
 * light does with the sun's depression below the horizon (the planet's
 * shadow), where linear interpolation overestimates by tens of percent. */
void sf_grid_interp_geometric(const sf_grid_view *g, int axis, const double *pos, double *out);

/* Corner offsets and weights of the interpolation at pos: 2^4 corners
 * (some with weight 0). For callers that combine several grids of one
 * layout. offsets are in samples (multiply by n_values for floats). */
void sf_grid_corners(const sf_grid_view *g, const double *pos, long offsets[16], double weights[16]);

#endif
