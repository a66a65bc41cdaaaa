#include "codegen/emit_sigmoid.h"

#include <stdio.h>
#include <stdlib.h>

static void emit_return_t(sf_code_writer *w, int nk, const char *t) {
  if (nk == 1) sf_cw_emit(w, "  return %s[0];\n}\n\n", t);
  else if (nk == 2) sf_cw_emit(w, "  return @vec2(%s[0], %s[1]);\n}\n\n", t, t);
  else if (nk == 3) sf_cw_emit(w, "  return @vec3(%s[0], %s[1], %s[2]);\n}\n\n", t, t, t);
  else sf_cw_emit(w, "  return @vec4(%s[0], %s[1], %s[2], %s[3]);\n}\n\n", t, t, t, t);
}

void sf_emit_sigmoid_ray(sf_code_writer *w, const sf_sigmoid_emit *e) {
  const sf_sigmoid_model *m = &e->model;
  int nc = m->n_constituents, nk = m->n_channels;
  double *flat = malloc(sizeof(double) * (size_t)(nc * nk * SF_SIGMOID_N_COEFFS));
  if (!flat) {
    sf_cw_emit(w, "@outofmemory");
    return;
  }
  for (int c = 0; c < nc; ++c)
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j)
        flat[(c * nk + k) * SF_SIGMOID_N_COEFFS + j] = m->a[c][k][j];
  float R = (float)e->bottom_radius_km, Rt = (float)e->top_radius_km;
  double h_enter = (double)(Rt - R), h_top = (double)(float)(e->top_radius_km - e->bottom_radius_km);
  sf_cw_emit(w, "/* sigmoid: seed 000 §9.5, T = prod over constituents of\n"
                " * 1 / (1 + exp(-(a1 + a2 h + a3 mu + a4 mu^2))); a[constituent][channel][4].\n"
                " * `logt` selects log T (for segments) instead of T. */\n");
  sf_cw_emit(w, "@fn %V skyfit_sigmoid_fit(float h_km, float mu, int logt) {\n", nk);
  sf_cw_const_floats(w, "  ", "a", flat, nc * nk * SF_SIGMOID_N_COEFFS);
  free(flat);
  sf_cw_emit(w, "  float t[4];\n"
                "  for (int k = 0; k < %d; ++k) {\n"
                "    t[k] = logt != 0 ? 0.0f : 1.0f;\n"
                "    for (int c = 0; c < %d; ++c) {\n"
                "      int i = (c * %d + k) * 4;\n"
                "      float x = a[i] + a[i + 1] * h_km + a[i + 2] * mu + a[i + 3] * mu * mu;\n"
                "      /* log sigmoid(x) = -softplus(-x), stable both ways */\n"
                "      if (logt != 0) t[k] -= @max(-x, 0.0f) + @log(1.0f + @exp(-@abs(x)));\n"
                "      else t[k] *= skyfit_sigmoid(x);\n"
                "    }\n"
                "  }\n",
             nk, nc, nk);
  emit_return_t(w, nk, "t");
  char ones[64];
  if (nk == 1) snprintf(ones, sizeof ones, "1.0f");
  else if (nk == 2) snprintf(ones, sizeof ones, "@vec2(1.0f, 1.0f)");
  else if (nk == 3) snprintf(ones, sizeof ones, "@vec3(1.0f, 1.0f, 1.0f)");
  else snprintf(ones, sizeof ones, "@vec4(1.0f, 1.0f, 1.0f, 1.0f)");
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_transmittance(float h_km, float mu) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, %F, h_km, mu, 0.0f, 0.0f);\n"
             "  if (e.w < 0.0f) return %E;\n"
             "  return skyfit_sigmoid_fit(e.x, e.y, 0);\n"
             "}\n\n",
             nk, (double)R, (double)Rt, h_enter, ones);
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_transmittance_segment(float h_km, float mu, float t_km) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, %F, h_km, mu, 0.0f, 0.0f);\n"
             "  float d = t_km - e.w;\n"
             "  if (e.w < 0.0f || !(d > 0.0f)) return %E;\n"
             "  float h = e.x, m = e.y;\n"
             "  float r = %F + h;\n"
             "  /* the ray's end: the ground if it hits it, else the top */\n"
             "  @vec2 g = skyfit_ray_sphere(r, m, %F);\n"
             "  @vec2 top = skyfit_ray_sphere(r, m, %F);\n"
             "  float end = m < 0.0f && g.x <= g.y ? @max(g.x, 0.0f) : @max(top.y, 0.0f);\n"
             "  if (d >= end) return skyfit_sigmoid_fit(h, m, 0);\n"
             "  float r_d = skyfit_radius_at(r, m, d);\n"
             "  float mu_d = @min(@max((r * m + d) / @max(r_d, 1e-6f), -1.0f), 1.0f);\n"
             "  float h_d = @min(@max(r_d - %F, 0.0f), %F);\n"
             "  %V la = skyfit_sigmoid_fit(h, m, 1);\n"
             "  %V lb = skyfit_sigmoid_fit(h_d, mu_d, 1);\n"
             "  return %C",
             nk, (double)R, (double)Rt, h_enter, ones, (double)R, (double)R, (double)Rt, (double)R, h_top, nk, nk,
             nk);
  static const char *const mem[4] = {".x", ".y", ".z", ".w"};
  for (int k = 0; k < nk; ++k) {
    const char *s = nk == 1 ? "" : mem[k];
    sf_cw_emit(w, "%s@exp(@min(la%s - lb%s, 0.0f))", k ? ", " : "", s, s);
  }
  sf_cw_emit(w, ");\n}\n\n");
  sf_cw_need(w, SF_HELPER_SIGMOID | SF_HELPER_RAY_ENTER | SF_HELPER_RAY_SPHERE | SF_HELPER_RADIUS_AT);
}

void sf_emit_sigmoid(sf_code_writer *w, const sf_sigmoid_model *m) {
  int nc = m->n_constituents, nk = m->n_channels;
  double *flat = malloc(sizeof(double) * (size_t)(nc * nk * SF_SIGMOID_N_COEFFS));
  if (!flat) {
    sf_cw_emit(w, "@outofmemory");
    return;
  }
  for (int c = 0; c < nc; ++c)
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j)
        flat[(c * nk + k) * SF_SIGMOID_N_COEFFS + j] = m->a[c][k][j];
  sf_cw_emit(w, "/* sigmoid: seed 000 §9.5, T = prod over constituents of\n"
                " * 1 / (1 + exp(-(a1 + a2 h + a3 mu + a4 mu^2))); a[constituent][channel][4]. */\n");
  sf_cw_emit(w, "@fn %V skyfit_sigmoid_transmittance(float h_km, float mu) {\n", nk);
  sf_cw_const_floats(w, "  ", "a", flat, nc * nk * SF_SIGMOID_N_COEFFS);
  free(flat);
  sf_cw_emit(w, "  float t[4];\n"
                "  for (int k = 0; k < %d; ++k) {\n"
                "    t[k] = 1.0f;\n"
                "    for (int c = 0; c < %d; ++c) {\n"
                "      int i = (c * %d + k) * 4;\n"
                "      t[k] *= skyfit_sigmoid(a[i] + a[i + 1] * h_km + a[i + 2] * mu + a[i + 3] * mu * mu);\n"
                "    }\n"
                "  }\n",
             nk, nc, nk);
  emit_return_t(w, nk, "t");
  sf_cw_need(w, SF_HELPER_SIGMOID);
}
