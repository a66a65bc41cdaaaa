#include "codegen/emit_sigmoid.h"

#include <stdio.h>
#include <stdlib.h>

static void emit_return_t(sf_code_writer *w, int nk, const char *t) {
  if (nk == 1) sf_cw_emit(w, "  return %s[0];\n}\n\n", t);
  else if (nk == 2) sf_cw_emit(w, "  return @vec2(%s[0], %s[1]);\n}\n\n", t, t);
  else if (nk == 3) sf_cw_emit(w, "  return @vec3(%s[0], %s[1], %s[2]);\n}\n\n", t, t, t);
  else sf_cw_emit(w, "  return @vec4(%s[0], %s[1], %s[2], %s[3]);\n}\n\n", t, t, t, t);
}

/* Per channel: "@min(0.0f, A.x - B.x)"-style combination into a vector. */
static void emit_combine(sf_code_writer *w, int nk, const char *fmt_one) {
  static const char *const mem[4] = {".x", ".y", ".z", ".w"};
  sf_cw_emit(w, "%C", nk);
  for (int k = 0; k < nk; ++k) {
    const char *s = nk == 1 ? "" : mem[k];
    char piece[256];
    snprintf(piece, sizeof piece, fmt_one, s, s);
    sf_cw_emit(w, "%s%E", k ? ", " : "", piece);
  }
  sf_cw_emit(w, ");\n");
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
  double R = (double)(float)e->bottom_radius_km;
  double h_top = (double)(float)(e->top_radius_km - e->bottom_radius_km);
  char ones[64];
  if (nk == 1) snprintf(ones, sizeof ones, "1.0f");
  else if (nk == 2) snprintf(ones, sizeof ones, "@vec2(1.0f, 1.0f)");
  else if (nk == 3) snprintf(ones, sizeof ones, "@vec3(1.0f, 1.0f, 1.0f)");
  else snprintf(ones, sizeof ones, "@vec4(1.0f, 1.0f, 1.0f, 1.0f)");
  sf_cw_emit(w, "/* sigmoid: seed 000 §9.5 and eq. 43 (models/sigmoid_transmittance.h): the fit is\n"
                " * log T_top = sum over constituents of -softplus(-(a1 + a2 h + a3 mu + a4 mu^2)),\n"
                " * a[constituent][channel][4]; rays looking down are reversed. */\n");
  sf_cw_emit(w, "@fn %V skyfit_sigmoid_log_top(float h_km, float mu) {\n", nk);
  sf_cw_const_floats(w, "  ", "a", flat, nc * nk * SF_SIGMOID_N_COEFFS);
  free(flat);
  sf_cw_emit(w, "  float t[4];\n"
                "  for (int k = 0; k < %d; ++k) {\n"
                "    t[k] = 0.0f;\n"
                "    for (int c = 0; c < %d; ++c) {\n"
                "      int i = (c * %d + k) * 4;\n"
                "      float x = a[i] + a[i + 1] * h_km + a[i + 2] * mu + a[i + 3] * mu * mu;\n"
                "      t[k] -= @max(-x, 0.0f) + @log(1.0f + @exp(-@abs(x)));\n"
                "    }\n"
                "  }\n",
             nk, nc, nk);
  emit_return_t(w, nk, "t");
  /* log T of the whole ray from a viewer inside: steps 3-5; whether the
   * line hits the ground is passed in, so that the two ends of a segment
   * (the same line) take the same branch even where float32 evaluations of
   * the hit test at the two ends would disagree (grazing rays) */
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_log_line(float h, float mu, int ground) {\n"
             "  if (mu >= 0.0f) return skyfit_sigmoid_log_top(h, mu);\n"
             "  float r = %F + h;\n"
             "  float disc = -h * (r + %F) + (r * mu) * (r * mu);\n"
             "  %V up = skyfit_sigmoid_log_top(h, -mu);\n"
             "  if (ground == 0) {  /* past the tangent point and up again */\n"
             "    float h_t = @max(-disc, 0.0f) / (@sqrt(r * r * ((1.0f - mu) * (1.0f + mu))) + %F);\n"
             "    %V tangent = skyfit_sigmoid_log_top(h_t, 0.0f);\n"
             "    return ",
             nk, R, R, nk, R, nk);
  emit_combine(w, nk, "@min(0.0f, 2.0f * tangent%s - up%s)");
  sf_cw_emit(w,
             "  }\n"
             "  %V ground_up = skyfit_sigmoid_log_top(0.0f, @sqrt(@max(disc, 0.0f)) / %F);  /* reversed, eq. 43 */\n"
             "  return ",
             nk, R);
  emit_combine(w, nk, "@min(0.0f, ground_up%s - up%s)");
  sf_cw_emit(w, "}\n\n");
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_log_full(float h, float mu) {\n"
             "  @vec2 g = skyfit_sphere_hits(%F + h, mu, %F, -h);\n"
             "  return skyfit_sigmoid_log_line(h, mu, mu < 0.0f && g.x <= g.y ? 1 : 0);\n"
             "}\n\n",
             nk, R, R);
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_transmittance(float h_km, float mu) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, @max(h_km, 0.0f), @min(@max(mu, -1.0f), 1.0f), 0.0f, 0.0f);\n"
             "  if (e.w < 0.0f) return %E;\n"
             "  %V l = skyfit_sigmoid_log_full(e.x, e.y);\n"
             "  return ",
             nk, R, h_top, ones, nk);
  emit_combine(w, nk, "@exp(l%s)");
  sf_cw_emit(w, "}\n\n");
  sf_cw_emit(w,
             "@fn %V skyfit_sigmoid_transmittance_segment(float h_km, float mu, float t_km) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, @max(h_km, 0.0f), @min(@max(mu, -1.0f), 1.0f), 0.0f, 0.0f);\n"
             "  float d = t_km - e.w;\n"
             "  if (e.w < 0.0f || !(d > 0.0f)) return %E;\n"
             "  float h = e.x, m = e.y;\n"
             "  float r = %F + h;\n"
             "  /* the segment ends at the ray's end at most: the ground or the top */\n"
             "  @vec2 g = skyfit_sphere_hits(r, m, %F, -h);\n"
             "  @vec2 top = skyfit_sphere_hits(r, m, %F, %F - h);\n"
             "  int ground = m < 0.0f && g.x <= g.y ? 1 : 0;  /* as skyfit_sigmoid_log_full decides */\n"
             "  float end = ground != 0 ? @max(g.x, 0.0f) : @max(top.y, 0.0f);\n"
             "  if (d >= end) {  /* the whole ray: the fit's T_top at the exit is not 1 exactly */\n"
             "    %V l = skyfit_sigmoid_log_line(h, m, ground);\n"
             "    return ",
             nk, R, h_top, ones, R, R, R + h_top, h_top, nk);
  emit_combine(w, nk, "@exp(l%s)");
  sf_cw_emit(w,
             "  }\n"
             "  float h_raw = skyfit_altitude_at(%F, h, m, d);\n"
             "  float h_d = @min(@max(h_raw, 0.0f), %F);\n"
             "  float mu_d = @min(@max((r * m + d) / @max(%F + h_raw, 1e-6f), -1.0f), 1.0f);\n"
             "  %V la, lb;\n"
             "  if (ground != 0) {  /* reversed: from the point at d back up through the viewer */\n"
             "    la = skyfit_sigmoid_log_top(h_d, -mu_d);\n"
             "    lb = skyfit_sigmoid_log_top(h, -m);\n"
             "  } else {\n"
             "    la = skyfit_sigmoid_log_line(h, m, 0);\n"
             "    lb = skyfit_sigmoid_log_line(h_d, mu_d, 0);\n"
             "  }\n"
             "  return ",
             R, h_top, R, nk);
  emit_combine(w, nk, "@exp(@min(la%s - lb%s, 0.0f))");
  sf_cw_emit(w, "}\n\n");
  sf_cw_need(w, SF_HELPER_RAY_ENTER | SF_HELPER_SPHERE_HITS | SF_HELPER_ALTITUDE_AT);
}
