#include "codegen/baseline_spline.h"

#include <stdio.h>

/* Hermite value on [0, 1] with slopes already scaled by the step, and the
 * weights of the 1-D node data across a d cell. */
static void emit_helpers(sf_code_writer *w) {
  sf_cw_emit(w,
      "#ifndef SKYFIT_HELPER_SPLINE\n#define SKYFIT_HELPER_SPLINE\n"
      "/* cubic Hermite on [0, 1]: values p0, p1, slopes (times the step) m0, m1 */\n"
      "@fn float skyfit_hermite(float u, float p0, float m0, float p1, float m1) {\n"
      "  float u2 = u * u, u3 = u2 * u;\n"
      "  return (2.0f * u3 - 3.0f * u2 + 1.0f) * p0 + (u3 - 2.0f * u2 + u) * m0\n"
      "         + (3.0f * u2 - 2.0f * u3) * p1 + (u3 - u2) * m1;\n"
      "}\n"
      "@fn @vec4 skyfit_hermite_weights(float v) {\n"
      "  float v2 = v * v, v3 = v2 * v;\n"
      "  return @vec4(2.0f * v3 - 3.0f * v2 + 1.0f, v3 - 2.0f * v2 + v,\n"
      "               3.0f * v2 - 2.0f * v3, v3 - v2);\n"
      "}\n"
      "#endif\n\n");
}

/* One vec4 per node (value, x slope, d slope, mixed slope): Mesa's llvmpipe
 * compiles a 1000-element vec4 array in seconds, the same data as a
 * 4000-element float array in minutes. */
static void emit_grid_array(sf_code_writer *w, const char *name, const sf_spline_grid *g) {
  int n = g->n_x * g->n_d, c = w->lang == SF_CODE_C;
  sf_cw_emit(w, c ? "static const @vec4 %s[%d] = {\n" : "const @vec4 %s[%d] = @vec4[%d](\n", name,
             n, n);
  for (int k = 0; k < n; ++k)
    sf_cw_emit(w, c ? "    {%F, %F, %F, %F}%s\n" : "    @vec4(%F, %F, %F, %F)%s\n", g->value[k],
               g->d_dx[k], g->d_dd[k], g->d_dxdd[k], k + 1 < n ? "," : "");
  sf_cw_emit(w, c ? "};\n" : ");\n");
}

/* The d cell (float counter: no float-to-int cast, spelled alike in C and
 * GLSL), the node data of the 1-D spline, and the loop over the x cells
 * up to b; `piece` is the body that adds one cell's integral over [lo, hi]
 * to sum given p0, m0, p1, m1 (slopes times the step) and x0. Each node's
 * data is formed once (a cell's end is the next one's start) and the loop
 * stops at b's cell, as the double model's (models/optical_depth_spline.c)
 * does: the same bits as forming both ends of every cell, 6 % faster (the
 * pieces' Gauss-Legendre nodes are most of the cost). */
static void emit_integral(sf_code_writer *w, const char *fn, const char *array,
                          const sf_spline_grid *g, const char *extra_param, const char *piece) {
  sf_cw_emit(w,
      "@fn float %s(float d, float a, float b%s) {\n"
      "  float x = (d - %F) / %F;\n"
      "  int j = 0;\n"
      "  float fj = 0.0f, fk = 0.0f;\n"
      "  for (int k = 0; k < %d; ++k) {\n"
      "    if (x >= fk) { j = k; fj = fk; }\n"
      "    fk += 1.0f;\n"
      "  }\n"
      "  @vec4 wd = skyfit_hermite_weights(@min(@max(x - fj, 0.0f), 1.0f));\n"
      "  float ds = %F, xs = %F;\n"
      "  a = @max(a, 0.0f);\n"
      "  b = @min(b, %F);\n"
      "  float sum = 0.0f, x0 = 0.0f;\n"
      "  int k0 = j * %d, k1 = k0 + %d;\n"
      "  float p0 = wd.x * %s[k0].x + wd.y * ds * %s[k0].z + wd.z * %s[k1].x + wd.w * ds * %s[k1].z;\n"
      "  float m0 = xs * (wd.x * %s[k0].y + wd.y * ds * %s[k0].w + wd.z * %s[k1].y + wd.w * ds * %s[k1].w);\n"
      "  for (int i = 0; i < %d; ++i) {\n"
      "    float x1 = x0 + xs;\n"
      "    k0 += 1; k1 += 1;\n"
      "    float p1 = wd.x * %s[k0].x + wd.y * ds * %s[k0].z + wd.z * %s[k1].x + wd.w * ds * %s[k1].z;\n"
      "    float m1 = xs * (wd.x * %s[k0].y + wd.y * ds * %s[k0].w + wd.z * %s[k1].y + wd.w * ds * %s[k1].w);\n"
      "    float lo = @max(a, x0), hi = i == %d ? b : @min(b, x1);\n"
      "    if (hi > lo) {\n"
      "%E"
      "    }\n"
      "    if (b <= x1) break;\n"
      "    p0 = p1; m0 = m1;\n"
      "    x0 = x1;\n"
      "  }\n"
      "  return sum;\n"
      "}\n\n",
      fn, extra_param, g->d_first, g->d_step, g->n_d - 1, g->d_step, g->x_step,
      g->x_step * (g->n_x - 1), g->n_x, g->n_x,
      array, array, array, array, array, array, array, array,
      g->n_x - 1,
      array, array, array, array, array, array, array, array, g->n_x - 2, piece);
}

/* Region I: a cubic, exact with 2-point Gauss-Legendre. */
static const char miss_piece[] =
    "      float hw = 0.5f * (hi - lo), mid = 0.5f * (hi + lo), g = hw * 0.57735026918962576f;\n"
    "      sum += hw * (skyfit_hermite((mid - g - x0) / xs, p0, m0, p1, m1)\n"
    "                     + skyfit_hermite((mid + g - x0) / xs, p0, m0, p1, m1));\n";

/* Region II: s(h) / sqrt(h + delta) is 2 s(q^2 - delta) dq, q = sqrt(h +
 * delta), degree 6 in q: exact with 4-point Gauss-Legendre. */
static const char hit_piece[] =
    "      float qa = @sqrt(lo + delta), qb = @sqrt(hi + delta), qc = @sqrt(x0 + delta);\n"
    "      float hw = 0.5f * (hi - lo) / (qa + qb), mid = 0.5f * (qa + qb);\n"
    "      float q1 = mid - hw * 0.86113631159405258f, q2 = mid - hw * 0.33998104358485626f;\n"
    "      float q3 = mid + hw * 0.33998104358485626f, q4 = mid + hw * 0.86113631159405258f;\n"
    "      sum += 2.0f * hw * (0.34785484513745386f * (skyfit_hermite((q1 - qc) * (q1 + qc) / xs, p0, m0, p1, m1)\n"
    "                                                   + skyfit_hermite((q4 - qc) * (q4 + qc) / xs, p0, m0, p1, m1))\n"
    "                            + 0.65214515486254614f * (skyfit_hermite((q2 - qc) * (q2 + qc) / xs, p0, m0, p1, m1)\n"
    "                                                     + skyfit_hermite((q3 - qc) * (q3 + qc) / xs, p0, m0, p1, m1)));\n";

void sf_emit_spline_tables(sf_code_writer *w, const sf_spline_model *model) {
  emit_helpers(w);
  for (int i = 0; i < model->n_constituents; ++i) {
    if (!model->is_exponential[i]) continue;
    char array[64], fn[64];
    snprintf(array, sizeof array, "skyfit_spline_miss_nodes_%d", i);
    emit_grid_array(w, array, &model->miss[i]);
    snprintf(fn, sizeof fn, "skyfit_spline_miss_%d", i);
    emit_integral(w, fn, array, &model->miss[i], "", miss_piece);
    snprintf(array, sizeof array, "skyfit_spline_hit_nodes_%d", i);
    emit_grid_array(w, array, &model->hit[i]);
    snprintf(fn, sizeof fn, "skyfit_spline_hit_%d", i);
    emit_integral(w, fn, array, &model->hit[i], ", float delta", hit_piece);
  }
}

void sf_emit_spline_depths(sf_code_writer *w, const sf_atmosphere *atm,
                           const sf_spline_model *model) {
  /* region I in |s| from P_O, region II in the altitude (seed 002 §IV.E);
   * eq. 13 through P_O, eq. 14 as one integral between the ends. A segment
   * through P_O is on a line that misses the ground whatever float32 says
   * of d (the clip decided): region I, as in the double model. */
  sf_cw_emit(w,
             "    float h0 = seg.z, h1 = seg.w;\n"
             "    float u0 = @abs(s0), u1 = @abs(s1);\n"
             "    float delta = -dd_bb / (d + %F);  /* r - d */\n",
             atm->bottom_radius_km);
  for (int i = 0; i < model->n_constituents; ++i) {
    if (!model->is_exponential[i]) continue;
    sf_cw_emit(w,
               "    {  /* %s */\n"
               "      float tau = dd_bb >= 0.0f || shape == 2\n"
               "          ? (shape == 2 ? skyfit_spline_miss_%d(d, 0.0f, u0) + skyfit_spline_miss_%d(d, 0.0f, u1)\n"
               "                        : skyfit_spline_miss_%d(d, @min(u0, u1), @max(u0, u1)))\n"
               "          : (shape == 2 ? skyfit_spline_hit_%d(d, 0.0f, h0, delta) + skyfit_spline_hit_%d(d, 0.0f, h1, delta)\n"
               "                        : skyfit_spline_hit_%d(d, @min(h0, h1), @max(h0, h1), delta));\n"
               "      d%d = tau > 0.0f ? %F * tau : 0.0f;\n"
               "    }\n",
               atm->constituents[i].name, i, i, i, i, i, i, i, model->surface_density[i]);
  }
}
