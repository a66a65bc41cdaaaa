/* 8-bit RGB PNG files (libpng), written atomically (util/atomic_file.h):
 * the report's previews of the standard views (SPEC §12). */
#ifndef SKYFIT_UTIL_PNG_WRITE_H
#define SKYFIT_UTIL_PNG_WRITE_H

#include "util/error.h"

/* rgb holds width * height * 3 bytes, rows top to bottom. */
int sf_png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb, sf_error *err);

#endif
