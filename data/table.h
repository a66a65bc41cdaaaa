/* A self-describing table of float samples over 1–4 axes with one value per
 * colour channel (SPEC §6 "Tables"): transmittance over (h, mu), scattering
 * over (h, mu, mu_s, nu). The description (sf_table_desc) says what the
 * numbers are; data/table_exr.h stores both in one EXR file.
 *
 * Memory layout (axis order, channels interleaved):
 *   value(i0, i1, i2, i3; c) = data[c + n_channels *
 *                                   (i0 + n0 * (i1 + n1 * (i2 + n2 * i3)))]
 * where n_k = axes[k].size; axes[0] varies fastest, missing axes have size 1.
 *
 * Image layout (the EXR picture, and a GPU upload of it): a 4D table is
 * tiled into 2D. Each tile is an n0 x n1 picture of axes 0 and 1; the tiles
 * form an n2-column, n3-row grid:
 *   x = i0 + n0 * i2,   y = i1 + n1 * i3,   width = n0*n2, height = n1*n3.
 * With axes (h², cos view, cos light, cos gamma) this is Leenman's Figure 6
 * (seed 000 §9.1: x/y inside a tile = h², cos θv; tile x/y = cos θl, cos γ);
 * with Bruneton's axes (mu_s, mu, nu, h) — data/table_params.h — it is his
 * 3D scattering texture (x = mu_s + MU_S_SIZE * nu, y = mu) with its depth
 * slices (h, i.e. r) stacked vertically: y = mu + MU_SIZE * h.
 * A 2D table is a plain n0 x n1 picture; a 1D table one row. */
#ifndef SKYFIT_DATA_TABLE_H
#define SKYFIT_DATA_TABLE_H

#include <stddef.h>
#include "models/atmosphere.h"
#include "util/error.h"

#define SF_TABLE_MAX_AXES 4
#define SF_TABLE_NAME_LEN 32
#define SF_TABLE_CHANNEL_NAME_LEN 16   /* = sf_atmosphere.channel_names */
#define SF_TABLE_DEFAULT_MAX_BYTES ((size_t)4 << 30)   /* 4 GiB */

/* One axis. Sample i of the axis stands for the value of the quantity
 * `name` obtained by `mapping` (a parameterisation's name for its index ->
 * value function, e.g. "leenman_x", "bruneton_r", "linear") over the range
 * [min, max]. The table itself does not interpret mapping, min or max; it
 * only stores them so that the file says what its samples mean. */
typedef struct sf_table_axis {
  char name[SF_TABLE_NAME_LEN];      /* e.g. "h_km", "mu", "mu_s", "nu" */
  int size;                          /* samples, >= 1 */
  double min, max;                   /* finite */
  char mapping[SF_TABLE_NAME_LEN];
} sf_table_axis;

/* What a table holds. A plain value: fill it (memset to 0 first), copy it.
 * Names are non-empty and use only [A-Za-z0-9_.-] so that they are safe in
 * file names, EXR channel names and JSON. */
typedef struct sf_table_desc {
  char quantity[SF_TABLE_NAME_LEN];         /* "transmittance", "single_rayleigh",
                                               "single_mie", "multiple", ... */
  char parameterization[SF_TABLE_NAME_LEN]; /* "leenman", "bruneton", ... */
  int n_axes;                               /* 1..SF_TABLE_MAX_AXES */
  sf_table_axis axes[SF_TABLE_MAX_AXES];    /* axes[0] varies fastest */
  int n_channels;                           /* 1..SF_MAX_CHANNELS */
  char channel_names[SF_MAX_CHANNELS][SF_TABLE_CHANNEL_NAME_LEN]; /* unique */
  char content_hash[17];  /* "" or 16 lowercase hex digits: the cache key of
                             what determined the table (data/table_cache.h) */
} sf_table_desc;

/* How a multiple-scattering table's orders ended (data/precompute_multiple.h),
 * kept with the table (the EXR header's skyfit:orders) so that a table
 * from the cache says what the computed one said. */
typedef struct sf_table_orders {
  int highest;              /* last order computed; 0: not known (any other table) */
  double left_fraction;     /* what the orders after it would add, as a fraction
                               of the sky radiance; may be INFINITY */
} sf_table_orders;

typedef struct sf_table {
  sf_table_desc desc;
  int width, height;        /* image layout above, derived from desc */
  char *atmosphere_json;    /* canonical atmosphere JSON ("" if none), owned */
  float *data;              /* memory layout above, owned */
  sf_table_orders orders;
} sf_table;

/* Copies the channel names of an atmosphere into desc (n_channels too). */
void sf_table_desc_set_channels(sf_table_desc *desc, const sf_atmosphere *atm);

/* Checks a description: names, sizes, finite ranges, unique channels, and
 * that the data fit in max_bytes (0 = SF_TABLE_DEFAULT_MAX_BYTES) and in an
 * EXR picture. SF_ERR_INPUT with a message naming the field otherwise. */
int sf_table_desc_check(const sf_table_desc *desc, size_t max_bytes, sf_error *err);

/* 1 if a and b describe the same table: every field above, doubles
 * compared bit for bit, unused axis/channel slots ignored. */
int sf_table_desc_equal(const sf_table_desc *a, const sf_table_desc *b);

/* Samples per channel: n0 * n1 * n2 * n3 (desc must pass the check). */
size_t sf_table_desc_points(const sf_table_desc *desc);

/* Allocates a zero-filled table for desc (checked as above) and copies
 * atmosphere_json (NULL means ""). On failure *t is empty (safe to free). */
int sf_table_init(sf_table *t, const sf_table_desc *desc, const char *atmosphere_json,
                  size_t max_bytes, sf_error *err);
/* Releases the data and JSON and empties *t; safe on an empty table. */
void sf_table_free(sf_table *t);

/* Offset (in floats) of channel 0 of the sample at index[0..n_axes-1];
 * every index must lie in [0, axes[k].size). */
static inline size_t sf_table_offset(const sf_table *t, const int *index) {
  size_t linear = 0;
  for (int k = t->desc.n_axes - 1; k >= 0; --k)
    linear = linear * (size_t)t->desc.axes[k].size + (size_t)index[k];
  return linear * (size_t)t->desc.n_channels;
}
/* The n_channels values of one sample (pointer into t->data). */
static inline float *sf_table_at(const sf_table *t, const int *index) {
  return t->data + sf_table_offset(t, index);
}

/* Width and height of the image layout (desc must pass the check). */
void sf_table_desc_image_size(const sf_table_desc *desc, int *width, int *height);
/* Image position of a sample, and back (the tiling above). */
void sf_table_pixel_of(const sf_table_desc *desc, const int *index, int *x, int *y);
void sf_table_index_of(const sf_table_desc *desc, int x, int y, int *index);

#endif
