#include "data/table.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Size of axis k, 1 for axes the table does not have (the tiling formula
 * treats a 2D table as a 4D one with n2 = n3 = 1). */
static int axis_size(const sf_table_desc *d, int k) {
  return k < d->n_axes ? d->axes[k].size : 1;
}

/* Non-empty, NUL-terminated within cap, only [A-Za-z0-9_.-]. */
static int name_ok(const char *s, size_t cap) {
  size_t n = strnlen(s, cap);
  if (n == 0 || n == cap) return 0;
  for (size_t i = 0; i < n; ++i) {
    char c = s[i];
    int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
             c == '_' || c == '.' || c == '-';
    if (!ok) return 0;
  }
  return 1;
}

static int hash_ok(const char *s) {
  size_t n = strnlen(s, 17);
  if (n == 0) return 1;
  if (n != 16) return 0;
  for (size_t i = 0; i < n; ++i)
    if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'f'))) return 0;
  return 1;
}

void sf_table_desc_set_channels(sf_table_desc *desc, const sf_atmosphere *atm) {
  desc->n_channels = atm->n_channels;
  for (int c = 0; c < atm->n_channels && c < SF_MAX_CHANNELS; ++c) {
    memcpy(desc->channel_names[c], atm->channel_names[c], SF_TABLE_CHANNEL_NAME_LEN);
    desc->channel_names[c][SF_TABLE_CHANNEL_NAME_LEN - 1] = '\0';
  }
}

int sf_table_desc_check(const sf_table_desc *d, size_t max_bytes, sf_error *err) {
  if (max_bytes == 0) max_bytes = SF_TABLE_DEFAULT_MAX_BYTES;
  if (!name_ok(d->quantity, sizeof d->quantity))
    return sf_fail(err, SF_ERR_INPUT, "table quantity '%.*s' must be 1-%d characters of [A-Za-z0-9_.-]",
                   (int)sizeof d->quantity, d->quantity, (int)sizeof d->quantity - 1);
  if (!name_ok(d->parameterization, sizeof d->parameterization))
    return sf_fail(err, SF_ERR_INPUT,
                   "table parameterization '%.*s' must be 1-%d characters of [A-Za-z0-9_.-]",
                   (int)sizeof d->parameterization, d->parameterization,
                   (int)sizeof d->parameterization - 1);
  if (d->n_axes < 1 || d->n_axes > SF_TABLE_MAX_AXES)
    return sf_fail(err, SF_ERR_INPUT, "table has %d axes; 1 to %d are supported", d->n_axes,
                   SF_TABLE_MAX_AXES);
  /* Every count is checked against the budget before it is multiplied, so
   * no product below can overflow size_t. */
  size_t max_floats = max_bytes / sizeof(float);
  size_t points = 1;
  for (int k = 0; k < d->n_axes; ++k) {
    const sf_table_axis *a = &d->axes[k];
    if (!name_ok(a->name, sizeof a->name))
      return sf_fail(err, SF_ERR_INPUT, "table axis %d: name '%.*s' must be 1-%d characters of [A-Za-z0-9_.-]",
                     k, (int)sizeof a->name, a->name, (int)sizeof a->name - 1);
    if (!name_ok(a->mapping, sizeof a->mapping))
      return sf_fail(err, SF_ERR_INPUT, "table axis %d (%s): mapping '%.*s' must be 1-%d characters of [A-Za-z0-9_.-]",
                     k, a->name, (int)sizeof a->mapping, a->mapping, (int)sizeof a->mapping - 1);
    if (a->size < 1)
      return sf_fail(err, SF_ERR_INPUT, "table axis %d (%s): size %d must be at least 1", k, a->name, a->size);
    if (!isfinite(a->min) || !isfinite(a->max))
      return sf_fail(err, SF_ERR_INPUT, "table axis %d (%s): range [%g, %g] must be finite", k, a->name,
                     a->min, a->max);
    if ((size_t)a->size > max_floats / points)
      return sf_fail(err, SF_ERR_INPUT, "table of %d axes is larger than the %zu-byte limit (at axis %d, %s, size %d)",
                     d->n_axes, max_bytes, k, a->name, a->size);
    points *= (size_t)a->size;
  }
  if (d->n_channels < 1 || d->n_channels > SF_MAX_CHANNELS)
    return sf_fail(err, SF_ERR_INPUT, "table has %d channels; 1 to %d are supported", d->n_channels,
                   SF_MAX_CHANNELS);
  if ((size_t)d->n_channels > max_floats / points)
    return sf_fail(err, SF_ERR_INPUT, "table of %zu samples x %d channels is larger than the %zu-byte limit",
                   points, d->n_channels, max_bytes);
  for (int c = 0; c < d->n_channels; ++c) {
    if (!name_ok(d->channel_names[c], sizeof d->channel_names[c]))
      return sf_fail(err, SF_ERR_INPUT, "table channel %d: name '%.*s' must be 1-%d characters of [A-Za-z0-9_.-]",
                     c, (int)sizeof d->channel_names[c], d->channel_names[c],
                     (int)sizeof d->channel_names[c] - 1);
    for (int o = 0; o < c; ++o)
      if (strcmp(d->channel_names[o], d->channel_names[c]) == 0)
        return sf_fail(err, SF_ERR_INPUT, "table channels %d and %d are both named '%s'", o, c,
                       d->channel_names[c]);
  }
  /* EXR pictures are indexed by int32; one scanline must also fit. */
  long long width = (long long)axis_size(d, 0) * axis_size(d, 2);
  long long height = (long long)axis_size(d, 1) * axis_size(d, 3);
  if (width > INT32_MAX / 2 || height > INT32_MAX / 2 ||
      width * d->n_channels > INT32_MAX / (long long)sizeof(float))
    return sf_fail(err, SF_ERR_INPUT, "table image of %lld x %lld pixels x %d channels is too large for EXR",
                   width, height, d->n_channels);
  if (!hash_ok(d->content_hash))
    return sf_fail(err, SF_ERR_INPUT, "table content hash '%.*s' must be empty or 16 lowercase hex digits",
                   (int)sizeof d->content_hash, d->content_hash);
  return SF_OK;
}

static int same_double(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

int sf_table_desc_equal(const sf_table_desc *a, const sf_table_desc *b) {
  if (strncmp(a->quantity, b->quantity, SF_TABLE_NAME_LEN) != 0 || strncmp(a->parameterization, b->parameterization, SF_TABLE_NAME_LEN) != 0 ||
      strncmp(a->content_hash, b->content_hash, 17) != 0 || a->n_axes != b->n_axes ||
      a->n_channels != b->n_channels)
    return 0;
  for (int k = 0; k < a->n_axes && k < SF_TABLE_MAX_AXES; ++k) {
    const sf_table_axis *x = &a->axes[k], *y = &b->axes[k];
    if (strncmp(x->name, y->name, SF_TABLE_NAME_LEN) != 0 ||
        strncmp(x->mapping, y->mapping, SF_TABLE_NAME_LEN) != 0 || x->size != y->size ||
        !same_double(x->min, y->min) || !same_double(x->max, y->max))
      return 0;
  }
  for (int c = 0; c < a->n_channels && c < SF_MAX_CHANNELS; ++c)
    if (strncmp(a->channel_names[c], b->channel_names[c], SF_TABLE_CHANNEL_NAME_LEN) != 0) return 0;
  return 1;
}

size_t sf_table_desc_points(const sf_table_desc *desc) {
  size_t points = 1;
  for (int k = 0; k < desc->n_axes; ++k) points *= (size_t)desc->axes[k].size;
  return points;
}

void sf_table_desc_image_size(const sf_table_desc *desc, int *width, int *height) {
  *width = axis_size(desc, 0) * axis_size(desc, 2);
  *height = axis_size(desc, 1) * axis_size(desc, 3);
}

int sf_table_init(sf_table *t, const sf_table_desc *desc, const char *atmosphere_json,
                  size_t max_bytes, sf_error *err) {
  memset(t, 0, sizeof *t);
  if (sf_table_desc_check(desc, max_bytes, err) != SF_OK) return SF_ERR_INPUT;
  size_t floats = sf_table_desc_points(desc) * (size_t)desc->n_channels;
  const char *json = atmosphere_json ? atmosphere_json : "";
  size_t json_bytes = strlen(json) + 1;
  float *data = calloc(floats, sizeof(float));
  char *json_copy = malloc(json_bytes);
  if (!data || !json_copy) {
    free(data);
    free(json_copy);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory allocating a %s table of %zu floats",
                   desc->quantity, floats);
  }
  memcpy(json_copy, json, json_bytes);
  t->desc = *desc;
  sf_table_desc_image_size(desc, &t->width, &t->height);
  t->atmosphere_json = json_copy;
  t->data = data;
  return SF_OK;
}

void sf_table_free(sf_table *t) {
  free(t->data);
  free(t->atmosphere_json);
  memset(t, 0, sizeof *t);
}

void sf_table_pixel_of(const sf_table_desc *desc, const int *index, int *x, int *y) {
  int i[SF_TABLE_MAX_AXES] = {0, 0, 0, 0};
  for (int k = 0; k < desc->n_axes; ++k) i[k] = index[k];
  *x = i[0] + axis_size(desc, 0) * i[2];
  *y = i[1] + axis_size(desc, 1) * i[3];
}

void sf_table_index_of(const sf_table_desc *desc, int x, int y, int *index) {
  int i[SF_TABLE_MAX_AXES];
  i[0] = x % axis_size(desc, 0);
  i[2] = x / axis_size(desc, 0);
  i[1] = y % axis_size(desc, 1);
  i[3] = y / axis_size(desc, 1);
  for (int k = 0; k < desc->n_axes; ++k) index[k] = i[k];
}
