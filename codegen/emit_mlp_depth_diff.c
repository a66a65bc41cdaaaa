#include "codegen/emit_mlp_depth_diff.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codegen/emit_mlp_parts.h"

/* ---- tau_top(a) - tau_top(b) of a depth-mode transmittance network ----
 * (models/mlp_sky_impl.inc t_depth_diff, unit_diff): the two forward passes
 * and their difference carried beside them, dx = x_a - x_b, dz = W d(a_prev)
 * (the biases cancel), d(a) of each unit from dz without subtracting two
 * close values. */

/* The per-unit difference helpers the hidden activation and the output
 * need; |dz| >= 1 takes the plain difference, as accurate as dz there. */
static void emit_diff_helpers(sf_code_writer *w, sf_mlp_activation hidden, sf_mlp_activation out) {
  if (hidden == SF_ACT_SIGMOID)
    sf_cw_emit(w,
               "/* s(z_a) - s(z_b) of the sigmoid from e_a = exp(-z_a), s_a, s_b and dz = z_a - z_b:\n"
               " * s_a s_b (e^-z_b - e^-z_a) = e_a s_a s_b expm1(dz) */\n"
               "@fn float skyfit_mlp_sigmoid_diff(float e_a, float s_a, float s_b, float dz) {\n"
               "  return @abs(dz) < 1.0f ? e_a * s_a * s_b * skyfit_expm1(dz) : s_a - s_b;\n"
               "}\n\n");
  if (hidden == SF_ACT_TANH)
    sf_cw_emit(w,
               "/* tanh(z_a) - tanh(z_b) = tanh(dz) (1 - t_a t_b), tanh(dz) from expm1(2 dz) */\n"
               "@fn float skyfit_mlp_tanh_diff(float t_a, float t_b, float dz) {\n"
               "  if (!(@abs(dz) < 1.0f)) return t_a - t_b;\n"
               "  float e = skyfit_expm1(2.0f * dz);\n"
               "  return e / (e + 2.0f) * (1.0f - t_a * t_b);\n"
               "}\n\n");
  if (hidden == SF_ACT_RELU)
    sf_cw_emit(w,
               "/* relu(z_a) - relu(z_b): dz where both are positive */\n"
               "@fn float skyfit_mlp_relu_diff(float z_a, float z_b, float dz) {\n"
               "  if (z_a > 0.0f && z_b > 0.0f) return dz;\n"
               "  return @max(z_a, 0.0f) - @max(z_b, 0.0f);\n"
               "}\n\n");
  if (out == SF_ACT_EXP_NEG_EXP)
    sf_cw_emit(w,
               "/* the optical depths e^-z_a - e^-z_b = e^-z_b expm1(-dz) (exp_neg_exp output) */\n"
               "@fn float skyfit_mlp_depth_diff(float z_a, float z_b, float dz) {\n"
               "  float t_a = @exp(-@max(z_a, -80.0f)), t_b = @exp(-@max(z_b, -80.0f));\n"
               "  return @abs(dz) < 1.0f ? t_b * skyfit_expm1(-dz) : t_a - t_b;\n"
               "}\n\n");
  if (hidden == SF_ACT_SIGMOID || hidden == SF_ACT_TANH || out == SF_ACT_EXP_NEG_EXP)
    sf_cw_need(w, SF_HELPER_EXPM1);
}

/* C: units of the two points in ua, ub, their difference in ud; the
 * inputs are floats xa0.., xb0.. and their difference dx0..; the outputs
 * tau_a - tau_b in vd. */
static void emit_network_diff_c(sf_code_writer *w, const sf_mlp_f *net, sf_mlp_activation out) {
  const sf_mlp_shape *s = &net->shape;
  int widest = 1;
  for (int l = 0; l <= s->n_layers; ++l) widest = s->sizes[l] > widest ? s->sizes[l] : widest;
  sf_mlp_code_params_c(w, net);
  sf_cw_emit(w, "  float ua[%d], ub[%d], ud[%d], va[%d], vb[%d], vd[%d];\n", widest, widest, widest, widest,
             widest, widest);
  for (int k = 0; k < s->sizes[0]; ++k)
    sf_cw_emit(w, "  ua[%d] = xa%d;\n  ub[%d] = xb%d;\n  ud[%d] = dx%d;\n", k, k, k, k, k, k);
  int offset = 0;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    int last = l + 1 == s->n_layers, only_dz = last && out == SF_ACT_EXP_NEG;
    sf_cw_emit(w, "  for (int i = 0; i < %d; ++i) {  /* layer %d: %d -> %d */\n", n_out, l, n_in, n_out);
    if (only_dz)   /* tau = z: d tau = dz */
      sf_cw_emit(w,
                 "    float dz = 0.0f;\n"
                 "    for (int j = 0; j < %d; ++j) dz += p[%d + i * %d + j] * ud[j];\n"
                 "    vd[i] = dz;\n  }\n",
                 n_in, offset, n_in);
    else
      sf_cw_emit(w,
                 "    float za = p[%d + i], zb = za, dz = 0.0f;\n"
                 "    for (int j = 0; j < %d; ++j) {\n"
                 "      float wij = p[%d + i * %d + j];\n"
                 "      za += wij * ua[j];\n"
                 "      zb += wij * ub[j];\n"
                 "      dz += wij * ud[j];\n"
                 "    }\n",
                 offset + n_out * n_in, n_in, offset, n_in);
    if (last && !only_dz) {
      sf_cw_emit(w, "    vd[i] = skyfit_mlp_depth_diff(za, zb, dz);\n  }\n");
    } else if (!last) {
      switch (s->hidden) {
        case SF_ACT_SIGMOID:
          sf_cw_emit(w,
                     "    float ea = @exp(-@max(za, -87.0f));\n"
                     "    va[i] = 1.0f / (1.0f + ea);\n"
                     "    vb[i] = 1.0f / (1.0f + @exp(-@max(zb, -87.0f)));\n"
                     "    vd[i] = skyfit_mlp_sigmoid_diff(ea, va[i], vb[i], dz);\n");
          break;
        case SF_ACT_TANH:
          sf_cw_emit(w,
                     "    va[i] = tanhf(@min(@max(za, -20.0f), 20.0f));\n"
                     "    vb[i] = tanhf(@min(@max(zb, -20.0f), 20.0f));\n"
                     "    vd[i] = skyfit_mlp_tanh_diff(va[i], vb[i], dz);\n");
          break;
        case SF_ACT_RELU:
          sf_cw_emit(w,
                     "    va[i] = @max(za, 0.0f);\n"
                     "    vb[i] = @max(zb, 0.0f);\n"
                     "    vd[i] = skyfit_mlp_relu_diff(za, zb, dz);\n");
          break;
        default:
          sf_cw_emit(w, "    va[i] = za;\n    vb[i] = zb;\n    vd[i] = dz;\n");
          break;
      }
      sf_cw_emit(w,
                 "  }\n"
                 "  for (int i = 0; i < %d; ++i) {\n"
                 "    ua[i] = va[i];\n"
                 "    ub[i] = vb[i];\n"
                 "    ud[i] = vd[i];\n"
                 "  }\n",
                 n_out);
    }
    offset += n_out * (n_in + 1);
  }
}

/* f(args with member m of each vector name), component by component:
 * "vecR(f(e.x, a.x), f(e.y, a.y), ...)" (R = 1: "f(e, a)"). */
static void emit_per_component(sf_code_writer *w, int R, const char *f, int n_args, const char *const *args) {
  char type[16];
  sf_mlp_code_glsl_type(R, type, sizeof type);
  if (R > 1) sf_cw_emit(w, "%s(", type);
  for (int k = 0; k < R; ++k) {
    sf_cw_emit(w, k ? ", %s(" : "%s(", f);
    for (int a = 0; a < n_args; ++a) sf_cw_emit(w, a ? ", %s%s" : "%s%s", args[a], sf_mlp_code_member(R, k));
    sf_cw_emit(w, ")");
  }
  if (R > 1) sf_cw_emit(w, ")");
}

/* GLSL: the pieces ua{l}_{c}, ub{l}_{c} (the two points) and ud{l}_{c}
 * (their difference); inputs xa0.., xb0.., dx0..; the outputs tau_a - tau_b in the
 * last layer's ud pieces, named as out_name with prefix "ud". */
static void emit_network_diff_glsl(sf_code_writer *w, const sf_mlp_f *net, sf_mlp_activation out, sf_mlp_code_outputs *o) {
  const sf_mlp_shape *s = &net->shape;
  int in_sizes[SF_MLP_CODE_MAX_CHUNKS], out_sizes[SF_MLP_CODE_MAX_CHUNKS];
  int n_in_chunks = sf_mlp_code_chunk_sizes(s->sizes[0], 0, in_sizes);
  char type[16];
  static const char *const sides[3] = {"a", "b", "d"};
  for (int side = 0; side < 3; ++side)
    for (int c = 0, k = 0; c < n_in_chunks; ++c) {
      sf_mlp_code_glsl_type(in_sizes[c], type, sizeof type);
      sf_cw_emit(w, "  %s u%s0_%d = %s(", type, sides[side], c, type);
      for (int i = 0; i < in_sizes[c]; ++i, ++k) {
        if (side < 2) sf_cw_emit(w, i ? ", x%s%d" : "x%s%d", sides[side], k);
        else sf_cw_emit(w, i ? ", dx%d" : "dx%d", k);
      }
      sf_cw_emit(w, ");\n");
    }
  int offset = 0;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    int last = l + 1 == s->n_layers;
    int n_out_chunks = sf_mlp_code_chunk_sizes(n_out, 0, out_sizes);
    const float *W = net->params + offset, *b = W + n_out * n_in;
    sf_cw_emit(w, "  /* layer %d: %d -> %d */\n", l, n_in, n_out);
    for (int oc = 0, row0 = 0; oc < n_out_chunks; row0 += out_sizes[oc++]) {
      int R = out_sizes[oc];
      sf_mlp_code_glsl_type(R, type, sizeof type);
      sf_mlp_code_piece_constants_glsl(w, l, oc, R, row0, W, b, n_in, in_sizes, n_in_chunks);
      /* za, zb as the forward pass sums them; dz without the bias */
      for (int side = 0; side < 3; ++side) {
        char sum[2048], input[4];
        snprintf(input, sizeof input, "u%s", sides[side]);
        sf_mlp_code_piece_sum_glsl(sum, sizeof sum, l, oc, R, in_sizes, n_in_chunks, input, side < 2);
        sf_cw_emit(w, "  %s z%s%d_%d = (%s);\n", type, sides[side], l, oc, sum);
      }
      char za[32], zb[32], dz[32], va[32], vb[32], ea[32];
      snprintf(za, sizeof za, "za%d_%d", l, oc);
      snprintf(zb, sizeof zb, "zb%d_%d", l, oc);
      snprintf(dz, sizeof dz, "zd%d_%d", l, oc);
      snprintf(va, sizeof va, "ua%d_%d", l + 1, oc);
      snprintf(vb, sizeof vb, "ub%d_%d", l + 1, oc);
      snprintf(ea, sizeof ea, "ea%d_%d", l, oc);
      if (last) {
        sf_cw_emit(w, "  %s ud%d_%d = ", type, l + 1, oc);
        if (out == SF_ACT_EXP_NEG) sf_cw_emit(w, "%s", dz);   /* tau = z */
        else {
          const char *args[3] = {za, zb, dz};
          emit_per_component(w, R, "skyfit_mlp_depth_diff", 3, args);
        }
        sf_cw_emit(w, ";\n");
        continue;
      }
      switch (s->hidden) {
        case SF_ACT_SIGMOID: {
          sf_cw_emit(w,
                     "  %s %s = @exp(-@max(%s, -87.0f));\n"
                     "  %s %s = 1.0f / (1.0f + %s);\n"
                     "  %s %s = 1.0f / (1.0f + @exp(-@max(%s, -87.0f)));\n"
                     "  %s ud%d_%d = ",
                     type, ea, za, type, va, ea, type, vb, zb, type, l + 1, oc);
          const char *args[4] = {ea, va, vb, dz};
          emit_per_component(w, R, "skyfit_mlp_sigmoid_diff", 4, args);
          break;
        }
        case SF_ACT_TANH: {
          sf_cw_emit(w,
                     "  %s %s = tanh(@min(@max(%s, -20.0f), 20.0f));\n"
                     "  %s %s = tanh(@min(@max(%s, -20.0f), 20.0f));\n"
                     "  %s ud%d_%d = ",
                     type, va, za, type, vb, zb, type, l + 1, oc);
          const char *args[3] = {va, vb, dz};
          emit_per_component(w, R, "skyfit_mlp_tanh_diff", 3, args);
          break;
        }
        case SF_ACT_RELU: {
          sf_cw_emit(w, "  %s %s = @max(%s, 0.0f);\n  %s %s = @max(%s, 0.0f);\n  %s ud%d_%d = ", type, va, za, type,
                     vb, zb, type, l + 1, oc);
          const char *args[3] = {za, zb, dz};
          emit_per_component(w, R, "skyfit_mlp_relu_diff", 3, args);
          break;
        }
        default:
          sf_cw_emit(w, "  %s %s = %s;\n  %s %s = %s;\n  %s ud%d_%d = %s", type, va, za, type, vb, zb, type, l + 1,
                     oc, dz);
          break;
      }
      sf_cw_emit(w, ";\n");
    }
    memcpy(in_sizes, out_sizes, sizeof in_sizes);
    n_in_chunks = n_out_chunks;
    offset += n_out * (n_in + 1);
  }
  sf_mlp_code_outputs_set(o, in_sizes, n_in_chunks, s->n_layers);
}

/* x_a - x_b of skyfit_mlp_transmittance_inputs from the differences of
 * the mapping's parts (models/mlp_sky_impl.inc t_inputs_diff, operation
 * for operation): each mapped value carries a few ulp of rounding, which
 * a network at tau ~ 500 turns into 3e-5 of a segment's T. */
static void emit_inputs_diff(sf_code_writer *w, const sf_mlp_sky *t) {
  sf_cw_emit(w,
             "/* x_a - x_b of skyfit_mlp_transmittance_inputs without subtracting the two\n"
             " * mapped values (models/mlp_sky_impl.inc t_inputs_diff) */\n");
  if (t->input_map != SF_MLP_INPUTS_BRUNETON) {
    sf_cw_emit(w,
               "@fn @vec2 skyfit_mlp_transmittance_inputs_diff(float h_a, float mu_a, float h_b, float mu_b) {\n"
               "  float ha = @max(h_a, 0.0f), hb = @max(h_b, 0.0f);\n"
               "  float sa = @sqrt(ha), sb = @sqrt(hb);\n"
               "  return @vec2((sa + sb > 0.0f ? (ha - hb) / (sa + sb) : 0.0f) * %F,\n"
               "               (@min(@max(mu_a, -1.0f), 1.0f) - @min(@max(mu_b, -1.0f), 1.0f)) * %F);\n"
               "}\n\n",
               (double)t->scale_f[0], (double)t->scale_f[1]);
    return;
  }
  sf_cw_emit(w,
             "@fn @vec2 skyfit_mlp_transmittance_inputs_diff(float h_a, float mu_a, float h_b, float mu_b, @vec2 xa,\n"
             "                                               @vec2 xb) {\n");
  double R = t->bottom_radius_km, Rt = t->top_radius_km;
  float R_f = (float)R, Rt_f = (float)Rt, h_top_f = (float)(Rt - R), H_f = (float)sqrt((Rt - R) * (Rt + R));
  sf_cw_emit(w,
             "  float ha = @min(@max(h_a, 0.0f), %F), hb = @min(@max(h_b, 0.0f), %F);\n"
             "  float ma = @min(@max(mu_a, -1.0f), 1.0f), mb = @min(@max(mu_b, -1.0f), 1.0f);\n"
             "  float dh = ha - hb, two_r = %F + ha + hb;\n"
             "  float rho_a = @sqrt(ha * (%F + ha)), rho_b = @sqrt(hb * (%F + hb));\n"
             "  float drho = rho_a + rho_b > 0.0f ? dh * two_r / (rho_a + rho_b) : 0.0f;\n"
             "  float dx_r = drho / %F * %F;\n"
             "  float below_a = %F - ha, below_b = %F - hb;\n"
             "  float up_a = below_a * (%F + (%F + ha)), up_b = below_b * (%F + (%F + hb));\n"
             "  float rm_a = (%F + ha) * ma, rm_b = (%F + hb) * mb;\n"
             "  float q_a = @sqrt(up_a + rm_a * rm_a), q_b = @sqrt(up_b + rm_b * rm_b);\n"
             "  float d_a = ma > 0.0f ? up_a / (rm_a + q_a) : q_a - rm_a;\n"
             "  float d_b = mb > 0.0f ? up_b / (rm_b + q_b) : q_b - rm_b;\n"
             "  float N_a = d_a - below_a, N_b = d_b - below_b;\n"
             "  float D_a = rho_a + %F - below_a, D_b = rho_b + %F - below_b;\n"
             "  float xm_a = N_a / D_a, xm_b = N_b / D_b;\n"
             "  if (!(xm_a > 0.0f && xm_a < 1.0f && xm_b > 0.0f && xm_b < 1.0f)) return @vec2(dx_r, xa.y - xb.y);\n"
             "  float drm = %F * (ma - mb) + (ha * ma - hb * mb);\n"
             "  float dup = -dh * two_r;  /* Rt^2 - r^2 */\n"
             "  float dq = q_a + q_b > 0.0f ? (dup + drm * (rm_a + rm_b)) / (q_a + q_b) : 0.0f;\n"
             "  float dd = dq - drm;  /* the distance to the top */\n"
             "  if (ma > 0.0f && mb > 0.0f) {\n"
             "    float s_a = rm_a + q_a, s_b = rm_b + q_b;\n"
             "    dd = (dup * s_b - up_b * (drm + dq)) / (s_a * s_b);\n"
             "  }\n"
             "  float dN = dd + dh, dD = drho + dh;\n"
             "  return @vec2(dx_r, (dN * D_b - N_b * dD) / (D_a * D_b) * %F);\n"
             "}\n\n",
             (double)h_top_f, (double)h_top_f, (double)(2.0f * R_f), (double)(2.0f * R_f), (double)(2.0f * R_f),
             (double)H_f, (double)t->scale_f[0], (double)h_top_f, (double)h_top_f, (double)Rt_f, (double)R_f,
             (double)Rt_f, (double)R_f, (double)R_f, (double)R_f, (double)H_f, (double)H_f, (double)R_f,
             (double)t->scale_f[1]);
}

void sf_emit_mlp_depth_diff(sf_code_writer *w, const sf_mlp_sky *t) {
  int n = t->n_channels, bruneton = t->input_map == SF_MLP_INPUTS_BRUNETON;
  emit_diff_helpers(w, t->net.shape.hidden, t->net.shape.output);
  emit_inputs_diff(w, t);
  sf_cw_emit(w,
             "/* tau_top(h_a, mu_a) - tau_top(h_b, mu_b), the difference carried through the\n"
             " * network beside the two forward passes (models/mlp_sky_impl.inc t_depth_diff) */\n"
             "@fn %V skyfit_mlp_transmittance_depth_diff(float h_a, float mu_a, float h_b, float mu_b) {\n"
             "  @vec2 xa = skyfit_mlp_transmittance_inputs(h_a, mu_a);\n"
             "  @vec2 xb = skyfit_mlp_transmittance_inputs(h_b, mu_b);\n"
             "  @vec2 dx = skyfit_mlp_transmittance_inputs_diff(h_a, mu_a, h_b, mu_b%s);\n"
             "  float xa0 = xa.x, xa1 = xa.y, xb0 = xb.x, xb1 = xb.y, dx0 = dx.x, dx1 = dx.y;\n",
             n, bruneton ? ", xa, xb" : "");
  sf_mlp_code_outputs od;
  memset(&od, 0, sizeof od);
  if (w->lang == SF_CODE_C) emit_network_diff_c(w, &t->net_f, t->net.shape.output);
  else emit_network_diff_glsl(w, &t->net_f, t->net.shape.output, &od);
  sf_cw_emit(w, "  return %C", n);
  for (int c = 0; c < n; ++c) {
    char name[32];
    if (w->lang == SF_CODE_C) snprintf(name, sizeof name, "vd[%d]", c);
    else sf_mlp_code_piece_name(&od, "ud", c, name, sizeof name);
    sf_cw_emit(w, c ? ", %s" : "%s", name);
  }
  sf_cw_emit(w, ");\n}\n\n");
}
