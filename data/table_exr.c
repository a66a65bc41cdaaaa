#include "data/table_exr.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenEXR/openexr.h>

#include "util/atomic_file.h"
#include "util/exr_fd_write.h"
#include "util/hash64.h"

/* The ZIP level is set per file so that the bytes do not depend on the
 * library's process-wide default (which any code could change). */
#define TABLE_ZIP_LEVEL 6

/* ---- I/O glue: OpenEXR talks to our file descriptor through pread/pwrite,
 * and its error messages land here instead of on stderr. ---- */

typedef struct exr_stream {
  int fd;
  char message[512];   /* first error OpenEXR reported */
  int write_errno;     /* the first failed write's errno, 0 if none */
} exr_stream;

static void keep_first_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  void *user = NULL;
  if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
  exr_stream *s = (exr_stream *)user;
  if (s->message[0] != '\0') return;
  snprintf(s->message, sizeof s->message, "%s", msg ? msg : exr_get_default_error_message(code));
  /* Messages about damaged headers quote the damaged bytes; keep ours text. */
  for (char *c = s->message; *c; ++c)
    if ((unsigned char)*c < 0x20 || (unsigned char)*c > 0x7e) *c = '?';
}

static int64_t stream_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  exr_stream *s = (exr_stream *)user;
  return sf_exr_write_fd(ctxt, s->fd, buffer, sz, offset, error_cb, &s->write_errno);
}

static int64_t stream_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  exr_stream *s = (exr_stream *)user;
  char *p = (char *)buffer;
  uint64_t done = 0;
  while (done < sz) {
    ssize_t n = pread(s->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s", strerror(errno));
      return -1;
    }
    if (n == 0) break;   /* end of file: a short count tells OpenEXR */
    done += (uint64_t)n;
  }
  return (int64_t)done;
}

static int64_t stream_size(exr_const_context_t ctxt, void *user) {
  (void)ctxt;
  struct stat st;
  return fstat(((exr_stream *)user)->fd, &st) == 0 ? (int64_t)st.st_size : -1;
}

static const char *exr_reason(const exr_stream *s, exr_result_t rv) {
  return s->message[0] ? s->message : exr_get_default_error_message(rv);
}

/* A write context's error handler keeps nothing: OpenEXR calls it with the
 * context's lock held (from exr_write_header's writes), and
 * exr_get_user_data takes that lock, so keep_first_error there waited on
 * itself forever (a full disk under the header hung sample and build). The
 * failed write's errno reaches the stream through the write callback's own
 * user pointer instead (sf_exr_write_fd). */
static void ignore_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt;
  (void)code;
  (void)msg;
}

static void write_reason(const exr_stream *s, exr_result_t rv, char *text, size_t n) {
  if (s->write_errno) snprintf(text, n, "write failed: %s", strerror(s->write_errno));
  else snprintf(text, n, "%s", exr_get_default_error_message(rv));
}

/* A write that failed (a full disk: exit 1) or OpenEXR refusing the table,
 * which sf_table_desc_check has passed (ours to fix: exit 1 too). */
static int write_failure_status(const exr_stream *s) {
  return s->write_errno ? sf_write_error_status(s->write_errno) : SF_ERR_INTERNAL;
}

/* ---- The skyfit header strings and the checksum ---- */

enum {
  ATTR_FORMAT, ATTR_QUANTITY, ATTR_PARAMETERIZATION, ATTR_AXES, ATTR_CHANNELS, ATTR_TILING,
  ATTR_ATMOSPHERE, ATTR_CONTENT_HASH, ATTR_COUNT
};
static const char *const attr_names[ATTR_COUNT] = {
  "skyfit:format", "skyfit:quantity", "skyfit:parameterization", "skyfit:axes",
  "skyfit:channels", "skyfit:tiling", "skyfit:atmosphere", "skyfit:content_hash"};
#define ATTR_CHECKSUM "skyfit:checksum"
/* Optional (multiple scattering only): "HIGHEST LEFT", data/table.h's
 * sf_table_orders, e.g. "6 0.00123" or "2 inf". */
#define ATTR_ORDERS "skyfit:orders"

/* The skyfit:orders text of o in text (at most n bytes), or NULL if the
 * table has none. */
static const char *orders_text(const sf_table_orders *o, char *text, size_t n) {
  if (o->highest < 1) return NULL;
  snprintf(text, n, "%d %.17g", o->highest, o->left_fraction);
  return text;
}

/* Parses an orders text; returns NULL or what is wrong. */
static const char *parse_orders(const char *text, sf_table_orders *o) {
  char *end = NULL;
  long highest = strtol(text, &end, 10);
  if (end == text || *end != ' ' || highest < 1 || highest > INT_MAX) return "does not start with an order >= 1";
  const char *number = end + 1;
  double left = strtod(number, &end);
  if (end == number || *end != '\0' || !(left >= 0.0)) return "does not end with a fraction >= 0 (or inf)";
  o->highest = (int)highest;
  o->left_fraction = left;
  return NULL;
}

static cJSON *exact_number(double v) {
  /* cJSON prints 15 digits when they compare "close enough"; 17 are needed
   * for the axis ranges to come back bit-identical. */
  char text[40];
  snprintf(text, sizeof text, "%.17g", v);
  return cJSON_CreateRaw(text);
}

/* cJSON-allocated JSON text of the axes (free with cJSON_free), or NULL. */
static char *axes_json(const sf_table_desc *d) {
  cJSON *array = cJSON_CreateArray();
  for (int k = 0; array && k < d->n_axes; ++k) {
    const sf_table_axis *a = &d->axes[k];
    cJSON *o = cJSON_CreateObject();
    if (!o) { cJSON_Delete(array); return NULL; }
    cJSON_AddItemToArray(array, o);
    cJSON_AddStringToObject(o, "name", a->name);
    cJSON_AddNumberToObject(o, "size", a->size);
    cJSON_AddItemToObject(o, "min", exact_number(a->min));
    cJSON_AddItemToObject(o, "max", exact_number(a->max));
    cJSON_AddStringToObject(o, "mapping", a->mapping);
  }
  char *text = array ? cJSON_PrintUnformatted(array) : NULL;
  cJSON_Delete(array);
  return text;
}

static char *channels_json(const sf_table_desc *d) {
  cJSON *array = cJSON_CreateArray();
  for (int c = 0; array && c < d->n_channels; ++c)
    cJSON_AddItemToArray(array, cJSON_CreateString(d->channel_names[c]));
  char *text = array ? cJSON_PrintUnformatted(array) : NULL;
  cJSON_Delete(array);
  return text;
}

static uint64_t checksum(const char *const strings[ATTR_COUNT], const char *orders, const float *data, size_t n) {
  uint64_t h = SF_FNV1A64_OFFSET;
  for (int i = 0; i < ATTR_COUNT; ++i) h = sf_fnv1a64_field(h, strings[i]);
  if (orders) h = sf_fnv1a64_field(h, orders);
  for (size_t i = 0; i < n; ++i) {
    uint32_t bits;
    memcpy(&bits, &data[i], sizeof bits);
    unsigned char le[4] = {(unsigned char)bits, (unsigned char)(bits >> 8),
                           (unsigned char)(bits >> 16), (unsigned char)(bits >> 24)};
    h = sf_fnv1a64(h, le, 4);
  }
  return h;
}

/* Table channel whose name is `name`, or -1. */
static int channel_index(const sf_table_desc *d, const char *name) {
  for (int c = 0; c < d->n_channels; ++c)
    if (strcmp(d->channel_names[c], name) == 0) return c;
  return -1;
}

/* Row y of the image layout <-> the table's memory: for fixed (i1, i3) and
 * tile column i2, the n0 samples of axis 0 are contiguous in both. */
static void gather_row(const sf_table *t, int y, float *row) {
  const sf_table_desc *d = &t->desc;
  int index[SF_TABLE_MAX_AXES] = {0, 0, 0, 0};
  int n0 = d->axes[0].size, n_ch = d->n_channels;
  for (int x = 0; x < t->width; x += n0) {
    sf_table_index_of(d, x, y, index);
    memcpy(row + (size_t)x * n_ch, sf_table_at(t, index), sizeof(float) * (size_t)n0 * n_ch);
  }
}

static void scatter_row(sf_table *t, int y, const float *row) {
  const sf_table_desc *d = &t->desc;
  int index[SF_TABLE_MAX_AXES] = {0, 0, 0, 0};
  int n0 = d->axes[0].size, n_ch = d->n_channels;
  for (int x = 0; x < t->width; x += n0) {
    sf_table_index_of(d, x, y, index);
    memcpy(sf_table_at(t, index), row + (size_t)x * n_ch, sizeof(float) * (size_t)n0 * n_ch);
  }
}

/* ---- Writing ---- */

static int first_non_finite(const float *v, size_t n, size_t *at) {
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(v[i])) { *at = i; return 1; }
  return 0;
}

/* Encodes every scanline chunk from t into the open context. */
static int write_pixels(exr_context_t ctx, int part, const sf_table *t, const char *path,
                        const exr_stream *stream, sf_error *err) {
  const sf_table_desc *d = &t->desc;
  int32_t chunks = 0, lines = 0;
  exr_result_t rv = exr_get_chunk_count(ctx, part, &chunks);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
  if (rv != EXR_ERR_SUCCESS || lines < 1)
    return sf_fail(err, SF_ERR_INTERNAL, "%s: OpenEXR chunk layout: %s", path, exr_get_default_error_message(rv));
  size_t row_floats = (size_t)t->width * d->n_channels;
  float *rows = malloc(sizeof(float) * row_floats * (size_t)lines);
  if (!rows) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", path);
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int status = SF_OK, initialised = 0;
  for (int32_t ci = 0; ci < chunks && status == SF_OK; ++ci) {
    int y0 = ci * lines;
    exr_chunk_info_t cinfo;
    rv = exr_write_scanline_chunk_info(ctx, part, y0, &cinfo);
    if (rv == EXR_ERR_SUCCESS) {
      rv = initialised ? exr_encoding_update(ctx, part, &cinfo, &enc)
                       : exr_encoding_initialize(ctx, part, &cinfo, &enc);
      initialised = initialised || rv == EXR_ERR_SUCCESS;
    }
    if (rv != EXR_ERR_SUCCESS) {
      char why[300];
      write_reason(stream, rv, why, sizeof why);
      status = sf_fail(err, write_failure_status(stream), "%s: OpenEXR chunk %d: %s", path, (int)ci, why);
      break;
    }
    for (int ly = 0; ly < cinfo.height; ++ly) gather_row(t, y0 + ly, rows + (size_t)ly * row_floats);
    size_t bad;
    if (first_non_finite(rows, row_floats * (size_t)cinfo.height, &bad)) {
      int x = (int)((bad / d->n_channels) % (size_t)t->width);
      int y = y0 + (int)(bad / row_floats);
      int index[SF_TABLE_MAX_AXES] = {0, 0, 0, 0};
      sf_table_index_of(d, x, y, index);
      status = sf_fail(err, SF_ERR_INTERNAL,
                       "%s: refusing to write a %s table holding %g at index (%d, %d, %d, %d) channel %s",
                       path, d->quantity, rows[bad], index[0], index[1], index[2], index[3],
                       d->channel_names[bad % (size_t)d->n_channels]);
      break;
    }
    for (int k = 0; k < enc.channel_count; ++k) {
      exr_coding_channel_info_t *ch = &enc.channels[k];
      int c = channel_index(d, ch->channel_name);
      if (c < 0) {
        status = sf_fail(err, SF_ERR_INTERNAL, "%s: OpenEXR reports unknown channel '%s'", path, ch->channel_name);
        break;
      }
      ch->encode_from_ptr = (const uint8_t *)(rows + c);
      ch->user_pixel_stride = (int32_t)(sizeof(float) * d->n_channels);
      ch->user_line_stride = (int32_t)(sizeof(float) * row_floats);
      ch->user_bytes_per_element = (int16_t)sizeof(float);
      ch->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (status != SF_OK) break;
    rv = exr_encoding_choose_default_routines(ctx, part, &enc);
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, &enc);
    if (rv != EXR_ERR_SUCCESS) {
      char why[300];
      write_reason(stream, rv, why, sizeof why);
      status = sf_fail(err, write_failure_status(stream), "%s: writing pixel chunk %d failed: %s", path, (int)ci, why);
    }
  }
  if (initialised) exr_encoding_destroy(ctx, &enc);
  free(rows);
  return status;
}

static int write_header(exr_context_t ctx, int *part, const sf_table *t, const char *const strings[ATTR_COUNT],
                        const char *orders, const char *checksum_hex) {
  const sf_table_desc *d = &t->desc;
  exr_result_t rv = exr_add_part(ctx, "table", EXR_STORAGE_SCANLINE, part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, *part, t->width, t->height, EXR_COMPRESSION_ZIP);
  if (rv == EXR_ERR_SUCCESS) rv = exr_set_zip_compression_level(ctx, *part, TABLE_ZIP_LEVEL);
  for (int c = 0; rv == EXR_ERR_SUCCESS && c < d->n_channels; ++c)
    rv = exr_add_channel(ctx, *part, d->channel_names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (int i = 0; rv == EXR_ERR_SUCCESS && i < ATTR_COUNT; ++i)
    rv = exr_attr_set_string(ctx, *part, attr_names[i], strings[i]);
  if (rv == EXR_ERR_SUCCESS && orders) rv = exr_attr_set_string(ctx, *part, ATTR_ORDERS, orders);
  if (rv == EXR_ERR_SUCCESS) rv = exr_attr_set_string(ctx, *part, ATTR_CHECKSUM, checksum_hex);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
  return rv;
}

int sf_table_write_exr(const sf_table *t, const char *path, sf_error *err) {
  sf_error check = {0};
  if (!t->data || sf_table_desc_check(&t->desc, SIZE_MAX, &check) != SF_OK)
    return sf_fail(err, SF_ERR_INTERNAL, "%s: not writing a malformed table: %s", path,
                   t->data ? check.message : "no data");
  char *axes = axes_json(&t->desc), *channels = channels_json(&t->desc);
  if (!axes || !channels) {
    cJSON_free(axes);
    cJSON_free(channels);
    return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", path);
  }
  const char *strings[ATTR_COUNT];
  strings[ATTR_FORMAT] = SF_TABLE_EXR_FORMAT;
  strings[ATTR_QUANTITY] = t->desc.quantity;
  strings[ATTR_PARAMETERIZATION] = t->desc.parameterization;
  strings[ATTR_AXES] = axes;
  strings[ATTR_CHANNELS] = channels;
  strings[ATTR_TILING] = SF_TABLE_EXR_TILING;
  strings[ATTR_ATMOSPHERE] = t->atmosphere_json ? t->atmosphere_json : "";
  strings[ATTR_CONTENT_HASH] = t->desc.content_hash;
  char orders_buf[64];
  const char *orders = orders_text(&t->orders, orders_buf, sizeof orders_buf);
  char checksum_hex[17];
  sf_hash64_hex(checksum(strings, orders, t->data, sf_table_desc_points(&t->desc) * (size_t)t->desc.n_channels),
                checksum_hex);

  int status = SF_OK;
  sf_atomic_file file;
  if (sf_atomic_open(&file, path, err) != SF_OK) status = err->status;
  exr_stream stream = {.fd = file.stream ? fileno(file.stream) : -1};
  exr_context_t ctx = NULL;
  if (status == SF_OK) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = ignore_write_error;
    init.user_data = &stream;
    init.write_fn = stream_write;
    init.zip_level = TABLE_ZIP_LEVEL;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    int part = 0;
    if (rv == EXR_ERR_SUCCESS) rv = write_header(ctx, &part, t, strings, orders, checksum_hex);
    char why[300];
    if (rv != EXR_ERR_SUCCESS) {
      write_reason(&stream, rv, why, sizeof why);
      status = sf_fail(err, write_failure_status(&stream), "%s: writing the EXR header failed: %s", path, why);
    }
    if (status == SF_OK) status = write_pixels(ctx, part, t, path, &stream, err);
    /* exr_finish writes the chunk offset table; its failure is a failed write. */
    rv = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (status == SF_OK && rv != EXR_ERR_SUCCESS) {
      write_reason(&stream, rv, why, sizeof why);
      status = sf_fail(err, write_failure_status(&stream), "%s: finishing the EXR file failed: %s", path, why);
    }
    if (status == SF_OK) status = sf_atomic_commit(&file, err);
    else sf_atomic_abort(&file);
  }
  cJSON_free(axes);
  cJSON_free(channels);
  return status;
}

/* ---- Reading ---- */

/* Copy of a string attribute (NUL-terminated, caller frees), or NULL with
 * *why set. */
static char *get_string_attr(exr_context_t ctx, const char *name, const char **why) {
  int32_t length = 0;
  const char *value = NULL;
  exr_result_t rv = exr_attr_get_string(ctx, 0, name, &length, &value);
  if (rv == EXR_ERR_NO_ATTR_BY_NAME) { *why = "is missing"; return NULL; }
  if (rv != EXR_ERR_SUCCESS || length < 0 || (length > 0 && !value)) {
    *why = "is not a readable string";
    return NULL;
  }
  if (memchr(value, '\0', (size_t)length)) { *why = "contains a NUL byte"; return NULL; }
  char *copy = malloc((size_t)length + 1);
  if (!copy) { *why = "does not fit in memory"; return NULL; }
  memcpy(copy, value, (size_t)length);
  copy[length] = '\0';
  return copy;
}

static int copy_name(char *dst, size_t cap, const char *src) {
  size_t n = strlen(src);
  if (n >= cap) return -1;
  memcpy(dst, src, n + 1);
  return 0;
}

/* Fills desc->axes from the skyfit:axes JSON; returns NULL or what is wrong. */
static const char *parse_axes(const char *text, sf_table_desc *desc) {
  cJSON *root = cJSON_Parse(text);
  const char *why = NULL;
  if (!cJSON_IsArray(root)) why = "is not a JSON array";
  else if (cJSON_GetArraySize(root) < 1 || cJSON_GetArraySize(root) > SF_TABLE_MAX_AXES)
    why = "must list 1 to 4 axes";
  else {
    desc->n_axes = cJSON_GetArraySize(root);
    int k = 0;
    for (const cJSON *o = root->child; o && !why; o = o->next, ++k) {
      sf_table_axis *a = &desc->axes[k];
      const cJSON *name = cJSON_GetObjectItemCaseSensitive(o, "name");
      const cJSON *size = cJSON_GetObjectItemCaseSensitive(o, "size");
      const cJSON *min = cJSON_GetObjectItemCaseSensitive(o, "min");
      const cJSON *max = cJSON_GetObjectItemCaseSensitive(o, "max");
      const cJSON *mapping = cJSON_GetObjectItemCaseSensitive(o, "mapping");
      if (!cJSON_IsString(name) || copy_name(a->name, sizeof a->name, name->valuestring))
        why = "has an axis without a valid \"name\"";
      else if (!cJSON_IsString(mapping) || copy_name(a->mapping, sizeof a->mapping, mapping->valuestring))
        why = "has an axis without a valid \"mapping\"";
      else if (!cJSON_IsNumber(size) || !(size->valuedouble >= 1.0 && size->valuedouble <= INT_MAX) ||
               size->valuedouble != floor(size->valuedouble))
        why = "has an axis whose \"size\" is not a positive integer";
      else if (!cJSON_IsNumber(min) || !cJSON_IsNumber(max))
        why = "has an axis without numeric \"min\" and \"max\"";
      else {
        a->size = (int)size->valuedouble;
        a->min = min->valuedouble;
        a->max = max->valuedouble;
      }
    }
  }
  cJSON_Delete(root);
  return why;
}

static const char *parse_channels(const char *text, sf_table_desc *desc) {
  cJSON *root = cJSON_Parse(text);
  const char *why = NULL;
  if (!cJSON_IsArray(root)) why = "is not a JSON array";
  else if (cJSON_GetArraySize(root) < 1 || cJSON_GetArraySize(root) > SF_MAX_CHANNELS)
    why = "must list 1 to 128 channel names";
  else {
    desc->n_channels = cJSON_GetArraySize(root);
    int c = 0;
    for (const cJSON *s = root->child; s && !why; s = s->next, ++c)
      if (!cJSON_IsString(s) ||
          copy_name(desc->channel_names[c], sizeof desc->channel_names[c], s->valuestring))
        why = "holds a channel name that is not a short string";
  }
  cJSON_Delete(root);
  return why;
}

/* Reads the skyfit attributes, checks them and allocates *out. */
static int read_description(exr_context_t ctx, const char *path, size_t max_bytes, sf_table *out,
                            char *strings[ATTR_COUNT], char checksum_hex[17], sf_error *err) {
  const char *why = NULL;
  for (int i = 0; i < ATTR_COUNT; ++i) {
    strings[i] = get_string_attr(ctx, attr_names[i], &why);
    if (!strings[i])
      return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s (not a skyfit table, or damaged)",
                     path, attr_names[i], why);
  }
  char *sum = get_string_attr(ctx, ATTR_CHECKSUM, &why);
  if (!sum)
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s", path, ATTR_CHECKSUM, why);
  int sum_ok = copy_name(checksum_hex, 17, sum) == 0 && strlen(sum) == 16;
  free(sum);
  if (!sum_ok) return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is not 16 hex digits", path, ATTR_CHECKSUM);
  if (strcmp(strings[ATTR_FORMAT], SF_TABLE_EXR_FORMAT) != 0)
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is '%.64s', expected '%s'", path,
                   attr_names[ATTR_FORMAT], strings[ATTR_FORMAT], SF_TABLE_EXR_FORMAT);
  if (strcmp(strings[ATTR_TILING], SF_TABLE_EXR_TILING) != 0)
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is '%.64s', expected '%s'", path,
                   attr_names[ATTR_TILING], strings[ATTR_TILING], SF_TABLE_EXR_TILING);
  sf_table_desc desc;
  memset(&desc, 0, sizeof desc);
  if (copy_name(desc.quantity, sizeof desc.quantity, strings[ATTR_QUANTITY]))
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is too long", path, attr_names[ATTR_QUANTITY]);
  if (copy_name(desc.parameterization, sizeof desc.parameterization, strings[ATTR_PARAMETERIZATION]))
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is too long", path,
                   attr_names[ATTR_PARAMETERIZATION]);
  if (copy_name(desc.content_hash, sizeof desc.content_hash, strings[ATTR_CONTENT_HASH]))
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s is too long", path,
                   attr_names[ATTR_CONTENT_HASH]);
  if ((why = parse_axes(strings[ATTR_AXES], &desc)))
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s", path, attr_names[ATTR_AXES], why);
  if ((why = parse_channels(strings[ATTR_CHANNELS], &desc)))
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s", path, attr_names[ATTR_CHANNELS], why);
  sf_table_orders orders = {0, 0.0};
  char *orders_attr = get_string_attr(ctx, ATTR_ORDERS, &why);
  if (orders_attr) {
    const char *bad = parse_orders(orders_attr, &orders);
    free(orders_attr);
    if (bad) return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s", path, ATTR_ORDERS, bad);
  } else if (strcmp(why, "is missing") != 0) {
    return sf_fail(err, SF_ERR_INPUT, "%s: header attribute %s %s", path, ATTR_ORDERS, why);
  }
  sf_error inner = {0};
  if (sf_table_init(out, &desc, strings[ATTR_ATMOSPHERE], max_bytes, &inner) != SF_OK)
    return sf_fail(err, inner.status, "%s: %s", path, inner.message);
  out->orders = orders;
  return SF_OK;
}

/* The EXR part must be the picture the description promises. */
static int check_structure(exr_context_t ctx, const char *path, const sf_table *t, sf_error *err) {
  int parts = 0;
  exr_storage_t storage;
  if (exr_get_count(ctx, &parts) != EXR_ERR_SUCCESS || parts != 1 ||
      exr_get_storage(ctx, 0, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE)
    return sf_fail(err, SF_ERR_INPUT, "%s: expected one scanline image part", path);
  exr_attr_box2i_t dw;
  if (exr_get_data_window(ctx, 0, &dw) != EXR_ERR_SUCCESS || dw.min.x != 0 || dw.min.y != 0 ||
      dw.max.x != t->width - 1 || dw.max.y != t->height - 1)
    return sf_fail(err, SF_ERR_INPUT, "%s: data window (%d,%d)-(%d,%d) does not match the %d x %d picture of the axes",
                   path, dw.min.x, dw.min.y, dw.max.x, dw.max.y, t->width, t->height);
  const exr_attr_chlist_t *list = NULL;
  if (exr_get_channels(ctx, 0, &list) != EXR_ERR_SUCCESS || !list)
    return sf_fail(err, SF_ERR_INPUT, "%s: channel list is unreadable", path);
  if (list->num_channels != t->desc.n_channels)
    return sf_fail(err, SF_ERR_INPUT, "%s: holds %d channels, header attribute skyfit:channels lists %d", path,
                   list->num_channels, t->desc.n_channels);
  int seen[SF_MAX_CHANNELS] = {0};
  for (int k = 0; k < list->num_channels; ++k) {
    const exr_attr_chlist_entry_t *e = &list->entries[k];
    int c = e->name.str ? channel_index(&t->desc, e->name.str) : -1;
    if (c < 0 || seen[c])
      return sf_fail(err, SF_ERR_INPUT, "%s: EXR channel '%s' is not one of skyfit:channels (or repeats)", path,
                     e->name.str ? e->name.str : "");
    seen[c] = 1;
    if (e->pixel_type != EXR_PIXEL_FLOAT || e->x_sampling != 1 || e->y_sampling != 1)
      return sf_fail(err, SF_ERR_INPUT, "%s: EXR channel '%s' is not full-resolution float32", path, e->name.str);
  }
  return SF_OK;
}

static int read_pixels(exr_context_t ctx, const char *path, sf_table *t, const exr_stream *stream,
                       sf_error *err) {
  const sf_table_desc *d = &t->desc;
  int32_t chunks = 0, lines = 0;
  exr_result_t rv = exr_get_chunk_count(ctx, 0, &chunks);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  if (rv != EXR_ERR_SUCCESS || lines < 1 || (int64_t)chunks * lines < t->height)
    return sf_fail(err, SF_ERR_INPUT, "%s: chunk layout is unreadable: %s", path, exr_reason(stream, rv));
  size_t row_floats = (size_t)t->width * d->n_channels;
  float *rows = malloc(sizeof(float) * row_floats * (size_t)lines);
  if (!rows) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", path);
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int status = SF_OK, initialised = 0;
  for (int32_t ci = 0; ci < chunks && status == SF_OK; ++ci) {
    int y0 = ci * lines;
    exr_chunk_info_t cinfo;
    rv = exr_read_scanline_chunk_info(ctx, 0, y0, &cinfo);
    if (rv == EXR_ERR_SUCCESS) {
      rv = initialised ? exr_decoding_update(ctx, 0, &cinfo, &dec)
                       : exr_decoding_initialize(ctx, 0, &cinfo, &dec);
      initialised = initialised || rv == EXR_ERR_SUCCESS;
    }
    if (rv == EXR_ERR_SUCCESS &&
        (cinfo.start_y != y0 || cinfo.height < 1 || cinfo.height > lines || y0 + cinfo.height > t->height ||
         cinfo.width != t->width))
      rv = EXR_ERR_CORRUPT_CHUNK;
    for (int k = 0; rv == EXR_ERR_SUCCESS && k < dec.channel_count; ++k) {
      exr_coding_channel_info_t *ch = &dec.channels[k];
      int c = channel_index(d, ch->channel_name);
      if (c < 0) { rv = EXR_ERR_CORRUPT_CHUNK; break; }
      ch->decode_to_ptr = (uint8_t *)(rows + c);
      ch->user_pixel_stride = (int32_t)(sizeof(float) * d->n_channels);
      ch->user_line_stride = (int32_t)(sizeof(float) * row_floats);
      ch->user_bytes_per_element = (int16_t)sizeof(float);
      ch->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctx, 0, &dec);
    if (rv != EXR_ERR_SUCCESS) {
      status = sf_fail(err, SF_ERR_INPUT, "%s: pixel data chunk %d (rows %d-%d) is damaged or truncated: %s",
                       path, (int)ci, y0, y0 + lines - 1, exr_reason(stream, rv));
      break;
    }
    for (int ly = 0; ly < cinfo.height; ++ly) scatter_row(t, y0 + ly, rows + (size_t)ly * row_floats);
  }
  if (initialised) exr_decoding_destroy(ctx, &dec);
  free(rows);
  return status;
}

int sf_table_read_exr(const char *path, size_t max_bytes, sf_table *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  exr_stream stream = {.fd = open(path, O_RDONLY)};
  if (stream.fd < 0) return sf_fail(err, SF_ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  if (fstat(stream.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(stream.fd);
    return sf_fail(err, SF_ERR_INPUT, "%s: not a regular file", path);
  }
  if (st.st_size == 0) {
    close(stream.fd);
    return sf_fail(err, SF_ERR_INPUT, "%s: file is empty (0 bytes), not an EXR table", path);
  }
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = keep_first_error;
  init.user_data = &stream;
  init.read_fn = stream_read;
  init.size_fn = stream_size;
  /* A damaged file must fail, not be patched up by guessing chunk offsets. */
  init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER | EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, path, &init);
  char *strings[ATTR_COUNT] = {0};
  char stored_sum[17] = "";
  int status = SF_OK;
  if (rv != EXR_ERR_SUCCESS)
    status = sf_fail(err, SF_ERR_INPUT, "%s: not a readable EXR file (%lld bytes): %s", path,
                     (long long)st.st_size, exr_reason(&stream, rv));
  if (status == SF_OK) status = read_description(ctx, path, max_bytes, out, strings, stored_sum, err);
  if (status == SF_OK) status = check_structure(ctx, path, out, err);
  if (status == SF_OK) status = read_pixels(ctx, path, out, &stream, err);
  if (status == SF_OK) {
    size_t n = sf_table_desc_points(&out->desc) * (size_t)out->desc.n_channels, bad;
    if (first_non_finite(out->data, n, &bad)) {
      int index[SF_TABLE_MAX_AXES] = {0, 0, 0, 0};
      size_t point = bad / (size_t)out->desc.n_channels;
      for (int k = 0; k < out->desc.n_axes; ++k) {
        index[k] = (int)(point % (size_t)out->desc.axes[k].size);
        point /= (size_t)out->desc.axes[k].size;
      }
      status = sf_fail(err, SF_ERR_INPUT, "%s: value %g at index (%d, %d, %d, %d) channel %s is not finite",
                       path, out->data[bad], index[0], index[1], index[2], index[3],
                       out->desc.channel_names[bad % (size_t)out->desc.n_channels]);
    }
  }
  if (status == SF_OK) {
    char actual[17], orders_buf[64];
    sf_hash64_hex(checksum((const char *const *)strings, orders_text(&out->orders, orders_buf, sizeof orders_buf),
                           out->data,
                           sf_table_desc_points(&out->desc) * (size_t)out->desc.n_channels),
                  actual);
    if (strcmp(actual, stored_sum) != 0)
      status = sf_fail(err, SF_ERR_INPUT, "%s: checksum mismatch (stored %s, contents give %s): the file is damaged",
                       path, stored_sum, actual);
  }
  for (int i = 0; i < ATTR_COUNT; ++i) free(strings[i]);
  if (ctx) exr_finish(&ctx);
  close(stream.fd);
  if (status != SF_OK) sf_table_free(out);
  return status;
}
