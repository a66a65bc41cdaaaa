#include "util/png_write.h"

#include <png.h>
#include <setjmp.h>

#include "util/atomic_file.h"

/* libpng reports failures by longjmp; the rows and the stream are set up
 * before setjmp, so nothing needs to survive it but the return path. */
static int write_stream(FILE *stream, int width, int height, const unsigned char *rgb) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
  if (!png) return -1;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, NULL);
    return -1;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return -1;
  }
  png_init_io(png, stream);
  /* No time stamp or text: the same pixels give the same bytes. */
  png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, (png_const_bytep)(rgb + (size_t)y * (size_t)width * 3));
  png_write_end(png, NULL);
  png_destroy_write_struct(&png, &info);
  return 0;
}

int sf_png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb, sf_error *err) {
  if (width < 1 || height < 1) return sf_fail(err, SF_ERR_INTERNAL, "%s: empty image", path);
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  if (write_stream(f.stream, width, height, rgb) != 0) {
    sf_atomic_abort(&f);
    return sf_fail(err, SF_ERR_INTERNAL, "%s: libpng failed to write the image", path);
  }
  return sf_atomic_commit(&f, err);
}
