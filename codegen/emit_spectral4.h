/* The 4-wavelength spectral weights (SPEC §7.3, seed 003 §5.4; weights
 * format in fit/spectral4_run.h) as emitted code: the 3x4 matrices and the
 * per-constituent coefficients at the 4 chosen wavelengths, so a renderer
 * computes its sky as one vec4 (one wavelength per component) and converts:
 *   vec3 skyfit_spectral4_to_linear_srgb(vec4 radiance)   M_srgb L (eq. 5.12, then XYZ -> sRGB)
 *   vec3 skyfit_spectral4_to_xyz(vec4 radiance)           M_xyz L (eq. 5.12)
 *   vec4 skyfit_spectral4_wavelengths_nm(void)            l_1 .. l_4
 *   vec4 skyfit_spectral4_sun_irradiance(void)
 *   vec4 skyfit_spectral4_ground_albedo(void)
 *   vec4 skyfit_spectral4_scattering(int constituent)     beta_s, 1/km (0 outside the range)
 *   vec4 skyfit_spectral4_absorption(int constituent)     beta_a, 1/km
 * (GLSL `()` for `(void)`). In GLSL the matrices are mat4x3 (4 columns,
 * 3 rows: M * L). Constituent indices follow the weights file's atmosphere. */
#ifndef SKYFIT_CODEGEN_EMIT_SPECTRAL4_H
#define SKYFIT_CODEGEN_EMIT_SPECTRAL4_H

#include "codegen/code_writer.h"
#include "models/atmosphere.h"
#include "models/weights_file.h"
#include "util/error.h"

typedef struct sf_spectral4_emit {
  double wavelengths_nm[4], weights_nm[4];
  double to_xyz[3][4], to_linear_srgb[3][4];
  double sun_irradiance[4], ground_albedo[4];
  int n_constituents;
  char names[SF_MAX_CONSTITUENTS][SF_NAME_LEN];
  double scattering[SF_MAX_CONSTITUENTS][4], absorption[SF_MAX_CONSTITUENTS][4];
} sf_spectral4_emit;

/* Reads the params of a "spectral4" weights file (shapes checked). */
int sf_spectral4_emit_load(const sf_weights *w, sf_spectral4_emit *out, sf_error *err);

void sf_emit_spectral4(sf_code_writer *w, const sf_spectral4_emit *m);

#endif
