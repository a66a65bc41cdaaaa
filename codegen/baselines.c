#include "codegen/baselines.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "models/air_segment.h"
#include "models/optical_depth.h"
#include "models/optical_depth_chapman.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_raymarch.h"
#include "models/optical_depth_taylor.h"

static const char *const kind_names[] = {"naive", "chapman", "taylor"};

int sf_baseline_kind_parse(const char *name) {
  for (int k = 0; k < 3; ++k)
    if (strcmp(name, kind_names[k]) == 0) return k;
  return -1;
}

const char *sf_baseline_kind_name(sf_baseline_kind kind) {
  return (unsigned)kind < 3 ? kind_names[kind] : "?";
}

void sf_baseline_describe(const sf_baseline *b, char *out, size_t n) {
  switch (b->kind) {
    case SF_BASELINE_NAIVE:
      snprintf(out, n, "%d-step midpoint raymarch of every constituent (SPEC 7.6 naive)",
               b->steps);
      break;
    case SF_BASELINE_CHAPMAN:
      snprintf(out, n, "Schuler's Chapman approximation (seed 000 eq. 22-25); "
                       "non-exponential constituents as seed 000 eq. 59 shells");
      break;
    default:
      snprintf(out, n, "Galaj's Taylor transmittance (seed 002 eq. 17, a = b = %.2f); "
                       "non-exponential constituents as seed 000 eq. 59 shells",
               SF_TAYLOR_A);
      break;
  }
}

int sf_baseline_check(const sf_baseline *b, sf_error *err) {
  const sf_atmosphere *atm = b->atmosphere;
  if (atm->n_channels < 1 || atm->n_channels > 4)
    return sf_fail(err, SF_ERR_INPUT,
                   "baseline %s: emitted code returns vec1-vec4, the atmosphere has %d channels",
                   sf_baseline_kind_name(b->kind), atm->n_channels);
  if (b->kind == SF_BASELINE_NAIVE && b->steps < 1)
    return sf_fail(err, SF_ERR_INPUT, "baseline naive: steps must be >= 1, got %d", b->steps);
  return SF_OK;
}

/* ---- double evaluation --------------------------------------------------- */

void sf_baseline_depth(const sf_baseline *b, double r, double mu, double t0, double t1,
                       double *depth) {
  const sf_atmosphere *atm = b->atmosphere;
  switch (b->kind) {
    case SF_BASELINE_NAIVE:
      sf_optical_depth_raymarch_segment(atm, r, mu, t0, t1, b->steps, SF_RAYMARCH_MIDPOINT,
                                        depth);
      return;
    case SF_BASELINE_CHAPMAN:
      sf_optical_depth_chapman_segment(atm, r, mu, t0, t1, depth);
      break;
    default:
      sf_optical_depth_taylor_segment(atm, r, mu, t0, t1, SF_TAYLOR_A, SF_TAYLOR_B, depth);
      break;
  }
  /* The constituents the approximation leaves out (NAN) are shells. */
  double a = t0, c = t1;
  int inside = sf_air_segment_clip(atm->bottom_radius_km, atm->top_radius_km, r, mu, &a, &c);
  for (int i = 0; i < atm->n_constituents; ++i) {
    if (!isnan(depth[i])) continue;
    double lo, hi;
    sf_flat_shell_of(atm, i, &lo, &hi);
    depth[i] = inside ? sf_flat_shell_chord(atm->bottom_radius_km + lo,
                                            atm->bottom_radius_km + hi, r, mu, a, c)
                      : 0.0;
  }
}

void sf_baseline_transmittance(const sf_baseline *b, double h_km, double mu, double t0,
                               double t1, double *transmittance) {
  double depth[SF_MAX_CONSTITUENTS];
  sf_baseline_depth(b, b->atmosphere->bottom_radius_km + h_km, mu, t0, t1, depth);
  sf_transmittance_from_depth(b->atmosphere, depth, transmittance);
}

/* ---- emission ------------------------------------------------------------- */

/* The clamped Bruneton density of constituent c at the float variable h
 * (models/atmosphere.c: layer by cumulative width, then clamp to [0, 1]). */
static void emit_layer_value(sf_code_writer *w, const sf_density_layer *l) {
  int terms = 0;
  if (l->linear_per_km != 0.0) {
    sf_cw_emit(w, "%F * h", l->linear_per_km);
    ++terms;
  }
  if (l->constant != 0.0) {
    sf_cw_emit(w, terms ? " + %F" : "%F", l->constant);
    ++terms;
  }
  if (l->exp_term != 0.0) {
    sf_cw_emit(w, terms ? " + %F * @exp(%F * h)" : "%F * @exp(%F * h)", l->exp_term,
               l->exp_scale_per_km);
    ++terms;
  }
  if (!terms) sf_cw_emit(w, "0.0f");
}

static void emit_density(sf_code_writer *w, const sf_constituent *c) {
  sf_cw_emit(w, "@min(@max(");
  double top_of_layer = 0.0;
  for (int i = 0; i < c->n_layers - 1; ++i) {
    top_of_layer += c->layers[i].width_km;
    sf_cw_emit(w, "h < %F ? ", top_of_layer);
    emit_layer_value(w, &c->layers[i]);
    sf_cw_emit(w, " : ");
  }
  if (c->n_layers > 0) emit_layer_value(w, &c->layers[c->n_layers - 1]);
  else sf_cw_emit(w, "0.0f");
  sf_cw_emit(w, ", 0.0f), 1.0f)");
}

/* return vecN(exp(-(sum_i extinction_i,ch * d_i)), ...) */
static void emit_transmittance_return(sf_code_writer *w, const sf_atmosphere *atm) {
  int n = atm->n_channels;
  sf_cw_emit(w, "  return %C", n);
  for (int ch = 0; ch < n; ++ch) {
    if (ch) sf_cw_emit(w, ",\n              ");
    int terms = 0;
    for (int i = 0; i < atm->n_constituents; ++i) {
      double e = sf_extinction(atm, i, ch);
      if (e == 0.0) continue;
      sf_cw_emit(w, terms ? " + %F * d%d" : "@exp(-(%F * d%d", e, i);
      ++terms;
    }
    sf_cw_emit(w, terms ? "))" : "1.0f");
  }
  sf_cw_emit(w, ");\n");
}

static void emit_naive_depths(sf_code_writer *w, const sf_baseline *b) {
  const sf_atmosphere *atm = b->atmosphere;
  sf_cw_emit(w,
             "    float dt = (seg.y - seg.x) / %F;\n"
             "    float k = 0.5f;\n"
             "    for (int i = 0; i < %d; ++i) {\n"
             "      float h = skyfit_altitude_at(%F, h_km, mu, seg.x + k * dt);\n",
             (double)b->steps, b->steps, atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    sf_cw_emit(w, "      d%d += ", i);
    emit_density(w, &atm->constituents[i]);
    sf_cw_emit(w, ";\n");
  }
  sf_cw_emit(w, "      k += 1.0f;\n    }\n");
  for (int i = 0; i < atm->n_constituents; ++i) sf_cw_emit(w, "    d%d *= dt;\n", i);
  sf_cw_need(w, SF_HELPER_ALTITUDE_AT);
}

/* The segment's ends as signed distances s from the line's closest
 * approach, the line itself, and the segment's shape (models/air_segment.c). */
static void emit_segment_ends(sf_code_writer *w, const sf_atmosphere *atm) {
  double bottom = atm->bottom_radius_km;
  sf_cw_emit(w,
             "    float r = %F + h_km;\n"
             "    float s0 = seg.x + r * mu, s1 = seg.y + r * mu;\n"
             "    /* the line's closest approach d and d^2 - bottom^2 = h (r + bottom) - (r mu)^2 */\n"
             "    float d = r * @sqrt((1.0f - mu) * (1.0f + mu));\n"
             "    float dd_bb = h_km * (r + %F) - (r * mu) * (r * mu);\n"
             "    int shape = s0 >= 0.0f ? 0 : (s1 <= 0.0f ? 1 : 2);\n",
             bottom, bottom);
}

static int is_exponential(const sf_constituent *c, double *H, double *d0) {
  return sf_constituent_exponential(c, H, d0);
}

static void emit_shells(sf_code_writer *w, const sf_atmosphere *atm) {
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0, lo, hi;
    if (is_exponential(&atm->constituents[i], &H, &d0)) continue;
    sf_flat_shell_of(atm, i, &lo, &hi);
    sf_cw_emit(w, "    d%d = skyfit_shell_chord(%F, %F, %F, h_km, mu, seg.x, seg.y);  /* %s: eq. 59 shell */\n",
               i, atm->bottom_radius_km, lo, hi, atm->constituents[i].name);
    sf_cw_need(w, SF_HELPER_SHELL_CHORD);
  }
}

static void emit_chapman_depths(sf_code_writer *w, const sf_baseline *b) {
  const sf_atmosphere *atm = b->atmosphere;
  emit_segment_ends(w, atm);
  sf_cw_emit(w,
             "    float h0 = seg.z, h1 = seg.w;\n"
             "    float r0 = %F + h0, r1 = %F + h1;\n"
             "    float c0 = @min(@max(s0 / r0, -1.0f), 1.0f);\n"
             "    float c1 = @min(@max(s1 / r1, -1.0f), 1.0f);\n"
             "    float hc = dd_bb / (d + %F);\n",
             atm->bottom_radius_km, atm->bottom_radius_km, atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!is_exponential(&atm->constituents[i], &H, &d0)) continue;
    /* seed 000 eq. 24: rising, falling (reversed), through the closest point */
    sf_cw_emit(w,
               "    {  /* %s */\n"
               "      float H = %F;\n"
               "      float tau = shape == 0 ? skyfit_chapman_up(H, h0, r0, c0) - skyfit_chapman_up(H, h1, r1, c1)\n"
               "                : shape == 1 ? skyfit_chapman_up(H, h1, r1, -c1) - skyfit_chapman_up(H, h0, r0, -c0)\n"
               "                : 2.0f * @sqrt(d / H) * @exp(-hc / H) - skyfit_chapman_up(H, h0, r0, -c0)\n"
               "                  - skyfit_chapman_up(H, h1, r1, c1);\n"
               "      d%d = tau > 0.0f ? %F * tau : 0.0f;\n"
               "    }\n",
               atm->constituents[i].name, H, i, H * d0);
  }
  sf_cw_need(w, SF_HELPER_CHAPMAN_UP);
  emit_shells(w, atm);
}

static void emit_taylor_depths(sf_code_writer *w, const sf_baseline *b) {
  const sf_atmosphere *atm = b->atmosphere;
  double bottom = atm->bottom_radius_km, top = atm->top_radius_km;
  emit_segment_ends(w, atm);
  /* seed 002 eq. 12 and the expansion point tau_b (models/optical_depth_taylor.c),
   * with b^2 - d^2 = -dd_bb and R^2 - d^2 = (R - r)(R + r) + (r mu)^2 */
  sf_cw_emit(w,
             "    float t_min = dd_bb < 0.0f ? @sqrt(-dd_bb) : 0.0f;\n"
             "    float tt = (%F - h_km) * (%F + r) + (r * mu) * (r * mu);\n"
             "    float t_max = tt > 0.0f ? @sqrt(tt) : 0.0f;\n"
             "    if (t_max < t_min) t_max = t_min;\n"
             "    float tau = t_min + %F * (t_max - t_min);\n"
             "    float rho = @sqrt(d * d + tau * tau);\n"
             "    @vec4 line = @vec4(tau, (dd_bb + tau * tau) / (rho + %F),\n"
             "                     rho > 0.0f ? tau / rho : 0.0f,\n"
             "                     rho > 0.0f ? %F * d * d / (rho * rho * rho) : 0.0f);\n"
             "    float u0 = @min(@max(@abs(s0), t_min), t_max);\n"
             "    float u1 = @min(@max(@abs(s1), t_min), t_max);\n",
             top - bottom, top, SF_TAYLOR_B, bottom, 0.5 * SF_TAYLOR_A);
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!is_exponential(&atm->constituents[i], &H, &d0)) continue;
    /* eq. 14 (one side of P_O) or eq. 13 (through it) */
    sf_cw_emit(w,
               "    {  /* %s */\n"
               "      float H = %F;\n"
               "      float tau_h = shape == 0 ? skyfit_taylor_piece(line, d, %F, H, u0, u1)\n"
               "                  : shape == 1 ? skyfit_taylor_piece(line, d, %F, H, u1, u0)\n"
               "                  : skyfit_taylor_piece(line, d, %F, H, t_min, u0)\n"
               "                    + skyfit_taylor_piece(line, d, %F, H, t_min, u1);\n"
               "      d%d = @min(%F * tau_h, 3.4e38f);\n"
               "    }\n",
               atm->constituents[i].name, H, bottom, bottom, bottom, bottom, i, d0);
  }
  sf_cw_need(w, SF_HELPER_TAYLOR_PIECE);
  emit_shells(w, atm);
}

void sf_emit_baseline(sf_code_writer *w, const sf_baseline *b) {
  const sf_atmosphere *atm = b->atmosphere;
  const char *name = sf_baseline_kind_name(b->kind);
  int n = atm->n_channels;
  char description[256];
  sf_baseline_describe(b, description, sizeof description);
  sf_cw_emit(w, "/* %s: %s. */\n", name, description);
  sf_cw_emit(w,
             "@fn %V skyfit_%s_transmittance_between(float h_km, float mu, float t0, float t1) {\n"
             "  @vec4 seg = skyfit_air_clip(%F, %F, h_km, mu, t0, t1);\n",
             n, name, atm->bottom_radius_km,
             atm->top_radius_km - atm->bottom_radius_km);
  sf_cw_need(w, SF_HELPER_AIR_CLIP);
  for (int i = 0; i < atm->n_constituents; ++i)
    sf_cw_emit(w, "  float d%d = 0.0f;  /* %s, km */\n", i, atm->constituents[i].name);
  sf_cw_emit(w, "  if (seg.y > seg.x) {\n");
  if (b->kind == SF_BASELINE_NAIVE) emit_naive_depths(w, b);
  else if (b->kind == SF_BASELINE_CHAPMAN) emit_chapman_depths(w, b);
  else emit_taylor_depths(w, b);
  sf_cw_emit(w, "  }\n");
  emit_transmittance_return(w, atm);
  sf_cw_emit(w,
             "}\n\n"
             "@fn %V skyfit_%s_transmittance(float h_km, float mu) {\n"
             "  return skyfit_%s_transmittance_between(h_km, mu, 0.0f, 3.4e38f);\n"
             "}\n\n"
             "@fn %V skyfit_%s_transmittance_segment(float h_km, float mu, float t_km) {\n"
             "  return skyfit_%s_transmittance_between(h_km, mu, 0.0f, t_km);\n"
             "}\n\n",
             n, name, name, n, name, name);
}

void sf_baseline_measure(const sf_baseline *b, const sf_scene_domain *domain, double *rmse,
                         double *max_abs) {
  const sf_atmosphere *atm = b->atmosphere;
  enum { NH = 16, NMU = 48 };
  double sum_sq = 0.0, worst = 0.0;
  long count = 0;
  for (int i = 0; i < NH; ++i) {
    double h = domain->h_min_km + (domain->h_max_km - domain->h_min_km) * i / (NH - 1);
    for (int j = 0; j < NMU; ++j) {
      double mu = domain->mu_min + (domain->mu_max - domain->mu_min) * j / (NMU - 1);
      double depth[SF_MAX_CONSTITUENTS], want[SF_MAX_CHANNELS], got[SF_MAX_CHANNELS];
      sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
      sf_transmittance_from_depth(atm, depth, want);
      sf_baseline_transmittance(b, h, mu, 0.0, INFINITY, got);
      for (int ch = 0; ch < atm->n_channels; ++ch) {
        double e = fabs(got[ch] - want[ch]);
        sum_sq += e * e;
        if (e > worst) worst = e;
        ++count;
      }
    }
  }
  *rmse = count ? sqrt(sum_sq / count) : 0.0;
  *max_abs = worst;
}
