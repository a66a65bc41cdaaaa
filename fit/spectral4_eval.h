/* Colour error of the ways to turn a sky spectrum into linear sRGB, against
 * the full spectrum (SPEC §7.3 metrics): ΔE2000 after exposure and tone
 * mapping (SPEC §12, models/color_space.h sf_display_lab), per sample. */
#ifndef SKYFIT_FIT_SPECTRAL4_EVAL_H
#define SKYFIT_FIT_SPECTRAL4_EVAL_H

#include <stddef.h>

#include "fit/spectral4_fit.h"
#include "models/spectral_data.h"

typedef enum sf_color_method_kind {
  SF_COLOR_FOUR_WAVELENGTHS,  /* XYZ = sum_i w_i cmf(l_i) L(l_i), then M_srgb */
  SF_COLOR_PLAIN_RGB          /* rgb = scale (L(l_r), L(l_g), L(l_b)) */
} sf_color_method_kind;

typedef struct sf_color_method {
  const char *name;
  sf_color_method_kind kind;
  sf_spectral4_params four;
  double rgb_nm[3], rgb_scale;
} sf_color_method;

/* Linear sRGB of spectrum L (n channels on an even grid) by method m. */
void sf_color_method_apply(const sf_color_method *m, const sf_cmf *cmf, int n, const double *lambda_nm,
                           const double *L, double rgb[3]);

typedef struct sf_delta_e_stats {
  double mean, p99, max;
  size_t n;
} sf_delta_e_stats;

/* Mean, 99th percentile (nearest rank) and maximum of values[0..n); sorts
 * values in place. */
void sf_delta_e_summarise(double *values, size_t n, sf_delta_e_stats *out);

#endif
