#include "codegen/emit_sky.h"

#include <math.h>
#include <stdlib.h>

#include "models/single_scattering.h"
#include "util/constants.h"

static double clampd(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

void sf_sky_clamped_angles(sf_sky_form form, double mu, double mu_s, double nu, double *theta, double *gamma,
                           double *elevation) {
  double ct = clampd(mu, form == SF_SKY_FORM_HOSEK ? 0.0 : SF_SKY_PEREZ_MIN_MU, 1.0);
  double ms = clampd(mu_s, -1.0, 1.0);
  double cg = sf_clamp_nu(ct, ms, clampd(nu, -1.0, 1.0));
  *theta = acos(ct);
  *gamma = acos(cg);
  *elevation = asin(ms);
}

void sf_sky_radiance_clamped(const sf_elevation_sky_model *m, double mu, double mu_s, double nu,
                             double *radiance) {
  double theta, gamma, elevation;
  sf_sky_clamped_angles(m->form, mu, mu_s, nu, &theta, &gamma, &elevation);
  sf_elevation_sky_radiance(m, elevation, theta, gamma, radiance);
  /* A radiance is never negative; the fitted forms dip below 0 near the
   * horizon at a low sun (Hosek's default fit: -0.0038 in G at 3 degrees). */
  for (int k = 0; k < m->n_channels; ++k) radiance[k] = radiance[k] > 0.0 ? radiance[k] : 0.0;
}

void sf_emit_sky(sf_code_writer *w, const sf_elevation_sky_model *m) {
  int n = m->n_channels, nc = m->n_coeffs, stride = nc + 1;
  int hosek = m->form == SF_SKY_FORM_HOSEK;
  const char *name = sf_sky_form_model_name(m->form);
  int count = n * SF_BEZIER_POINTS * stride;
  double *flat = malloc(sizeof(double) * (size_t)count);
  if (!flat) {
    sf_cw_emit(w, "@outofmemory");
    return;
  }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
      for (int i = 0; i < nc; ++i) flat[(k * SF_BEZIER_POINTS + j) * stride + i] = m->coefficients[k][j][i];
      flat[(k * SF_BEZIER_POINTS + j) * stride + nc] = m->scale[k][j];
    }
  if (hosek)
    sf_cw_emit(w, "/* hosek: L = S (1 + A exp(B / (cos theta + 0.01))) (C + D exp(E gamma) + F cos^2 gamma\n"
                  " *   + G (1 + cos^2 gamma) / (1 + H^2 - 2 H cos gamma)^(3/2) + I sqrt(cos theta)),\n"
                  " * seed 000 eq. 35-37; A..I and S a quintic Bezier in (elevation / (pi/2))^(1/3). */\n");
  else
    sf_cw_emit(w, "/* preetham (Perez form): L = S (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma),\n"
                  " * seed 000 eq. 33; A..E and S a quintic Bezier in (elevation / (pi/2))^(1/3). */\n");
  sf_cw_emit(w, "@fn %V skyfit_%s_sky_radiance(float mu, float mu_s, float nu) {\n", n, name);
  sf_cw_const_floats(w, "  ", "P", flat, count);
  free(flat);
  sf_cw_emit(w,
             "  float ct = @min(@max(mu, %F), 1.0f);\n"
             "  float ms = @min(@max(mu_s, -1.0f), 1.0f);\n"
             "  float cg = skyfit_clamp_nu(ct, ms, @min(@max(nu, -1.0f), 1.0f));\n"
             "  float gamma = skyfit_acos(cg);\n"
             "  float x = @pow(@min(@max(skyfit_asin(ms) * %F, 0.0f), 1.0f), %F);\n"
             "  float u = 1.0f - x;\n"
             "  float bw[6];\n"
             "  bw[0] = u * u * u * u * u;\n"
             "  bw[1] = 5.0f * u * u * u * u * x;\n"
             "  bw[2] = 10.0f * u * u * u * x * x;\n"
             "  bw[3] = 10.0f * u * u * x * x * x;\n"
             "  bw[4] = 5.0f * u * x * x * x * x;\n"
             "  bw[5] = x * x * x * x * x;\n"
             "  float L[4];\n"
             "  for (int k = 0; k < %d; ++k) {\n"
             "    float c[%d];\n"
             "    for (int i = 0; i < %d; ++i) {\n"
             "      float s = 0.0f;\n"
             "      for (int j = 0; j < 6; ++j) s += bw[j] * P[(k * 6 + j) * %d + i];\n"
             "      c[i] = s;\n"
             "    }\n",
             hosek ? 0.0 : SF_SKY_PEREZ_MIN_MU, 2.0 / SF_PI, 1.0 / 3.0, n, stride, stride, stride);
  if (hosek)
    sf_cw_emit(w,
               "    float q = 1.0f + c[7] * c[7] - 2.0f * c[7] * cg;\n"
               "    float chi = (1.0f + cg * cg) / (q * @sqrt(q));\n"
               "    L[k] = @max(c[9] * ((1.0f + c[0] * @exp(c[1] / (ct + 0.01f))) *\n"
               "                        (c[2] + c[3] * @exp(c[4] * gamma) + c[5] * cg * cg + c[6] * chi +\n"
               "                         c[8] * @sqrt(ct))), 0.0f);  /* never negative (the fit dips below 0) */\n"
               "  }\n");
  else
    sf_cw_emit(w,
               "    L[k] = @max(c[5] * ((1.0f + c[0] * @exp(c[1] / ct)) * (1.0f + c[2] * @exp(c[3] * gamma) +\n"
               "                                                       c[4] * cg * cg)), 0.0f);\n"
               "  }\n");
  if (n == 1) sf_cw_emit(w, "  return L[0];\n}\n\n");
  else if (n == 2) sf_cw_emit(w, "  return @vec2(L[0], L[1]);\n}\n\n");
  else if (n == 3) sf_cw_emit(w, "  return @vec3(L[0], L[1], L[2]);\n}\n\n");
  else sf_cw_emit(w, "  return @vec4(L[0], L[1], L[2], L[3]);\n}\n\n");
  sf_cw_need(w, SF_HELPER_CLAMP_NU | SF_HELPER_ASIN_ACOS);
}
