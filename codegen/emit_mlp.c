#include "codegen/emit_mlp.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codegen/emit_mlp_depth_diff.h"
#include "codegen/emit_mlp_parts.h"
#include "codegen/emit_phase.h"
#include "models/phase.h"
#include "util/constants.h"

static const char *const components[4] = {".x", ".y", ".z", ".w"};

/* Member k of a value of n floats ("" for a plain float). */
const char *sf_mlp_code_member(int n, int k) { return n == 1 ? "" : components[k]; }

int sf_emit_mlp_check(const sf_mlp_sky *m, char *problem, size_t n) {
  if (m->n_channels < 1 || m->n_channels > 4) {
    snprintf(problem, n, "emitted code returns vec1-vec4, the network has %d channels", m->n_channels);
    return -1;
  }
  for (int l = 0; l <= m->net.shape.n_layers; ++l)
    if (m->net.shape.sizes[l] > 64) {
      snprintf(problem, n, "layer %d has %d units; emitted networks have at most 64 per layer", l,
               m->net.shape.sizes[l]);
      return -1;
    }
  return 0;
}

/* Splits n units into pieces of at most 4: `by` units each when by > 0
 * (the separate target's per-channel blocks), else as evenly as possible
 * (8 -> 4 4, 9 -> 3 3 3, 5 -> 3 2). Returns the number of pieces. */
int sf_mlp_code_chunk_sizes(int n, int by, int *sizes) {
  if (by > 0) {
    int k = 0;
    for (int left = n; left > 0; left -= by) sizes[k++] = left < by ? left : by;
    return k;
  }
  int k = (n + 3) / 4;
  for (int i = 0; i < k; ++i) sizes[i] = n / k + (i < n % k ? 1 : 0);
  return k;
}

/* The float type of n values in GLSL. */
void sf_mlp_code_glsl_type(int n, char *out, size_t size) {
  if (n == 1) snprintf(out, size, "float");
  else snprintf(out, size, "vec%d", n);
}

/* f(value) for the activation, value a float (C) or float/vector (GLSL).
 * The clamps keep exp finite (SPEC §10); they change nothing above 1e-35. */
static void emit_activation(sf_code_writer *w, sf_mlp_activation a, const char *value) {
  int glsl = w->lang == SF_CODE_GLSL;
  switch (a) {
    case SF_ACT_SIGMOID: sf_cw_emit(w, "1.0f / (1.0f + @exp(-@max(%s, -87.0f)))", value); break;
    case SF_ACT_TANH:
      sf_cw_emit(w, "%s(@min(@max(%s, -20.0f), 20.0f))", glsl ? "tanh" : "tanhf", value);
      break;
    case SF_ACT_RELU: sf_cw_emit(w, "@max(%s, 0.0f)", value); break;
    case SF_ACT_LINEAR: sf_cw_emit(w, "%s", value); break;
    case SF_ACT_EXP_NEG: sf_cw_emit(w, "@exp(-@max(%s, -80.0f))", value); break;
    case SF_ACT_EXP_NEG_EXP: sf_cw_emit(w, "@exp(-@exp(-@max(%s, -80.0f)))", value); break;
  }
}


/* GLSL: output k among the last layer's pieces named prefix{last}_{c}. */
void sf_mlp_code_piece_name(const sf_mlp_code_outputs *o, const char *prefix, int k, char *out, size_t n) {
  int c = 0;
  while (k >= o->sizes[c]) k -= o->sizes[c++];
  snprintf(out, n, "%s%d_%d%s", prefix, o->last, c, sf_mlp_code_member(o->sizes[c], k));
}

static void out_name(const sf_code_writer *w, const sf_mlp_code_outputs *o, int k, char *out, size_t n) {
  if (w->lang == SF_CODE_C) snprintf(out, n, "o[%d]", k);
  else sf_mlp_code_piece_name(o, "a", k, out, n);
}

/* The network's parameters as one flat C array p, models/mlp.h order: W0
 * row-major, b0, W1, b1, ... */
void sf_mlp_code_params_c(sf_code_writer *w, const sf_mlp_f *net) {
  sf_cw_emit(w, "  static const float p[%d] = {", net->n_params);
  for (int i = 0; i < net->n_params; ++i) {
    if (i % 4 == 0) sf_cw_emit(w, "\n      ");
    sf_cw_emit(w, "%F", (double)net->params[i]);
    if (i + 1 < net->n_params) sf_cw_raw(w, i % 4 == 3 ? "," : ", ");
  }
  sf_cw_emit(w, "};\n");
}

/* GLSL: the constants of layer l's output piece oc (R rows from row0): its
 * biases b{l}_{oc} and, per input piece, the weight block W{l}_{oc}_{ic}
 * (a matrix, or a vector where either side is one unit). */
void sf_mlp_code_piece_constants_glsl(sf_code_writer *w, int l, int oc, int R, int row0, const float *W,
                                      const float *b, int n_in, const int *in_sizes, int n_in_chunks) {
  char type[16];
  sf_mlp_code_glsl_type(R, type, sizeof type);
  sf_cw_emit(w, "  const %s b%d_%d = %s(", type, l, oc, type);
  for (int i = 0; i < R; ++i) sf_cw_emit(w, i ? ", %F" : "%F", (double)b[row0 + i]);
  sf_cw_emit(w, ");\n");
  for (int ic = 0, col0 = 0; ic < n_in_chunks; col0 += in_sizes[ic++]) {
    int C = in_sizes[ic];
    char block[16];
    if (R > 1 && C > 1) {
      if (R == C) snprintf(block, sizeof block, "mat%d", C);
      else snprintf(block, sizeof block, "mat%dx%d", C, R);
    } else sf_mlp_code_glsl_type(R > 1 ? R : C, block, sizeof block);
    sf_cw_emit(w, "  const %s W%d_%d_%d = %s(", block, l, oc, ic, block);
    /* column-major: for each input (column), the outputs (rows) */
    for (int j = 0; j < C; ++j)
      for (int i = 0; i < R; ++i) sf_cw_emit(w, (i || j) ? ", %F" : "%F", (double)W[(row0 + i) * n_in + col0 + j]);
    sf_cw_emit(w, ");\n");
  }
}

void sf_mlp_code_piece_sum_glsl(char *sum, size_t size, int l, int oc, int R, const int *in_sizes, int n_in_chunks,
                                const char *input, int with_bias) {
  int k = with_bias ? snprintf(sum, size, "b%d_%d", l, oc) : 0;
  if (!with_bias) sum[0] = '\0';
  for (int ic = 0; ic < n_in_chunks; ++ic) {
    const char *plus = k ? " + " : "";
    if (R == 1 && in_sizes[ic] > 1)
      k += snprintf(sum + k, size - (size_t)k, "%sdot(W%d_%d_%d, %s%d_%d)", plus, l, oc, ic, input, l, ic);
    else
      k += snprintf(sum + k, size - (size_t)k, "%sW%d_%d_%d * %s%d_%d", plus, l, oc, ic, input, l, ic);
  }
}

void sf_mlp_code_outputs_set(sf_mlp_code_outputs *o, const int *sizes, int n_chunks, int last) {
  o->n_chunks = n_chunks;
  memcpy(o->sizes, sizes, sizeof o->sizes);
  o->last = last;
}

static void emit_network_c(sf_code_writer *w, const sf_mlp_f *net, sf_mlp_activation out_act) {
  const sf_mlp_shape *s = &net->shape;
  int widest = 1;
  for (int l = 0; l <= s->n_layers; ++l) widest = s->sizes[l] > widest ? s->sizes[l] : widest;
  sf_mlp_code_params_c(w, net);
  sf_cw_emit(w, "  float a[%d], o[%d];\n", widest, widest);
  for (int k = 0; k < s->sizes[0]; ++k) sf_cw_emit(w, "  a[%d] = x%d;\n", k, k);
  int offset = 0;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    int last = l + 1 == s->n_layers;
    sf_cw_emit(w,
               "  for (int i = 0; i < %d; ++i) {  /* layer %d: %d -> %d */\n"
               "    float z = p[%d + i];\n"
               "    for (int j = 0; j < %d; ++j) z += p[%d + i * %d + j] * a[j];\n"
               "    o[i] = ",
               n_out, l, n_in, n_out, offset + n_out * n_in, n_in, offset, n_in);
    emit_activation(w, last ? out_act : s->hidden, "z");
    sf_cw_emit(w, ";\n  }\n");
    if (!last) sf_cw_emit(w, "  for (int i = 0; i < %d; ++i) a[i] = o[i];\n", n_out);
    offset += n_out * (n_in + 1);
  }
}

static void emit_network_glsl(sf_code_writer *w, const sf_mlp_f *net, sf_mlp_activation out_act,
                              int out_by, sf_mlp_code_outputs *o) {
  const sf_mlp_shape *s = &net->shape;
  int in_sizes[SF_MLP_CODE_MAX_CHUNKS], out_sizes[SF_MLP_CODE_MAX_CHUNKS];
  int n_in_chunks = sf_mlp_code_chunk_sizes(s->sizes[0], 0, in_sizes);
  char type[16];
  for (int c = 0, k = 0; c < n_in_chunks; ++c) {
    sf_mlp_code_glsl_type(in_sizes[c], type, sizeof type);
    sf_cw_emit(w, "  %s a0_%d = %s(", type, c, type);
    for (int i = 0; i < in_sizes[c]; ++i, ++k) sf_cw_emit(w, i ? ", x%d" : "x%d", k);
    sf_cw_emit(w, ");\n");
  }
  int offset = 0;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    int last = l + 1 == s->n_layers;
    int n_out_chunks = sf_mlp_code_chunk_sizes(n_out, last ? out_by : 0, out_sizes);
    const float *W = net->params + offset, *b = W + n_out * n_in;
    sf_cw_emit(w, "  /* layer %d: %d -> %d */\n", l, n_in, n_out);
    for (int oc = 0, row0 = 0; oc < n_out_chunks; row0 += out_sizes[oc++]) {
      int R = out_sizes[oc];
      sf_mlp_code_glsl_type(R, type, sizeof type);
      sf_mlp_code_piece_constants_glsl(w, l, oc, R, row0, W, b, n_in, in_sizes, n_in_chunks);
      char sum[2048];
      sf_mlp_code_piece_sum_glsl(sum, sizeof sum, l, oc, R, in_sizes, n_in_chunks, "a", 1);
      sf_cw_emit(w, "  %s a%d_%d = ", type, l + 1, oc);
      char wrapped[2100];
      snprintf(wrapped, sizeof wrapped, "(%s)", sum);
      emit_activation(w, last ? out_act : s->hidden, wrapped);
      sf_cw_emit(w, ";\n");
    }
    memcpy(in_sizes, out_sizes, sizeof in_sizes);
    n_in_chunks = n_out_chunks;
    offset += n_out * (n_in + 1);
  }
  sf_mlp_code_outputs_set(o, in_sizes, n_in_chunks, s->n_layers);
}

static void emit_network(sf_code_writer *w, const sf_mlp_f *net, sf_mlp_activation out_act, int out_by,
                         sf_mlp_code_outputs *o) {
  memset(o, 0, sizeof *o);
  if (w->lang == SF_CODE_C) emit_network_c(w, net, out_act);
  else emit_network_glsl(w, net, out_act, out_by, o);
}

/* float x = (value - offset) * scale, as the model's float path. */
static void emit_input(sf_code_writer *w, const sf_mlp_sky *m, int k, const char *value) {
  sf_cw_emit(w, "  float x%d = (%E - %F) * %F;\n", k, value, (double)m->offset_f[k], (double)m->scale_f[k]);
}

/* "vecN(v, v, ...)" */
static void splat(char *out, size_t size, int n, const char *v) {
  int k = n == 1 ? snprintf(out, size, "(%s", v) : snprintf(out, size, "@vec%d(%s", n, v);
  for (int i = 1; i < n; ++i) k += snprintf(out + k, size - (size_t)k, ", %s", v);
  snprintf(out + k, size - (size_t)k, ")");
}

static int depth_mode(const sf_mlp_sky *t) {
  return t->net.shape.output == SF_ACT_EXP_NEG || t->net.shape.output == SF_ACT_EXP_NEG_EXP;
}

/* Radii as the float path has them (models/mlp_sky_impl.inc). */
typedef struct radii {
  double R, Rt, h_enter, h_top;
} radii;

static radii radii_of(const sf_mlp_sky *m) {
  radii r;
  float R = (float)m->bottom_radius_km, Rt = (float)m->top_radius_km;
  r.R = R;
  r.Rt = Rt;
  r.h_enter = (double)(Rt - R);
  r.h_top = (double)(float)(m->top_radius_km - m->bottom_radius_km);
  return r;
}

void sf_emit_mlp_transmittance(sf_code_writer *w, const sf_mlp_sky *t) {
  int n = t->n_channels, depth = depth_mode(t);
  radii g = radii_of(t);
  char ones[64];
  splat(ones, sizeof ones, n, "1.0f");
  sf_cw_emit(w,
             "/* mlp transmittance (seed 000 §9.6.1): network %d", t->net.shape.sizes[0]);
  for (int l = 1; l <= t->net.shape.n_layers; ++l) sf_cw_emit(w, "-%d", t->net.shape.sizes[l]);
  int bruneton = t->input_map == SF_MLP_INPUTS_BRUNETON;
  sf_cw_emit(w, ", %s hidden, %s output; inputs %s; %s. */\n",
             sf_mlp_activation_name(t->net.shape.hidden), sf_mlp_activation_name(t->net.shape.output),
             bruneton ? "Bruneton's x_r = rho / H, x_mu = (d - d_min) / (d_max - d_min)" : "sqrt(h), mu",
             depth ? "the network gives the optical depth to the top, tau_top = -log T_top"
                   : "the network gives T_top");
  /* the network's normalised inputs */
  sf_cw_emit(w, "@fn @vec2 skyfit_mlp_transmittance_inputs(float h_km, float mu) {\n");
  if (bruneton) {
    /* models/mlp_sky_impl.inc bruneton_coords, operation for operation */
    double R = t->bottom_radius_km, Rt = t->top_radius_km;
    float R_f = (float)R, Rt_f = (float)Rt, h_top_f = (float)(Rt - R), H_f = (float)sqrt((Rt - R) * (Rt + R));
    sf_cw_emit(w,
               "  float h = @min(@max(h_km, 0.0f), %F);\n"
               "  float m = @min(@max(mu, -1.0f), 1.0f);\n"
               "  float r = %F + h;\n"
               "  float rho = @sqrt(h * (%F + h));\n"
               "  float below = %F - h;  /* Rt - r */\n"
               "  float up = below * (%F + r);  /* Rt^2 - r^2 */\n"
               "  float rm = r * m;\n"
               "  float q = @sqrt(up + rm * rm);\n"
               "  float d = m > 0.0f ? up / (rm + q) : q - rm;  /* to the top, without cancellation */\n"
               "  float xm = (d - below) / (rho + %F - below);\n"
               "  float x_r = rho / %F;\n"
               "  float x_mu = @min(@max(xm, 0.0f), 1.0f);\n",
               (double)h_top_f, (double)R_f, (double)(2.0f * R_f), (double)h_top_f, (double)Rt_f, (double)H_f,
               (double)H_f);
    emit_input(w, t, 0, "x_r");
    emit_input(w, t, 1, "x_mu");
  } else {
    emit_input(w, t, 0, "@sqrt(@max(h_km, 0.0f))");
    emit_input(w, t, 1, "@min(@max(mu, -1.0f), 1.0f)");
  }
  sf_cw_emit(w, "  return @vec2(x0, x1);\n}\n\n");
  /* the raw network */
  sf_cw_emit(w,
             "@fn %V skyfit_mlp_transmittance_net(float h_km, float mu) {\n"
             "  @vec2 x = skyfit_mlp_transmittance_inputs(h_km, mu);\n"
             "  float x0 = x.x, x1 = x.y;\n",
             n);
  sf_mlp_code_outputs o;
  sf_mlp_activation out_act = depth ? SF_ACT_LINEAR : t->net.shape.output;
  emit_network(w, &t->net_f, out_act, 0, &o);
  sf_cw_emit(w, "  return %C", n);
  for (int c = 0; c < n; ++c) {
    char name[32];
    out_name(w, &o, c, name, sizeof name);
    if (c) sf_cw_emit(w, ", ");
    if (t->net.shape.output == SF_ACT_EXP_NEG_EXP) sf_cw_emit(w, "@exp(-@max(%s, -80.0f))", name);
    else sf_cw_emit(w, "%s", name);
  }
  sf_cw_emit(w, ");\n}\n\n");

  /* tau_top(a) - tau_top(b) without subtracting the two depths: at tau ~
   * 600 (SPEC §10's thick atmosphere) float32 had lost eq. 43's segment in
   * their rounding (T 1.3e-3 off) */
  if (depth) sf_emit_mlp_depth_diff(w, t);
  /* T_top(a) / T_top(b), eq. 43 */
  sf_cw_emit(w, "@fn %V skyfit_mlp_transmittance_ratio(float h_a, float mu_a, float h_b, float mu_b) {\n", n);
  if (depth)
    sf_cw_emit(w, "  %V d = skyfit_mlp_transmittance_depth_diff(h_a, mu_a, h_b, mu_b);\n  return %C", n, n);
  else
    sf_cw_emit(w,
               "  %V a = skyfit_mlp_transmittance_net(h_a, mu_a);\n"
               "  %V b = skyfit_mlp_transmittance_net(h_b, mu_b);\n"
               "  return %C",
               n, n, n);
  for (int c = 0; c < n; ++c) {
    const char *m = sf_mlp_code_member(n, c);
    if (c) sf_cw_emit(w, ",\n              ");
    if (depth) sf_cw_emit(w, "@exp(-@max(d%s, 0.0f))", m);
    else sf_cw_emit(w, "@min(@max(a%s / @max(b%s, 1e-30f), 0.0f), 1.0f)", m, m);
  }
  sf_cw_emit(w, ");\n}\n\n");

  sf_cw_emit(w,
             "/* the network's own quantity: T to the top from a viewer inside the\n"
             " * atmosphere; skyfit_mlp_transmittance takes any viewer (those in\n"
             " * space moved to where their ray enters, rays that miss: 1) */\n"
             "@fn %V skyfit_mlp_transmittance_top(float h_km, float mu) {\n"
             "  %V a = skyfit_mlp_transmittance_net(h_km, mu);\n"
             "  return %C",
             n, n, n);
  for (int c = 0; c < n; ++c) {
    const char *m = sf_mlp_code_member(n, c);
    if (c) sf_cw_emit(w, ", ");
    if (depth) sf_cw_emit(w, "@exp(-@max(a%s, 0.0f))", m);
    else sf_cw_emit(w, "@min(@max(a%s, 0.0f), 1.0f)", m);
  }
  sf_cw_emit(w, ");\n}\n\n");

  sf_cw_emit(w,
             "/* to the ground or the top; ground-hitting rays reversed (eq. 43, seed 000 §9.6.3) */\n"
             "@fn %V skyfit_mlp_transmittance(float h_km, float mu) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, h_km, mu, 0.0f, 0.0f);\n"
             "  if (e.w < 0.0f) return %E;\n"
             "  float h = e.x, m = e.y;\n"
             "  float r = %F + h;\n"
             "  @vec2 g = skyfit_sphere_hits(r, m, %F, -h);\n"
             "  if (!(m < 0.0f && g.x <= g.y)) return skyfit_mlp_transmittance_top(h, m);\n"
             "  float d = g.x > 0.0f ? g.x : 0.0f;\n"
             "  float mu_g = @min(@max((r * m + d) / %F, -1.0f), 1.0f);\n"
             "  return skyfit_mlp_transmittance_ratio(0.0f, -mu_g, h, -m);\n"
             "}\n\n",
             n, g.R, g.h_top, ones, g.R, g.R, g.R);
  sf_cw_emit(w,
             "/* The end of the first d km of the ray from altitude h along mu = m:\n"
             " * nothing lies past the ground, and an end on it is at altitude 0\n"
             " * exactly (from the distance, the altitude would cancel against the\n"
             " * radius). Returns (d cut at the ground, the altitude there before\n"
             " * clamping, the distance to the ground or -1 if the ray misses it,\n"
             " * 1 if the ray misses it and d reaches the top: the segment is the\n"
             " * whole ray, and a \"no hit\" d such as 3.4e38 or infinity would\n"
             " * overflow the altitude). */\n"
             "@fn @vec4 skyfit_mlp_segment_end(float h, float m, float d) {\n"
             "  @vec2 g = skyfit_sphere_hits(%F + h, m, %F, -h);\n"
             "  float d_ground = (m < 0.0f && g.x <= g.y) ? @max(g.x, 0.0f) : -1.0f;\n"
             "  if (d_ground >= 0.0f && d >= d_ground) return @vec4(d_ground, 0.0f, d_ground, 0.0f);\n"
             "  @vec2 s = skyfit_sphere_hits(%F + h, m, %F, %F - h);\n"
             "  if (d_ground < 0.0f && s.x <= s.y && d >= s.y) return @vec4(d, %F, -1.0f, 1.0f);\n"
             "  return @vec4(d, skyfit_altitude_at(%F, h, m, d), d_ground, 0.0f);\n"
             "}\n\n",
             g.R, g.R, g.R, g.Rt, g.h_top, g.h_top, g.R);
  sf_cw_emit(w,
             "/* the first t_km of that ray (eq. 43; reversed when the ray hits the ground or the\n"
             " * segment ends before the line's closest point: the two forms meet there up to\n"
             " * the network's error) */\n"
             "@fn %V skyfit_mlp_transmittance_segment(float h_km, float mu, float t_km) {\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, h_km, mu, 0.0f, 0.0f);\n"
             "  float d = t_km - e.w;\n"
             "  if (e.w < 0.0f || !(d > 0.0f)) return %E;\n"
             "  float h = e.x, m = e.y;\n"
             "  float r = %F + h;\n"
             "  @vec4 end = skyfit_mlp_segment_end(h, m, d);\n"
             "  if (end.w > 0.0f) return skyfit_mlp_transmittance_top(h, m);  /* the whole ray */\n"
             "  d = end.x;\n"
             "  float h_d = @min(@max(end.y, 0.0f), %F);\n"
             "  float mu_d = @min(@max((r * m + d) / @max(%F + end.y, 1e-6f), -1.0f), 1.0f);\n"
             "  /* reversed on the ground's rays, and before the closest point */\n"
             "  if (end.z >= 0.0f || mu_d < 0.0f) return skyfit_mlp_transmittance_ratio(h_d, -mu_d, h, -m);\n"
             "  return skyfit_mlp_transmittance_ratio(h, m, h_d, mu_d);\n"
             "}\n\n",
             n, g.R, g.h_top, ones, g.R, g.h_top, g.R);
  sf_cw_need(w, SF_HELPER_RAY_ENTER | SF_HELPER_SPHERE_HITS | SF_HELPER_ALTITUDE_AT);
}

/* float brightness = exp(b) of a brightness-normalised network
 * (models/mlp_sky.h: the polynomial at the inputs clamped to the fitted
 * square, capped, dimming on below its lowest sun), in the model's float
 * order. */
static void emit_brightness(sf_code_writer *w, const sf_mlp_output_norm *n) {
  int C = n->degree_mu_s;
  sf_cw_emit(w, "  /* log brightness of (sqrt h, mu_s), fit/output_norm.h */\n"
                "  float bu = @min(@max(x0, -1.0f), 1.0f), bv = @min(@max(x2, -1.0f), 1.0f);\n"
                "  float lb = 0.0f, slope = 0.0f, q;\n");
  for (int a = n->degree_h; a >= 0; --a) {
    const float *row = n->coef_f + a * (C + 1);
    sf_cw_emit(w, "  q = %F;\n", (double)row[C]);
    for (int c = C - 1; c >= 0; --c) sf_cw_emit(w, "  q = q * bv + %F;\n", (double)row[c]);
    sf_cw_emit(w, "  lb = lb * bu + q;\n  slope = slope * bu + %F;\n", (double)n->edge_slope_f[a]);
  }
  if (n->has_cap) sf_cw_emit(w, "  lb = lb > %F ? %F : lb;  /* the cap */\n", (double)n->cap_f, (double)n->cap_f);
  sf_cw_emit(w, "  float brightness = @exp(lb + @max(slope, 0.0f) * @min(x2 + 1.0f, 0.0f));\n");
}

void sf_emit_mlp_scattering(sf_code_writer *w, const sf_mlp_sky *s, const sf_mlp_sky *t) {
  int n = s->n_channels;
  radii g = radii_of(s);
  char zeros[64];
  splat(zeros, sizeof zeros, n, "0.0f");
  int split = s->horizon_split;
  sf_cw_emit(w, "/* mlp sky radiance (seed 000 §9.6.2): %s %d",
             split ? "networks (rays to the sky, rays to the ground)" : "network", s->net.shape.sizes[0]);
  for (int l = 1; l <= s->net.shape.n_layers; ++l) sf_cw_emit(w, "-%d", s->net.shape.sizes[l]);
  sf_cw_emit(w, ", %s hidden, %s output, target %s; inputs sqrt(h), mu, mu_s, nu. Sun irradiance 1. */\n",
             sf_mlp_activation_name(s->net.shape.hidden), sf_mlp_activation_name(s->net.shape.output),
             sf_mlp_target_name(s->target));
  if (split)   /* models/mlp_sky.h, the horizon split's test */
    sf_cw_emit(w,
               "/* 1 when the ray ends on the ground (the ground-ray network evaluates it) */\n"
               "@fn int skyfit_mlp_ray_ends_on_ground(float h_km, float mu) {\n"
               "  float h = @max(h_km, 0.0f);\n"
               "  float r = %F + h;\n"
               "  return (mu < 0.0f && -h * (%F + r) + (r * mu) * (r * mu) >= 0.0f) ? 1 : 0;\n"
               "}\n\n",
               g.R, g.R);
  sf_cw_emit(w, "@fn %V skyfit_mlp_sky_radiance_inside(float h_km, float mu, float mu_s, float nu%s) {\n", n,
             split ? ", int ground" : "");
  int separate = s->target == SF_MLP_TARGET_SEPARATE;
  if (split)   /* from h = 0 a ray to the ground has length 0 */
    sf_cw_emit(w, "  if (ground != 0 && !(h_km > 0.0f)) return %E;\n", zeros);
  emit_input(w, s, 0, "@sqrt(@max(h_km, 0.0f))");
  emit_input(w, s, 1, "mu");
  emit_input(w, s, 2, "mu_s");
  emit_input(w, s, 3, "nu");
  if (separate)
    for (int k = 0; k < s->n_single; ++k) sf_emit_phase(w, k, &s->phases[k]);
  for (int half = split; half >= 0; --half) {
    /* half 1: the ground-ray network, in its own block (same local names) */
    const char *indent = split ? "  " : "";
    if (half == 1) sf_cw_emit(w, "  if (ground != 0) {  /* rays to the ground */\n");
    else if (split) sf_cw_emit(w, "  {  /* rays to the sky */\n");
    const sf_mlp_output_norm *norm = half ? &s->norm_ground : &s->norm;
    if (norm->active) {   /* the network sees a sun below its lowest at the lowest */
      emit_brightness(w, norm);
      sf_cw_emit(w, "  x2 = @max(x2, -1.0f);\n");
    }
    sf_mlp_code_outputs o;
    emit_network(w, half ? &s->net_ground_f : &s->net_f, s->net.shape.output, separate ? n : 0, &o);
    /* an output that can go negative (linear, tanh) is held at 0: a
     * radiance (models/mlp_sky.h) */
    int clamp = sf_mlp_activation_can_be_negative(s->net.shape.output);
    sf_cw_emit(w, "  %sreturn %C", indent, n);
    for (int c = 0; c < n; ++c) {
      char name[32];
      if (c) sf_cw_emit(w, ",\n              %s", indent);
      out_name(w, &o, separate ? s->n_single * n + c : c, name, sizeof name);
      if (clamp) sf_cw_emit(w, "@max(");
      sf_cw_emit(w, "%s%s", name, norm->active ? " * brightness" : "");
      for (int k = 0; separate && k < s->n_single; ++k) {
        out_name(w, &o, k * n + c, name, sizeof name);
        sf_cw_emit(w, norm->active ? " + p%d * (%s * brightness)" : " + p%d * %s", k, name);
      }
      if (clamp) sf_cw_emit(w, ", 0.0f)");
    }
    sf_cw_emit(w, ");\n");
    if (split) sf_cw_emit(w, "  }\n");
  }
  sf_cw_emit(w, "}\n\n");

  sf_cw_emit(w,
             "/* the whole ray; a viewer in space first moved to where its ray enters */\n"
             "@fn %V skyfit_mlp_sky_radiance(float h_km, float mu, float mu_s, float nu) {\n"
             "  float m = @min(@max(mu, -1.0f), 1.0f), ms = @min(@max(mu_s, -1.0f), 1.0f);\n"
             "  float c = skyfit_clamp_nu(m, ms, nu);\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, h_km, m, ms, c);\n"
             "  if (e.w < 0.0f) return %E;\n"
             "  return skyfit_mlp_sky_radiance_inside(e.x, e.y, e.z, c%s);\n"
             "}\n\n",
             n, g.R, g.h_top, zeros, split ? ", skyfit_mlp_ray_ends_on_ground(e.x, e.y)" : "");
  sf_cw_need(w, SF_HELPER_RAY_ENTER | SF_HELPER_CLAMP_NU);
  if (!t) return;
  sf_cw_emit(w,
             "/* the first t_km of the ray (aerial perspective), eq. 44 */\n"
             "@fn %V skyfit_mlp_sky_radiance_segment(float h_km, float mu, float mu_s, float nu, float t_km) {\n"
             "  float m = @min(@max(mu, -1.0f), 1.0f), ms = @min(@max(mu_s, -1.0f), 1.0f);\n"
             "  float c = skyfit_clamp_nu(m, ms, nu);\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, h_km, m, ms, c);\n"
             "  float d = t_km - e.w;\n"
             "  if (e.w < 0.0f || !(d > 0.0f)) return %E;\n"
             "  float h = e.x;\n"
             "  m = e.y;\n"
             "  ms = e.z;\n"
             "  float r = %F + h;\n"
             "  @vec4 end = skyfit_mlp_segment_end(h, m, d);\n"
             "%s"
             "  %V lv = skyfit_mlp_sky_radiance_inside(h, m, ms, c%s);\n"
             "  if (end.w > 0.0f) return lv;  /* the whole ray: eq. 44's L at the top's exit is 0 */\n"
             "  d = end.x;\n"
             "  float h_d = @min(@max(end.y, 0.0f), %F);\n"
             "  float inv_r_d = 1.0f / @max(%F + end.y, 1e-6f);\n"
             "  float mu_d = @min(@max((r * m + d) * inv_r_d, -1.0f), 1.0f);\n"
             "  float mu_s_d = @min(@max((r * ms + d * c) * inv_r_d, -1.0f), 1.0f);\n"
             "  %V lp = skyfit_mlp_sky_radiance_inside(h_d, mu_d, mu_s_d, c%s);\n"
             "  %V tr = skyfit_mlp_transmittance_segment(h, m, d);\n"
             "  return %C",
             n, g.R, g.h_top, zeros, g.R,
             split ? "  int ground = skyfit_mlp_ray_ends_on_ground(h, m);  /* both ends: one ray */\n" : "", n,
             split ? ", ground" : "", g.h_top, g.R, n, split ? ", ground" : "", n, n);
  for (int c = 0; c < n; ++c) {
    const char *m = sf_mlp_code_member(n, c);
    if (c) sf_cw_emit(w, ",\n              ");
    sf_cw_emit(w, "@max(lv%s - tr%s * lp%s, 0.0f)", m, m, m);
  }
  sf_cw_emit(w, ");\n}\n\n");
}
