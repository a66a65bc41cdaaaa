#include "util/exr_image.h"

#include <OpenEXR/openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/atomic_file.h"
#include "util/exr_fd_write.h"

#define EXR_IMAGE_ZIP_LEVEL 6

static int encode_rows(exr_context_t ctx, int width, int n_channels, const char *const *names,
                       const float *pixels) {
  int32_t chunks = 0, lines = 0;
  if (exr_get_chunk_count(ctx, 0, &chunks) != EXR_ERR_SUCCESS ||
      exr_get_scanlines_per_chunk(ctx, 0, &lines) != EXR_ERR_SUCCESS)
    return -1;
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int initialised = 0, status = 0;
  size_t row_floats = (size_t)width * (size_t)n_channels;
  for (int32_t ci = 0; ci < chunks && status == 0; ++ci) {
    exr_chunk_info_t cinfo;
    exr_result_t rv = exr_write_scanline_chunk_info(ctx, 0, ci * lines, &cinfo);
    if (rv == EXR_ERR_SUCCESS) {
      rv = initialised ? exr_encoding_update(ctx, 0, &cinfo, &enc) : exr_encoding_initialize(ctx, 0, &cinfo, &enc);
      initialised = initialised || rv == EXR_ERR_SUCCESS;
    }
    if (rv != EXR_ERR_SUCCESS) { status = -1; break; }
    const float *rows = pixels + (size_t)cinfo.start_y * row_floats;
    for (int k = 0; k < enc.channel_count; ++k) {
      exr_coding_channel_info_t *ch = &enc.channels[k];
      int c = 0;
      while (c < n_channels && strcmp(names[c], ch->channel_name) != 0) ++c;
      if (c == n_channels) { status = -1; break; }
      ch->encode_from_ptr = (const uint8_t *)(rows + c);
      ch->user_pixel_stride = (int32_t)(sizeof(float) * (size_t)n_channels);
      ch->user_line_stride = (int32_t)(sizeof(float) * row_floats);
      ch->user_bytes_per_element = (int16_t)sizeof(float);
      ch->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (status) break;
    rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, 0, &enc);
    if (rv != EXR_ERR_SUCCESS) status = -1;
  }
  if (initialised) exr_encoding_destroy(ctx, &enc);
  return status;
}

static void quiet_errors(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt; (void)code; (void)msg;
}

typedef struct image_stream {
  int fd;
  int write_errno;   /* the first failed write's errno, 0 if none */
} image_stream;

/* OpenEXR writes through the atomic file's descriptor, so the image gets
 * the same temporary-then-rename, fsync and permissions as every output. */
static int64_t write_to_fd(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz, uint64_t offset,
                           exr_stream_error_func_ptr_t error_cb) {
  image_stream *s = (image_stream *)user;
  return sf_exr_write_fd(ctxt, s->fd, buffer, sz, offset, error_cb, &s->write_errno);
}

int sf_exr_write_image(const char *path, int width, int height, int n_channels,
                       const char *const *channel_names, const float *pixels, sf_error *err) {
  if (width < 1 || height < 1 || n_channels < 1) return sf_fail(err, SF_ERR_INTERNAL, "%s: empty image", path);
  sf_atomic_file file;
  if (sf_atomic_open(&file, path, err) != SF_OK) return err->status;
  image_stream stream = {.fd = fileno(file.stream)};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet_errors;
  init.user_data = &stream;
  init.write_fn = write_to_fd;
  init.zip_level = EXR_IMAGE_ZIP_LEVEL;
  exr_context_t ctx = NULL;
  int part = 0;
  exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, "image", EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS) rv = exr_initialize_required_attr_simple(ctx, part, width, height, EXR_COMPRESSION_ZIP);
  if (rv == EXR_ERR_SUCCESS) rv = exr_set_zip_compression_level(ctx, part, EXR_IMAGE_ZIP_LEVEL);
  for (int c = 0; rv == EXR_ERR_SUCCESS && c < n_channels; ++c)
    rv = exr_add_channel(ctx, part, channel_names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
  int status = rv == EXR_ERR_SUCCESS ? encode_rows(ctx, width, n_channels, channel_names, pixels) : -1;
  exr_result_t fin = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
  if (status != 0 || fin != EXR_ERR_SUCCESS) {
    sf_atomic_abort(&file);
    /* a failed write (a full disk) or OpenEXR refusing our image: both
     * exit 1, SPEC §11 */
    int why = stream.write_errno ? sf_write_error_status(stream.write_errno) : SF_ERR_INTERNAL;
    return sf_fail(err, why, "%s: writing the EXR image failed (%s%s%s)", path,
                   exr_get_default_error_message(rv != EXR_ERR_SUCCESS ? rv : fin),
                   stream.write_errno ? ": " : "", stream.write_errno ? strerror(stream.write_errno) : "");
  }
  return sf_atomic_commit(&file, err);
}
