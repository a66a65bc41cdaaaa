#include "codegen/emit_spectral4.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/spectral_data.h"

/* What an atmosphere file refuses (SPEC §4) is refused here too: the
 * wavelengths positive and increasing, their weights, the coefficients and
 * the sun's irradiance not negative, the ground albedo in [0, 1]. */
static int check_physical(const char *source, const sf_spectral4_emit *m, sf_error *err) {
  for (int j = 0; j < 4; ++j) {
    if (!(m->wavelengths_nm[j] > 0.0) || (j > 0 && !(m->wavelengths_nm[j] > m->wavelengths_nm[j - 1])))
      return sf_fail(err, SF_ERR_INPUT, "%s: params.wavelengths_nm[%d]: wavelengths must be positive and strictly "
                     "increasing, got %.15g", source, j, m->wavelengths_nm[j]);
    if (!(m->weights_nm[j] >= 0.0))
      return sf_fail(err, SF_ERR_INPUT, "%s: params.weights_nm[%d]: must not be negative, got %.15g", source, j,
                     m->weights_nm[j]);
    if (!(m->sun_irradiance[j] >= 0.0))
      return sf_fail(err, SF_ERR_INPUT, "%s: params.sun_irradiance[%d]: must not be negative, got %.15g", source, j,
                     m->sun_irradiance[j]);
    if (!(m->ground_albedo[j] >= 0.0 && m->ground_albedo[j] <= 1.0))
      return sf_fail(err, SF_ERR_INPUT, "%s: params.ground_albedo[%d]: must be in [0, 1], got %.15g", source, j,
                     m->ground_albedo[j]);
    for (int c = 0; c < m->n_constituents; ++c) {
      if (!(m->scattering[c][j] >= 0.0))
        return sf_fail(err, SF_ERR_INPUT, "%s: params.scattering[%d][%d]: must not be negative, got %.15g", source,
                       c, j, m->scattering[c][j]);
      if (!(m->absorption[c][j] >= 0.0))
        return sf_fail(err, SF_ERR_INPUT, "%s: params.absorption[%d][%d]: must not be negative, got %.15g", source,
                       c, j, m->absorption[c][j]);
    }
  }
  return SF_OK;
}

/* Matrix entries agree when they differ by less than this fraction of their
 * row's largest entry: 8 float32 ulps, what the emitted constants round to
 * anyway, and above the rounding of a file written to 7 significant digits
 * (2.8e-7 on a fit of examples/scenes/spectral4.json: an sRGB entry sums 3
 * rounded XYZ entries times up to 3.2). */
#define MATRIX_MATCH 1e-6

static double row_scale(const double row[4]) {
  double s = 0.0;
  for (int j = 0; j < 4; ++j) s = fmax(s, fabs(row[j]));
  return s;
}

/* -1, with its row and column, if an entry of got (3 x 4) differs from
 * expected (row-major) by more than MATRIX_MATCH of its row's largest
 * entry (the first such); 0 if none does. */
static int first_mismatch(const double (*got)[4], const double *expected, int *row, int *col) {
  for (int r = 0; r < 3; ++r) {
    double scale = fmax(row_scale(expected + 4 * r), row_scale(got[r]));
    for (int j = 0; j < 4; ++j)
      if (!(fabs(got[r][j] - expected[4 * r + j]) <= MATRIX_MATCH * scale)) {
        *row = r;
        *col = j;
        return -1;
      }
  }
  return 0;
}

/* The two matrices are what the format defines (fit/spectral4_run.h):
 * to_xyz[c][i] = cmf_c(l_i) w_i (seed 003 eq. 5.12) and to_linear_srgb =
 * xyz_to_srgb . to_xyz. A file where they disagree would emit an XYZ and an
 * sRGB conversion of two different spectral renderings. */
static int check_matrices(const char *source, const sf_spectral4_emit *m, sf_error *err) {
  sf_cmf *cmf = malloc(sizeof *cmf);
  if (!cmf) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", source);
  int rc = sf_cmf_load(cmf, err);
  /* row-major 3 x 4, as models/spectral_data.h's functions take them */
  double file_xyz[12], expected_xyz[12], expected_srgb[12];
  memcpy(file_xyz, m->to_xyz, sizeof file_xyz);
  if (rc == SF_OK) sf_spectral4_to_xyz(cmf, m->wavelengths_nm, m->weights_nm, expected_xyz);
  sf_spectral4_srgb_of_xyz(file_xyz, expected_srgb);   /* of the file's own to_xyz */
  free(cmf);
  if (rc) return rc;
  int r, j;
  if (first_mismatch(m->to_xyz, expected_xyz, &r, &j))
    return sf_fail(err, SF_ERR_INPUT, "%s: params.to_xyz[%d][%d]: must be the colour matching function at "
                   "params.wavelengths_nm[%d] times params.weights_nm[%d] (%.9g), got %.9g", source, r, j, j, j,
                   expected_xyz[4 * r + j], m->to_xyz[r][j]);
  if (first_mismatch(m->to_linear_srgb, expected_srgb, &r, &j))
    return sf_fail(err, SF_ERR_INPUT, "%s: params.to_linear_srgb[%d][%d]: must be the XYZ-to-linear-sRGB matrix "
                   "times params.to_xyz (%.9g), got %.9g", source, r, j, expected_srgb[4 * r + j],
                   m->to_linear_srgb[r][j]);
  return SF_OK;
}

int sf_spectral4_emit_load(const sf_weights *w, sf_spectral4_emit *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  int nc = w->atmosphere.n_constituents;
  int s4[1] = {4}, s34[2] = {3, 4}, sc4[2] = {nc, 4};
  double flat[SF_MAX_CONSTITUENTS * 4];
  if (sf_weights_param(w, "wavelengths_nm", 1, s4, out->wavelengths_nm, 4, err) ||
      sf_weights_param(w, "weights_nm", 1, s4, out->weights_nm, 4, err) ||
      sf_weights_param(w, "to_xyz", 2, s34, &out->to_xyz[0][0], 12, err) ||
      sf_weights_param(w, "to_linear_srgb", 2, s34, &out->to_linear_srgb[0][0], 12, err) ||
      sf_weights_param(w, "sun_irradiance", 1, s4, out->sun_irradiance, 4, err) ||
      sf_weights_param(w, "ground_albedo", 1, s4, out->ground_albedo, 4, err))
    return err->status;
  out->n_constituents = nc;
  if (sf_weights_param(w, "scattering", 2, sc4, flat, nc * 4, err)) return err->status;
  for (int c = 0; c < nc; ++c) memcpy(out->scattering[c], flat + 4 * c, sizeof out->scattering[c]);
  if (sf_weights_param(w, "absorption", 2, sc4, flat, nc * 4, err)) return err->status;
  for (int c = 0; c < nc; ++c) memcpy(out->absorption[c], flat + 4 * c, sizeof out->absorption[c]);
  for (int c = 0; c < nc; ++c) snprintf(out->names[c], sizeof out->names[c], "%s", w->atmosphere.constituents[c].name);
  if (sf_weights_check_params_read(w, err)) return err->status;
  int rc = check_physical(w->source, out, err);
  return rc ? rc : check_matrices(w->source, out, err);
}

static void emit_matrix_fn(sf_code_writer *w, const char *name, const double m[3][4]) {
  sf_cw_emit(w, "@fn @vec3 skyfit_spectral4_%s(@vec4 radiance) {\n", name);
  if (w->lang == SF_CODE_GLSL) {
    sf_cw_emit(w, "  const mat4x3 M = mat4x3(");
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) sf_cw_emit(w, (i || j) ? ", %F" : "%F", m[i][j]);
    sf_cw_emit(w, ");\n  return M * radiance;\n}\n\n");
    return;
  }
  sf_cw_emit(w, "  static const float M[12] = {");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) sf_cw_emit(w, (i || j) ? ", %F" : "%F", m[i][j]);
  sf_cw_emit(w, "};\n  return @vec3(");
  for (int i = 0; i < 3; ++i)
    sf_cw_emit(w, "%sM[%d] * radiance.x + M[%d] * radiance.y + M[%d] * radiance.z + M[%d] * radiance.w",
               i ? ",\n                     " : "", 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3);
  sf_cw_emit(w, ");\n}\n\n");
}

static void emit_vec4_fn(sf_code_writer *w, const char *name, const double v[4]) {
  sf_cw_emit(w, "@fn @vec4 skyfit_spectral4_%s(%s) {\n  return @vec4(%F, %F, %F, %F);\n}\n\n", name,
             w->lang == SF_CODE_C ? "void" : "", v[0], v[1], v[2], v[3]);
}

static void emit_table_fn(sf_code_writer *w, const char *name, const sf_spectral4_emit *m,
                          const double (*rows)[4]) {
  int n = m->n_constituents;
  double flat[SF_MAX_CONSTITUENTS * 4];
  for (int c = 0; c < n; ++c) memcpy(flat + 4 * c, rows[c], sizeof rows[c]);
  sf_cw_emit(w, "/* per constituent:");
  for (int c = 0; c < n; ++c) {
    char item[SF_NAME_LEN + 16];
    int k = snprintf(item, sizeof item, " %d ", c);
    for (const char *q = m->names[c]; *q && k + 1 < (int)sizeof item; ++q)
      item[k++] = (*q == '*' || *q == '/' || *q == '%' || *q == '@') ? '_' : *q;
    item[k] = '\0';
    sf_cw_raw(w, item);
  }
  sf_cw_emit(w, " */\n@fn @vec4 skyfit_spectral4_%s(int constituent) {\n", name);
  sf_cw_const_floats(w, "  ", "v", flat, 4 * n);
  sf_cw_emit(w,
             "  if (constituent < 0 || constituent >= %d) return @vec4(0.0f, 0.0f, 0.0f, 0.0f);\n"
             "  int i = 4 * constituent;\n"
             "  return @vec4(v[i], v[i + 1], v[i + 2], v[i + 3]);\n}\n\n",
             n);
}

void sf_emit_spectral4(sf_code_writer *w, const sf_spectral4_emit *m) {
  char line[512];
  snprintf(line, sizeof line,
           "/* spectral4: seed 003 §5.4, XYZ = sum_i w_i cmf(l_i) L(l_i) (eq. 5.12) at\n"
           " * l = %.6g, %.6g, %.6g, %.6g nm, w = %.6g, %.6g, %.6g, %.6g nm. */\n",
           m->wavelengths_nm[0], m->wavelengths_nm[1], m->wavelengths_nm[2], m->wavelengths_nm[3],
           m->weights_nm[0], m->weights_nm[1], m->weights_nm[2], m->weights_nm[3]);
  sf_cw_raw(w, line);
  emit_matrix_fn(w, "to_linear_srgb", m->to_linear_srgb);
  emit_matrix_fn(w, "to_xyz", m->to_xyz);
  emit_vec4_fn(w, "wavelengths_nm", m->wavelengths_nm);
  emit_vec4_fn(w, "sun_irradiance", m->sun_irradiance);
  emit_vec4_fn(w, "ground_albedo", m->ground_albedo);
  emit_table_fn(w, "scattering", m, (const double(*)[4])m->scattering);
  emit_table_fn(w, "absorption", m, (const double(*)[4])m->absorption);
}
