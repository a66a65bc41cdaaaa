/* Table files (SPEC §6): tables written as EXR come back bit-identical with
 * all their metadata, in the documented tiled picture, byte-identical on
 * every write; damaged or foreign files are refused with SF_ERR_INPUT and
 * never crash or return garbage; failed writes leave nothing behind.
 * Expected values come from an analytic function of the indices and the
 * tiling formula written out here, and the picture is inspected with the
 * OpenEXR C API directly, independently of data/table_exr.c. */
#include <errno.h>
#include <math.h>
#include <float.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <dirent.h>

#include <OpenEXR/openexr.h>

#include "data/table.h"
#include "data/table_exr.h"
#include "tests/check.h"

static char work_dir[256];

/* ---- the analytic table ---- */

static float analytic(const int i[4], int c) {
  /* A few special floats first, to prove bits (not just values) survive. */
  if (i[0] == 0 && i[1] == 0 && i[2] == 0 && i[3] == 0) {
    const float special[3] = {-0.0f, 1e-42f /* denormal */, FLT_MAX};
    return special[c % 3];
  }
  if (i[0] == 1 && i[1] == 0 && i[2] == 0 && i[3] == 0) {
    const float special[3] = {-FLT_MAX, FLT_MIN, -FLT_MIN / 64.0f};
    return special[c % 3];
  }
  double v = sin(0.731 * i[0] + 0.137 * i[1] + 1.9 * c) * exp(-0.05 * i[1]) + 1e-3 * i[2] - 0.25 * i[3] +
             0.1 * c;
  return (float)v;
}

static int n_of(const sf_table_desc *d, int k) { return k < d->n_axes ? d->axes[k].size : 1; }

/* Memory order of data/table.h, written out independently. */
static size_t linear_of(const sf_table_desc *d, const int i[4]) {
  return (size_t)i[0] + (size_t)n_of(d, 0) * (i[1] + (size_t)n_of(d, 1) * (i[2] + (size_t)n_of(d, 2) * i[3]));
}

static void fill(sf_table *t) {
  const sf_table_desc *d = &t->desc;
  int i[4];
  for (i[3] = 0; i[3] < n_of(d, 3); ++i[3])
    for (i[2] = 0; i[2] < n_of(d, 2); ++i[2])
      for (i[1] = 0; i[1] < n_of(d, 1); ++i[1])
        for (i[0] = 0; i[0] < n_of(d, 0); ++i[0])
          for (int c = 0; c < d->n_channels; ++c)
            t->data[c + d->n_channels * linear_of(d, i)] = analytic(i, c);
}

/* Number of values whose bits differ from the analytic function. */
static long count_wrong_bits(const sf_table *t) {
  const sf_table_desc *d = &t->desc;
  long wrong = 0;
  int i[4];
  for (i[3] = 0; i[3] < n_of(d, 3); ++i[3])
    for (i[2] = 0; i[2] < n_of(d, 2); ++i[2])
      for (i[1] = 0; i[1] < n_of(d, 1); ++i[1])
        for (i[0] = 0; i[0] < n_of(d, 0); ++i[0])
          for (int c = 0; c < d->n_channels; ++c) {
            float want = analytic(i, c), got = t->data[c + d->n_channels * linear_of(d, i)];
            if (memcmp(&want, &got, sizeof want) != 0) ++wrong;
          }
  return wrong;
}

static sf_table_desc make_desc(int n_axes, const int *sizes, int n_channels, const char *const *names) {
  static const char *const axis_names[4] = {"h_km", "mu", "mu_s", "nu"};
  static const char *const mappings[4] = {"leenman_x", "linear", "bruneton_mu_s", "linear"};
  const double mins[4] = {0.0, -1.0, -0.2, 1.0 / 3.0};
  const double maxs[4] = {60.0, 1.0, 0.1, 6360.123456789012};
  sf_table_desc d;
  memset(&d, 0, sizeof d);
  strcpy(d.quantity, n_axes == 2 ? "transmittance" : "single_rayleigh");
  strcpy(d.parameterization, "leenman");
  d.n_axes = n_axes;
  for (int k = 0; k < n_axes; ++k) {
    strcpy(d.axes[k].name, axis_names[k]);
    strcpy(d.axes[k].mapping, mappings[k]);
    d.axes[k].size = sizes[k];
    d.axes[k].min = mins[k];
    d.axes[k].max = maxs[k];
  }
  d.n_channels = n_channels;
  for (int c = 0; c < n_channels; ++c) strcpy(d.channel_names[c], names[c]);
  strcpy(d.content_hash, "0123456789abcdef");
  return d;
}

static const char *const rgb[3] = {"r", "g", "b"};
static const char *const atmosphere_text =
    "{\"name\":\"earth\",\"bottom_radius_km\":6360,\"top_radius_km\":6420,\"channels\":\"rgb\"}";

/* ---- file helpers ---- */

static void path_in(char *out, size_t n, const char *name) { snprintf(out, n, "%s/%s", work_dir, name); }

static unsigned char *slurp(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *bytes = malloc(n > 0 ? (size_t)n : 1);
  *size = fread(bytes, 1, (size_t)n, f);
  fclose(f);
  return bytes;
}

static void spit(const char *path, const unsigned char *bytes, size_t n) {
  FILE *f = fopen(path, "wb");
  if (n) fwrite(bytes, 1, n, f);
  fclose(f);
}

static int count_temporaries(void) {
  DIR *dir = opendir(work_dir);
  int n = 0;
  for (struct dirent *e; dir && (e = readdir(dir));)
    if (strstr(e->d_name, ".tmp.")) ++n;
  if (dir) closedir(dir);
  return n;
}

/* Empties and removes the work folder (flat, plus empty sub-folders). */
static void remove_work_dir(void) {
  DIR *dir = opendir(work_dir);
  for (struct dirent *e; dir && (e = readdir(dir));) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char path[600];
    snprintf(path, sizeof path, "%s/%s", work_dir, e->d_name);
    remove(path);
  }
  if (dir) closedir(dir);
  rmdir(work_dir);
}

/* ---- raw OpenEXR access, independent of data/table_exr.c ---- */

static void quiet(exr_const_context_t c, exr_result_t code, const char *msg) { (void)c; (void)code; (void)msg; }

/* Planar float picture of one channel (caller frees), or NULL. */
static float *raw_channel(const char *path, const char *channel, int *width, int *height) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  exr_context_t ctx = NULL;
  if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS) return NULL;
  exr_attr_box2i_t dw;
  exr_get_data_window(ctx, 0, &dw);
  *width = dw.max.x - dw.min.x + 1;
  *height = dw.max.y - dw.min.y + 1;
  float *plane = calloc((size_t)*width * *height, sizeof(float));
  int32_t chunks = 0, lines = 0;
  exr_get_chunk_count(ctx, 0, &chunks);
  exr_get_scanlines_per_chunk(ctx, 0, &lines);
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int ok = 1;
  for (int ci = 0; ci < chunks && ok; ++ci) {
    exr_chunk_info_t cinfo;
    ok = exr_read_scanline_chunk_info(ctx, 0, dw.min.y + ci * lines, &cinfo) == EXR_ERR_SUCCESS;
    ok = ok && (ci == 0 ? exr_decoding_initialize(ctx, 0, &cinfo, &dec)
                        : exr_decoding_update(ctx, 0, &cinfo, &dec)) == EXR_ERR_SUCCESS;
    for (int k = 0; ok && k < dec.channel_count; ++k) {
      exr_coding_channel_info_t *ch = &dec.channels[k];
      ch->decode_to_ptr = strcmp(ch->channel_name, channel) == 0
                              ? (uint8_t *)(plane + (size_t)(cinfo.start_y - dw.min.y) * *width)
                              : NULL;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * *width;
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
    }
    ok = ok && exr_decoding_choose_default_routines(ctx, 0, &dec) == EXR_ERR_SUCCESS;
    ok = ok && exr_decoding_run(ctx, 0, &dec) == EXR_ERR_SUCCESS;
  }
  exr_decoding_destroy(ctx, &dec);
  exr_finish(&ctx);
  if (!ok) { free(plane); return NULL; }
  return plane;
}

#define N_SKYFIT_ATTRS 9
static const char *const skyfit_attrs[N_SKYFIT_ATTRS] = {
    "skyfit:format", "skyfit:quantity", "skyfit:parameterization", "skyfit:axes", "skyfit:channels",
    "skyfit:tiling", "skyfit:atmosphere", "skyfit:content_hash", "skyfit:checksum"};

/* Copies of the skyfit string attributes of a file (NULL where absent). */
static void raw_attrs(const char *path, char *values[N_SKYFIT_ATTRS]) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  exr_context_t ctx = NULL;
  int ok = exr_start_read(&ctx, path, &init) == EXR_ERR_SUCCESS;
  for (int i = 0; i < N_SKYFIT_ATTRS; ++i) {
    const char *s = NULL;
    int32_t n = 0;
    values[i] = ok && exr_attr_get_string(ctx, 0, skyfit_attrs[i], &n, &s) == EXR_ERR_SUCCESS ? strndup(s, n) : NULL;
  }
  if (ok) exr_finish(&ctx);
}

/* Writes an EXR with the given channels (in any order), attributes (NULL
 * values are left out) and an interleaved float picture; HALF channels are
 * written as zeros. */
static int raw_write(const char *path, int width, int height, int n_ch, const char *const *names,
                     const exr_pixel_type_t *types, exr_compression_t compression, const float *pixels,
                     char *const values[N_SKYFIT_ATTRS]) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  exr_context_t ctx = NULL;
  int part = 0;
  exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, "table", EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS) rv = exr_initialize_required_attr_simple(ctx, part, width, height, compression);
  for (int c = 0; rv == EXR_ERR_SUCCESS && c < n_ch; ++c)
    rv = exr_add_channel(ctx, part, names[c], types[c], EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (int i = 0; rv == EXR_ERR_SUCCESS && i < N_SKYFIT_ATTRS; ++i)
    if (values[i]) rv = exr_attr_set_string(ctx, part, skyfit_attrs[i], values[i]);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
  int32_t chunks = 0, lines = 0;
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_chunk_count(ctx, part, &chunks);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
  uint16_t *zeros = calloc((size_t)width * (lines > 0 ? lines : 1), sizeof(uint16_t));
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  for (int ci = 0; rv == EXR_ERR_SUCCESS && ci < chunks; ++ci) {
    exr_chunk_info_t cinfo;
    rv = exr_write_scanline_chunk_info(ctx, part, ci * lines, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = ci == 0 ? exr_encoding_initialize(ctx, part, &cinfo, &enc) : exr_encoding_update(ctx, part, &cinfo, &enc);
    for (int k = 0; rv == EXR_ERR_SUCCESS && k < enc.channel_count; ++k) {
      exr_coding_channel_info_t *ch = &enc.channels[k];
      int c = 0;
      while (strcmp(names[c], ch->channel_name) != 0) ++c;
      if (types[c] == EXR_PIXEL_HALF) {
        ch->encode_from_ptr = (const uint8_t *)zeros;
        ch->user_pixel_stride = 2;
        ch->user_line_stride = 2 * width;
        ch->user_bytes_per_element = 2;
        ch->user_data_type = EXR_PIXEL_HALF;
      } else {
        ch->encode_from_ptr = (const uint8_t *)(pixels + ((size_t)ci * lines * width) * n_ch + c);
        ch->user_pixel_stride = 4 * n_ch;
        ch->user_line_stride = 4 * n_ch * width;
        ch->user_bytes_per_element = 4;
        ch->user_data_type = EXR_PIXEL_FLOAT;
      }
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_choose_default_routines(ctx, part, &enc);
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, &enc);
  }
  if (chunks > 0) exr_encoding_destroy(ctx, &enc);
  free(zeros);
  exr_result_t fin = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
  return rv == EXR_ERR_SUCCESS && fin == EXR_ERR_SUCCESS ? 0 : -1;
}

/* Interleaved picture (channels in the table's order) of the analytic
 * table, laid out by the tiling formula x = i0 + n0*i2, y = i1 + n1*i3. */
static float *analytic_picture(const sf_table_desc *d, int *width, int *height) {
  *width = n_of(d, 0) * n_of(d, 2);
  *height = n_of(d, 1) * n_of(d, 3);
  float *p = malloc(sizeof(float) * (size_t)*width * *height * d->n_channels);
  int i[4];
  for (i[3] = 0; i[3] < n_of(d, 3); ++i[3])
    for (i[2] = 0; i[2] < n_of(d, 2); ++i[2])
      for (i[1] = 0; i[1] < n_of(d, 1); ++i[1])
        for (i[0] = 0; i[0] < n_of(d, 0); ++i[0]) {
          int x = i[0] + n_of(d, 0) * i[2], y = i[1] + n_of(d, 1) * i[3];
          for (int c = 0; c < d->n_channels; ++c)
            p[((size_t)y * *width + x) * d->n_channels + c] = analytic(i, c);
        }
  return p;
}

/* ---- the tests ---- */

static int metadata_matches(const sf_table *got, const sf_table_desc *want, const char *json) {
  const sf_table_desc *g = &got->desc;
  int ok = strcmp(g->quantity, want->quantity) == 0 && strcmp(g->parameterization, want->parameterization) == 0 &&
           strcmp(g->content_hash, want->content_hash) == 0 && g->n_axes == want->n_axes &&
           g->n_channels == want->n_channels && strcmp(got->atmosphere_json, json) == 0;
  for (int k = 0; ok && k < want->n_axes; ++k)
    ok = strcmp(g->axes[k].name, want->axes[k].name) == 0 && strcmp(g->axes[k].mapping, want->axes[k].mapping) == 0 &&
         g->axes[k].size == want->axes[k].size && memcmp(&g->axes[k].min, &want->axes[k].min, 8) == 0 &&
         memcmp(&g->axes[k].max, &want->axes[k].max, 8) == 0;
  for (int c = 0; ok && c < want->n_channels; ++c) ok = strcmp(g->channel_names[c], want->channel_names[c]) == 0;
  return ok;
}

static void round_trip(const char *label, int n_axes, const int *sizes, const char *json) {
  printf("-- round trip: %s\n", label);
  sf_table_desc desc = make_desc(n_axes, sizes, 3, rgb);
  sf_table t;
  sf_error err = {0};
  CHECK(sf_table_init(&t, &desc, json, 0, &err) == SF_OK);
  fill(&t);
  char a[512], b[512], c[512];
  path_in(a, sizeof a, "a.exr");
  path_in(b, sizeof b, "b.exr");
  path_in(c, sizeof c, "c.exr");
  CHECK(sf_table_write_exr(&t, a, &err) == SF_OK);
  CHECK(sf_table_write_exr(&t, b, &err) == SF_OK);
  if (err.status) printf("write error: %s\n", err.message);

  sf_table back;
  CHECK(sf_table_read_exr(a, 0, &back, &err) == SF_OK);
  if (err.status) printf("read error: %s\n", err.message);
  long wrong = back.data ? count_wrong_bits(&back) : -1;
  printf("values %zu, with different bits after the round trip: %ld\n",
         sf_table_desc_points(&desc) * 3, wrong);
  CHECK(wrong == 0);
  CHECK(back.data && metadata_matches(&back, &desc, json));
  CHECK(back.width == n_of(&desc, 0) * n_of(&desc, 2) && back.height == n_of(&desc, 1) * n_of(&desc, 3));

  /* Same table, same bytes: twice from memory, and again after reading. */
  if (back.data) CHECK(sf_table_write_exr(&back, c, &err) == SF_OK);
  size_t na = 0, nb = 0, nc = 0;
  unsigned char *ba = slurp(a, &na), *bb = slurp(b, &nb), *bc = slurp(c, &nc);
  printf("file sizes %zu, %zu, %zu bytes (raw floats %zu)\n", na, nb, nc, sf_table_desc_points(&desc) * 12);
  CHECK(na > 0 && na == nb && memcmp(ba, bb, na) == 0);
  CHECK(na == nc && memcmp(ba, bc, na) == 0);
  free(ba); free(bb); free(bc);

  /* The picture is the documented tiling, seen through OpenEXR directly:
   * every pixel of every channel equals the analytic value at the index
   * that x = i0 + n0*i2, y = i1 + n1*i3 assigns to it. */
  int w = 0, h = 0, pw = 0, ph = 0;
  float *want = analytic_picture(&desc, &pw, &ph);
  long mismatched = 0;
  for (int ch = 0; ch < 3; ++ch) {
    float *plane = raw_channel(a, rgb[ch], &w, &h);
    CHECK(plane && w == pw && h == ph);
    for (long p = 0; plane && w == pw && h == ph && p < (long)w * h; ++p)
      if (memcmp(&plane[p], &want[p * 3 + ch], 4) != 0) ++mismatched;
    free(plane);
  }
  printf("picture %d x %d, pixels differing from the tiling formula: %ld\n", w, h, mismatched);
  CHECK(mismatched == 0);
  free(want);

  /* sf_table_pixel_of / sf_table_index_of agree with the formula. */
  int bad = 0, i[4];
  for (i[3] = 0; i[3] < n_of(&desc, 3); ++i[3])
    for (i[2] = 0; i[2] < n_of(&desc, 2); ++i[2])
      for (i[1] = 0; i[1] < n_of(&desc, 1); ++i[1])
        for (i[0] = 0; i[0] < n_of(&desc, 0); ++i[0]) {
          int x, y, j[4] = {0, 0, 0, 0};
          sf_table_pixel_of(&desc, i, &x, &y);
          sf_table_index_of(&desc, x, y, j);
          if (x != i[0] + n_of(&desc, 0) * i[2] || y != i[1] + n_of(&desc, 1) * i[3] ||
              memcmp(i, j, sizeof(int) * n_axes) != 0 || sf_table_at(&t, i) != t.data + 3 * linear_of(&desc, i))
            ++bad;
        }
  CHECK(bad == 0);
  sf_table_free(&back);
  sf_table_free(&t);
}

/* Table with 7 x 5 samples, 2 channels: small enough to damage every byte. */
static sf_table small_table(void) {
  static const char *const names[2] = {"550", "440"};
  int sizes[2] = {7, 5};
  sf_table_desc desc = make_desc(2, sizes, 2, names);
  sf_table t;
  sf_error err = {0};
  sf_table_init(&t, &desc, atmosphere_text, 0, &err);
  fill(&t);
  return t;
}

static int same_table(const sf_table *a, const sf_table *b) {
  size_t n = sf_table_desc_points(&a->desc) * a->desc.n_channels;
  return sf_table_desc_equal(&a->desc, &b->desc) && strcmp(a->atmosphere_json, b->atmosphere_json) == 0 &&
         memcmp(a->data, b->data, n * sizeof(float)) == 0;
}

static void damaged_files(void) {
  printf("-- damaged files\n");
  sf_table t = small_table();
  char good[512], bad[512];
  path_in(good, sizeof good, "good.exr");
  path_in(bad, sizeof bad, "bad.exr");
  sf_error err = {0};
  CHECK(sf_table_write_exr(&t, good, &err) == SF_OK);
  size_t n = 0;
  unsigned char *bytes = slurp(good, &n);
  printf("small file: %zu bytes\n", n);

  /* Zero-length, random bytes, random bytes behind the EXR magic number. */
  sf_table back;
  spit(bad, bytes, 0);
  err = (sf_error){0};
  CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, bad) &&
        strstr(err.message, "empty"));
  printf("zero length: %s\n", err.message);
  unsigned char *noise = malloc(4096);
  uint32_t state = 12345;
  for (int i = 0; i < 4096; ++i) noise[i] = (unsigned char)((state = state * 1664525u + 1013904223u) >> 24);
  spit(bad, noise, 4096);
  err = (sf_error){0};
  CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, bad));
  printf("random bytes: %s\n", err.message);
  memcpy(noise, bytes, 8);   /* magic 76 2f 31 01 and version */
  spit(bad, noise, 4096);
  err = (sf_error){0};
  CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, bad));
  printf("magic + random bytes: %s\n", err.message);
  free(noise);
  path_in(bad, sizeof bad, "missing.exr");
  err = (sf_error){0};
  CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, "cannot open"));
  CHECK(sf_table_read_exr(work_dir, 0, &back, &err) == SF_ERR_INPUT);
  path_in(bad, sizeof bad, "bad.exr");

  /* Truncation at every length: always refused. */
  int truncated_refused = 0, truncated_input = 0;
  for (size_t len = 0; len < n; ++len) {
    spit(bad, bytes, len);
    err = (sf_error){0};
    int rc = sf_table_read_exr(bad, 0, &back, &err);
    truncated_refused += rc != SF_OK;
    truncated_input += rc == SF_ERR_INPUT && strncmp(err.message, bad, strlen(bad)) == 0;
    if (rc == SF_OK) sf_table_free(&back);
    if (len == n / 2 || len == n - 1) printf("truncated to %zu: %s\n", len, err.message);
  }
  printf("truncations refused: %d of %zu (with SF_ERR_INPUT naming the file: %d)\n", truncated_refused, n,
         truncated_input);
  CHECK(truncated_refused == (int)n && truncated_input == (int)n);

  /* Every byte flipped (xor 0x01 and xor 0xff), one at a time. Whatever is
   * accepted must be exactly the original table; the rest is refused with
   * SF_ERR_INPUT. Accepted flips hit bytes that do not affect the table
   * (e.g. pixelAspectRatio, screenWindowCenter, the part name). */
  const unsigned char masks[2] = {0x01, 0xff};
  for (int m = 0; m < 2; ++m) {
    int refused = 0, accepted_same = 0, accepted_different = 0, other_status = 0;
    for (size_t pos = 0; pos < n; ++pos) {
      bytes[pos] ^= masks[m];
      spit(bad, bytes, n);
      bytes[pos] ^= masks[m];
      err = (sf_error){0};
      int rc = sf_table_read_exr(bad, 0, &back, &err);
      if (rc == SF_OK) {
        if (same_table(&back, &t)) ++accepted_same;
        else ++accepted_different;
        sf_table_free(&back);
      } else if (rc == SF_ERR_INPUT) {
        ++refused;
      } else {
        ++other_status;
        printf("unexpected status %d at byte %zu: %s\n", rc, pos, err.message);
      }
    }
    printf("byte flips xor 0x%02x: %zu positions, refused %d, accepted identical %d, accepted different %d\n",
           masks[m], n, refused, accepted_same, accepted_different);
    CHECK(accepted_different == 0);
    CHECK(other_status == 0);
    CHECK(refused > (int)(n * 8 / 10));   /* nearly every byte matters */
  }

  /* The last pixel chunk's compressed data: caught by zlib's Adler-32 or
   * the checksum; say which. */
  bytes[n - 3] ^= 0x10;
  spit(bad, bytes, n);
  bytes[n - 3] ^= 0x10;
  err = (sf_error){0};
  CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT);
  printf("flip near the end of the pixel data: %s\n", err.message);
  free(bytes);
  sf_table_free(&t);
}

/* Files that are valid EXRs but not valid tables, made with OpenEXR
 * directly from the good file's attributes. */
static void foreign_files(void) {
  printf("-- valid EXRs that are not valid tables\n");
  sf_table t = small_table();
  const sf_table_desc *d = &t.desc;
  char good[512], bad[512];
  path_in(good, sizeof good, "good.exr");
  path_in(bad, sizeof bad, "foreign.exr");
  sf_error err = {0};
  sf_table back;
  CHECK(sf_table_write_exr(&t, good, &err) == SF_OK);
  char *attrs[N_SKYFIT_ATTRS];
  raw_attrs(good, attrs);
  int all_present = 1;
  for (int i = 0; i < N_SKYFIT_ATTRS; ++i) all_present &= attrs[i] != NULL;
  CHECK(all_present);
  if (!all_present) return;
  printf("skyfit:axes = %s\nskyfit:channels = %s\n", attrs[3], attrs[4]);
  int w, h;
  float *pixels = analytic_picture(d, &w, &h);
  const char *names[2] = {d->channel_names[0], d->channel_names[1]};

  struct {
    const char *what, *expect;
  } cases[] = {{"uncompressed, exact pixels", NULL},
               {"uncompressed, one mantissa bit flipped", "checksum mismatch"},
               {"a NaN pixel", "not finite"},
               {"picture one column wider", "data window"},
               {"channel 440 missing", "channels"},
               {"channel 440 stored as half", "float32"},
               {"skyfit:axes not JSON", "skyfit:axes"},
               {"skyfit:checksum missing", "skyfit:checksum is missing"},
               {"skyfit:format of a future version", "skyfit:format"},
               {"plain image without skyfit attributes", "skyfit:format is missing"}};
  for (int k = 0; k < (int)(sizeof cases / sizeof cases[0]); ++k) {
    char *values[N_SKYFIT_ATTRS];
    memcpy(values, attrs, sizeof values);
    float *p = malloc(sizeof(float) * (size_t)(w + 1) * h * 2);
    memcpy(p, pixels, sizeof(float) * (size_t)w * h * 2);
    int width = w, n_ch = 2;
    exr_pixel_type_t types[2] = {EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT};
    exr_compression_t comp = EXR_COMPRESSION_NONE;
    char future[] = "skyfit-table 2", not_json[] = "not json";
    uint32_t bits;
    switch (k) {
      case 1: memcpy(&bits, &p[17], 4); bits ^= 1u; memcpy(&p[17], &bits, 4); break;
      case 2: p[2 * (w * 2 + 3) + 1] = NAN; comp = EXR_COMPRESSION_ZIP; break;
      case 3: width = w + 1; break;
      case 4: n_ch = 1; break;
      case 5: types[1] = EXR_PIXEL_HALF; break;
      case 6: values[3] = not_json; break;
      case 7: values[8] = NULL; break;
      case 8: values[0] = future; break;
      case 9: for (int i = 0; i < N_SKYFIT_ATTRS; ++i) values[i] = NULL; break;
    }
    CHECK(raw_write(bad, width, h, n_ch, names, types, comp, p, values) == 0);
    err = (sf_error){0};
    int rc = sf_table_read_exr(bad, 0, &back, &err);
    printf("%s: %s\n", cases[k].what, rc == SF_OK ? "accepted" : err.message);
    if (cases[k].expect) {
      CHECK(rc == SF_ERR_INPUT && strstr(err.message, cases[k].expect) && strstr(err.message, bad));
      CHECK(back.data == NULL);
    } else {
      CHECK(rc == SF_OK && same_table(&back, &t));
    }
    if (rc == SF_OK) sf_table_free(&back);
    free(p);
  }
  /* A reader's memory limit is honoured before anything is allocated. */
  err = (sf_error){0};
  CHECK(sf_table_read_exr(good, 100, &back, &err) == SF_ERR_INPUT && strstr(err.message, "limit"));
  printf("read with a 100-byte limit: %s\n", err.message);
  for (int i = 0; i < N_SKYFIT_ATTRS; ++i) free(attrs[i]);
  free(pixels);
  sf_table_free(&t);
}

static void bad_descriptions(void) {
  printf("-- descriptions refused by sf_table_init\n");
  int huge[4] = {1 << 20, 1 << 20, 1 << 20, 1 << 20};
  sf_table t;
  sf_error err = {0};
  sf_table_desc d = make_desc(4, huge, 3, rgb);
  CHECK(sf_table_init(&t, &d, NULL, 0, &err) == SF_ERR_INPUT && t.data == NULL);
  printf("2^80 samples: %s\n", err.message);
  int sizes[2] = {256, 64};
  d = make_desc(2, sizes, 3, rgb);
  err = (sf_error){0};
  CHECK(sf_table_init(&t, &d, NULL, 256 * 64 * 3 * 4 - 1, &err) == SF_ERR_INPUT);
  printf("one byte over the limit: %s\n", err.message);
  err = (sf_error){0};
  CHECK(sf_table_init(&t, &d, NULL, 256 * 64 * 3 * 4, &err) == SF_OK && t.data && t.data[0] == 0.0f &&
        strcmp(t.atmosphere_json, "") == 0);
  sf_table_free(&t);
  CHECK(t.data == NULL);
  sf_table_free(&t);   /* twice is harmless */
  static const char *const cases[] = {"size 0", "NaN range", "same channel twice", "slash in quantity",
                                      "5 axes", "uppercase hash", "no mapping"};
  for (int k = 0; k < (int)(sizeof cases / sizeof cases[0]); ++k) {
    d = make_desc(2, sizes, 3, rgb);
    switch (k) {
      case 0: d.axes[1].size = 0; break;
      case 1: d.axes[0].max = NAN; break;
      case 2: strcpy(d.channel_names[2], "r"); break;
      case 3: strcpy(d.quantity, "../etc"); break;
      case 4: d.n_axes = 5; break;
      case 5: strcpy(d.content_hash, "0123456789ABCDEF"); break;
      case 6: d.axes[0].mapping[0] = '\0'; break;
    }
    err = (sf_error){0};
    CHECK(sf_table_init(&t, &d, NULL, 0, &err) == SF_ERR_INPUT && t.data == NULL);
    printf("%s: %s\n", cases[k], err.message);
  }
}

static void failed_writes(void) {
  printf("-- failed writes\n");
  sf_table t = small_table();
  sf_error err = {0};
  char path[1100];
  snprintf(path, sizeof path, "%s/no/such/folder/t.exr", work_dir);
  CHECK(sf_table_write_exr(&t, path, &err) == SF_ERR_INPUT && strstr(err.message, path));
  printf("missing folder: %s\n", err.message);
  char file_as_folder[512];
  path_in(file_as_folder, sizeof file_as_folder, "plain_file");
  spit(file_as_folder, (const unsigned char *)"x", 1);
  snprintf(path, sizeof path, "%s/t.exr", file_as_folder);
  err = (sf_error){0};
  CHECK(sf_table_write_exr(&t, path, &err) == SF_ERR_INPUT);
  printf("folder is a file: %s\n", err.message);
  if (geteuid() != 0) {
    char locked[512];
    path_in(locked, sizeof locked, "locked");
    mkdir(locked, 0555);
    snprintf(path, sizeof path, "%s/t.exr", locked);
    err = (sf_error){0};
    CHECK(sf_table_write_exr(&t, path, &err) == SF_ERR_INPUT && access(path, F_OK) != 0);
    printf("read-only folder: %s\n", err.message);
  } else {
    printf("read-only folder: not testable as root (root writes anywhere)\n");
  }

  /* A NaN in the last row aborts mid-file: the previous file stays intact
   * and no temporary remains. */
  path_in(path, sizeof path, "kept.exr");
  err = (sf_error){0};
  CHECK(sf_table_write_exr(&t, path, &err) == SF_OK);
  size_t n_before = 0, n_after = 0;
  unsigned char *before = slurp(path, &n_before);
  int last[2] = {6, 4};
  sf_table_at(&t, last)[1] = NAN;
  err = (sf_error){0};
  CHECK(sf_table_write_exr(&t, path, &err) == SF_ERR_INTERNAL && strstr(err.message, "(6, 4, 0, 0) channel 440"));
  printf("NaN in the table: %s\n", err.message);
  unsigned char *after = slurp(path, &n_after);
  CHECK(n_before == n_after && memcmp(before, after, n_before) == 0);
  printf("temporary files left in %s: %d\n", work_dir, count_temporaries());
  CHECK(count_temporaries() == 0);
  free(before);
  free(after);
  sf_table_free(&t);
}

/* A multiple-scattering table's orders (skyfit:orders) come back bit for
 * bit, infinity too; a table without them has no such attribute; the
 * checksum covers the text, and a malformed one is named. */
static void orders_record(void) {
  printf("-- skyfit:orders\n");
  sf_table t = small_table();
  char path[512], bad[512];
  path_in(path, sizeof path, "orders.exr");
  path_in(bad, sizeof bad, "orders_bad.exr");
  const sf_table_orders cases[3] = {{6, 0.00123}, {2, INFINITY}, {0, 0.0}};
  for (int k = 0; k < 3; ++k) {
    t.orders = cases[k];
    sf_error err = {0};
    sf_table back;
    CHECK(sf_table_write_exr(&t, path, &err) == SF_OK);
    char *attrs[N_SKYFIT_ATTRS];
    raw_attrs(path, attrs);
    CHECK(attrs[N_SKYFIT_ATTRS - 1] != NULL);   /* a complete file */
    for (int i = 0; i < N_SKYFIT_ATTRS; ++i) free(attrs[i]);
    size_t n = 0;
    unsigned char *bytes = slurp(path, &n);
    const char *needle = k == 0 ? "6 0.00123" : k == 1 ? "2 inf" : "skyfit:orders";
    unsigned char *at = NULL;
    for (size_t i = 0; !at && i + strlen(needle) <= n; ++i)
      if (memcmp(bytes + i, needle, strlen(needle)) == 0) at = bytes + i;
    CHECK(k < 2 ? at != NULL : at == NULL);
    int ok = sf_table_read_exr(path, 0, &back, &err) == SF_OK;
    CHECK(ok && same_table(&back, &t) && back.orders.highest == cases[k].highest &&
          memcmp(&back.orders.left_fraction, &cases[k].left_fraction, sizeof(double)) == 0);
    if (ok) sf_table_free(&back);
    if (k < 2 && at) {
      /* another order, same length: the checksum no longer matches */
      at[0] = k == 0 ? '7' : '3';
      spit(bad, bytes, n);
      err = (sf_error){0};
      CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, "checksum mismatch"));
      printf("orders edited: %s\n", err.message);
      /* not a number: named before the checksum */
      at[0] = 'x';
      spit(bad, bytes, n);
      err = (sf_error){0};
      CHECK(sf_table_read_exr(bad, 0, &back, &err) == SF_ERR_INPUT && strstr(err.message, "skyfit:orders") &&
            strstr(err.message, bad));
      printf("orders malformed: %s\n", err.message);
    }
    free(bytes);
  }
  sf_table_free(&t);
}

int main(void) {
  const char *tmp = getenv("TMPDIR");
  snprintf(work_dir, sizeof work_dir, "%s/skyfit_table_exr_XXXXXX", tmp && *tmp ? tmp : "/tmp");
  if (!mkdtemp(work_dir)) { perror("mkdtemp"); return 1; }

  int sizes2[2] = {256, 64};
  round_trip("2D 256 x 64, 3 channels", 2, sizes2, atmosphere_text);
  int sizes4[4] = {8, 32, 16, 4};
  round_trip("4D 8 x 32 x 16 x 4, 3 channels", 4, sizes4, atmosphere_text);
  /* A spectral atmosphere's JSON is long; the header must carry it whole. */
  size_t big = 300000;
  char *long_json = malloc(big + 1);
  for (size_t i = 0; i < big; ++i) long_json[i] = "{}[]\"abc,:0123456789 \\n"[i % 23];
  long_json[big] = '\0';
  int sizes3[3] = {5, 3, 4};
  round_trip("3D 5 x 3 x 4 with a 300 kB atmosphere text", 3, sizes3, long_json);
  free(long_json);

  damaged_files();
  foreign_files();
  bad_descriptions();
  failed_writes();
  orders_record();

  remove_work_dir();
  return check_summary();
}
