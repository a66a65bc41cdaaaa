/* Float32 images as OpenEXR files (C API), written atomically: the
 * report's per-pixel error maps (SPEC §12). ZIP compression at a fixed
 * level, so the same pixels give the same bytes. */
#ifndef SKYFIT_UTIL_EXR_IMAGE_H
#define SKYFIT_UTIL_EXR_IMAGE_H

#include "util/error.h"

/* pixels: width * height * n_channels floats, interleaved, rows top to
 * bottom; channel_names[n_channels] (e.g. "R", "G", "B"). */
int sf_exr_write_image(const char *path, int width, int height, int n_channels,
                       const char *const *channel_names, const float *pixels, sf_error *err);

#endif
