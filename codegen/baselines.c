#include "codegen/baselines.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "models/air_segment.h"
#include "models/optical_depth.h"
#include "models/optical_depth_chapman.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_raymarch.h"
#include "models/optical_depth_spline.h"
#include "models/optical_depth_taylor.h"
#include "models/ray_geometry.h"
#include "models/tangent_sweep.h"
#include "codegen/baseline_spline.h"
#include "codegen/emit_sky_frame.h"

static const char *const kind_names[SF_BASELINE_COUNT] = {"naive", "chapman", "taylor", "flat",
                                                               "spline"};

int sf_baseline_kind_parse(const char *name) {
  for (int k = 0; k < SF_BASELINE_COUNT; ++k)
    if (strcmp(name, kind_names[k]) == 0) return k;
  return -1;
}

const char *sf_baseline_kind_name(sf_baseline_kind kind) {
  return (unsigned)kind < SF_BASELINE_COUNT ? kind_names[kind] : "?";
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
    case SF_BASELINE_FLAT:
      snprintf(out, n, "Leenman's flat model (seed 000 eq. 51; eq. 53 about the closest point, Fig. 11; "
                       "ground point as midpoint, 11.3.3; eq. 59 shells)");
      break;
    case SF_BASELINE_SPLINE:
      snprintf(out, n, "Galaj's spline transmittance (seed 002 IV.E, Hermite meshes %d x %d); "
                       "non-exponential constituents as seed 000 eq. 59 shells",
               SF_SPLINE_HEIGHT_POINTS, SF_SPLINE_DISTANCE_POINTS);
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
  if (b->kind != SF_BASELINE_NAIVE && sf_atmosphere_exponential_count(atm) == 0)
    return sf_fail(err, SF_ERR_INPUT,
                   "baseline %s: the analytic optical depths need an exponential constituent; %s has none",
                   sf_baseline_kind_name(b->kind), atm->name);
  if (b->kind == SF_BASELINE_SPLINE &&
      (!b->spline || b->spline->n_constituents != atm->n_constituents))
    return sf_fail(err, SF_ERR_INTERNAL, "baseline spline: no spline model for its atmosphere");
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
    case SF_BASELINE_SPLINE:
      sf_optical_depth_spline_segment(b->spline, r, mu, t0, t1, depth);  /* shells included */
      return;
    case SF_BASELINE_FLAT:
      for (int i = 0; i < atm->n_constituents; ++i) {
        double H, d0;
        depth[i] = sf_constituent_exponential(&atm->constituents[i], &H, &d0)
                       ? d0 * sf_flat_exponential_segment(atm->bottom_radius_km, atm->top_radius_km,
                                                          H, SF_FLAT_DESCENT_CLOSEST, r, mu, t0, t1)
                       : NAN;
      }
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
  const sf_atmosphere *atm = b->atmosphere;
  double depth[SF_MAX_CONSTITUENTS] = {0}, r = atm->bottom_radius_km + h_km;
  /* A viewer above the top starts where its ray enters, as the emitted
   * code's skyfit_ray_enter moves it (the sun's cosine is not used). */
  double t_enter = 0.0, mu_e = mu;
  if (r > atm->top_radius_km &&
      (!sf_ray_enter_from_above(r, mu, 1.0, mu, atm->top_radius_km, &t_enter, &mu_e, NULL) || !(t1 > t_enter))) {
    sf_transmittance_from_depth(atm, depth, transmittance);   /* never enters: T = 1 */
    return;
  }
  if (t_enter > 0.0)
    sf_baseline_depth(b, atm->top_radius_km, mu_e, fmax(t0 - t_enter, 0.0), t1 - t_enter, depth);
  else
    sf_baseline_depth(b, r, mu, t0, t1, depth);
  sf_transmittance_from_depth(atm, depth, transmittance);
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

void sf_emit_constituent_density(sf_code_writer *w, const sf_constituent *c) {
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
    sf_emit_constituent_density(w, &atm->constituents[i]);
    sf_cw_emit(w, ";\n");
  }
  sf_cw_emit(w, "      k += 1.0f;\n    }\n");
  for (int i = 0; i < atm->n_constituents; ++i) sf_cw_emit(w, "    d%d *= dt;\n", i);
  sf_cw_need(w, SF_HELPER_ALTITUDE_AT);
}

/* The segment's ends as signed distances s from the line's closest
 * approach, the line itself, and the segment's shape (models/air_segment.c). */
static void emit_segment_ends(sf_code_writer *w, const sf_atmosphere *atm, int with_closest) {
  double bottom = atm->bottom_radius_km;
  sf_cw_emit(w,
             "    float r = %F + h_km;\n"
             "    float s0 = seg.x + r * mu, s1 = seg.y + r * mu;\n"
             "    /* the line's closest approach d and d^2 - bottom^2 = h (r + bottom) - (r mu)^2 */\n",
             bottom);
  if (with_closest) sf_cw_emit(w, "    float d = r * @sqrt((1.0f - mu) * (1.0f + mu));\n");
  sf_cw_emit(w,
             "    float dd_bb = h_km * (r + %F) - (r * mu) * (r * mu);\n"
             "    int shape = s0 >= 0.0f ? 0 : (s1 <= 0.0f ? 1 : 2);\n",
             bottom);
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

void sf_emit_chapman_columns(sf_code_writer *w, const sf_atmosphere *atm) {
  emit_segment_ends(w, atm, 1);
  sf_cw_emit(w,
             "    float h0 = seg.z, h1 = seg.w;\n"
             "    float r0 = %F + h0, r1 = %F + h1;\n"
             "    float c0 = @min(@max(s0 / r0, -1.0f), 1.0f);\n"
             "    float c1 = @min(@max(s1 / r1, -1.0f), 1.0f);\n"
             "    float hc = dd_bb / (d + %F);\n"
             "    /* h1 - h0 and c1 - c0 from the ends' distances s (r^2 = d^2 + s^2) */\n"
             "    float ds = seg.y - seg.x;\n"
             "    float dh01 = ds * (s1 + s0) / (r1 + r0);\n"
             "    float dc01 = (ds * r0 - s0 * dh01) / (r0 * r1);\n",
             atm->bottom_radius_km, atm->bottom_radius_km, atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!is_exponential(&atm->constituents[i], &H, &d0)) continue;
    /* seed 000 eq. 24: rising, falling (reversed), through the closest
     * point; each piece as skyfit_chapman_diff, the difference of the two
     * ends' eq. 25 values without cancellation (a short segment's depth is
     * a tiny difference of two large values). */
    sf_cw_emit(w,
               "    {  /* %s */\n"
               "      float H = %F;\n"
               "      float tau = shape == 0 ? skyfit_chapman_diff(H, h0, r0, c0, dh01, dc01)\n"
               "                : shape == 1 ? skyfit_chapman_diff(H, h1, r1, -c1, -dh01, dc01)\n"
               "                : skyfit_chapman_diff(H, hc, d, 0.0f, s0 * s0 / (r0 + d), -s0 / r0)\n"
               "                  + skyfit_chapman_diff(H, hc, d, 0.0f, s1 * s1 / (r1 + d), s1 / r1);\n"
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
  emit_segment_ends(w, atm, 1);
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
               "      float tau_h = shape == 0 ? skyfit_taylor_piece(line, d, %F, H, u0, u1, seg.y - seg.x)\n"
               "                  : shape == 1 ? skyfit_taylor_piece(line, d, %F, H, u1, u0, seg.y - seg.x)\n"
               "                  : skyfit_taylor_piece(line, d, %F, H, t_min, u0, u0 - t_min)\n"
               "                    + skyfit_taylor_piece(line, d, %F, H, t_min, u1, u1 - t_min);\n"
               "      d%d = @min(%F * tau_h, 3.4e38f);\n"
               "    }\n",
               atm->constituents[i].name, H, bottom, bottom, bottom, bottom, i, d0);
  }
  sf_cw_need(w, SF_HELPER_TAYLOR_PIECE);
  emit_shells(w, atm);
}


/* The flat model's pieces in float32 (seed 000 eq. 51), each in units of
 * d0 = 1, emitted with the flat baseline behind their own guard. A point
 * is (altitude h, radius r, signed distance s = t + r mu from the line's
 * closest approach); eq. 51's r cos is s, A = (r + H)^2 - r^2 = H (2 r + H).
 * Differences between two points of one segment are formed from the exact
 * differences dh (= dr) and ds, so a short segment keeps its float32
 * precision instead of being a tiny difference of two columns:
 *   g = sqrt(A + s^2) - s = A / (q + s),
 *   g_a - g_b = (ds (g_a + g_b) - 2 H dh) / (q_a + q_b),  b = a + (dh, dh, ds). */
void sf_emit_flat_helpers(sf_code_writer *w) {
  sf_cw_emit(w,
      "#ifndef SKYFIT_HELPER_FLAT\n#define SKYFIT_HELPER_FLAT\n"
      "/* seed 000 eq. 51: the column of exp(-h/H) from (h, r) along s >= 0,\n"
      " * exp(-h/H) A / (sqrt(A + s^2) + s), A = H (2 r + H). */\n"
      "@fn float skyfit_flat_up(float H, float h, float r, float s) {\n"
      "  float A = H * (2.0f * r + H);\n"
      "  return @exp(-h / H) * A / (@sqrt(A + s * s) + s);\n"
      "}\n"
      "/* skyfit_flat_up(a) - skyfit_flat_up(b), b = a + (dh, dh, ds), both s >= 0. */\n"
      "@fn float skyfit_flat_up_diff(float H, float h_a, float r_a, float s_a, float dh, float ds) {\n"
      "  float r_b = r_a + dh, s_b = s_a + ds;\n"
      "  float A_a = H * (2.0f * r_a + H), A_b = H * (2.0f * r_b + H);\n"
      "  float q_a = @sqrt(A_a + s_a * s_a), q_b = @sqrt(A_b + s_b * s_b);\n"
      "  float g_a = A_a / (q_a + s_a), g_b = A_b / (q_b + s_b);\n"
      "  float dg = (ds * (g_a + g_b) - 2.0f * H * dh) / (q_a + q_b);\n"
      "  return @exp(-h_a / H) * (dg - g_b * skyfit_expm1(-dh / H));\n"
      "}\n"
      "#endif\n\n");
  sf_cw_need(w, SF_HELPER_EXPM1);
}

void sf_emit_flat_columns_closest(sf_code_writer *w, const sf_atmosphere *atm) {
  if (sf_atmosphere_exponential_count(atm) == 0) {   /* shells only: nothing reads the ends' geometry */
    emit_shells(w, atm);
    return;
  }
  emit_segment_ends(w, atm, 1);
  sf_cw_emit(w,
             "    float h0 = seg.z, h1 = seg.w;\n"
             "    float r0 = %F + h0, r1 = %F + h1;\n"
             "    float hc = dd_bb / (d + %F);  /* the closest approach's altitude */\n"
             "    /* h1 - h0 from the ends' distances s (r^2 = d^2 + s^2) */\n"
             "    float ds = seg.y - seg.x;\n"
             "    float dh01 = ds * (s1 + s0) / (r1 + r0);\n",
             atm->bottom_radius_km, atm->bottom_radius_km, atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!is_exponential(&atm->constituents[i], &H, &d0)) continue;
    /* rising: eq. 51 at both ends; falling: reversed, the lower end as
     * midpoint (§11.3.3); through the closest point c: eq. 53 about c,
     * 2 up(c, 0) - up(0 reversed) - up(1), as the two differences from c
     * (models/optical_depth_flat.c, descent CLOSEST; c to an end: dh =
     * r - d = s^2 / (r + d)) */
    sf_cw_emit(w,
               "    {  /* %s */\n"
               "      float H = %F;\n"
               "      float tau = shape == 0 ? skyfit_flat_up_diff(H, h0, r0, s0, dh01, ds)\n"
               "                : shape == 1 ? skyfit_flat_up_diff(H, h1, r1, -s1, -dh01, ds)\n"
               "                : skyfit_flat_up_diff(H, hc, d, 0.0f, s0 * s0 / (r0 + d), -s0)\n"
               "                  + skyfit_flat_up_diff(H, hc, d, 0.0f, s1 * s1 / (r1 + d), s1);\n"
               "      d%d = tau > 0.0f ? %F * tau : 0.0f;\n"
               "    }\n",
               atm->constituents[i].name, H, i, d0);
  }
  emit_shells(w, atm);
}

static void emit_spline_depths(sf_code_writer *w, const sf_baseline *b) {
  emit_segment_ends(w, b->atmosphere, 1);
  sf_emit_spline_depths(w, b->atmosphere, b->spline);
  emit_shells(w, b->atmosphere);
}

void sf_emit_baseline(sf_code_writer *w, const sf_baseline *b) {
  const sf_atmosphere *atm = b->atmosphere;
  const char *name = sf_baseline_kind_name(b->kind);
  int n = atm->n_channels;
  char description[256];
  sf_baseline_describe(b, description, sizeof description);
  if (b->kind == SF_BASELINE_FLAT) sf_emit_flat_helpers(w);
  if (b->kind == SF_BASELINE_SPLINE) sf_emit_spline_tables(w, b->spline);
  sf_cw_emit(w, "/* %s: %s. */\n", name, description);
  sf_cw_emit(w, "@fn %V skyfit_%s_transmittance_between(float h_km, float mu, float t0, float t1) {\n", n, name);
  /* A viewer above the top starts where its ray enters (the same ray):
   * from far out, every distance and altitude along the ray would be a
   * small difference of two values of order r^2 (a float32 viewer 1e6 km
   * away lost the ground by kilometres). The flat model too, as seed 000
   * moves its networks' viewers (§9.6): when it took eq. 53 at the viewer,
   * from a viewer far above the top, where exp(-h/H) is 0, it had given
   * T = 1 for a column of 8 (seed 000 §12.1.3's failure). */
  char ones[64] = "";
  for (int ch = 0; ch < n; ++ch) strcat(ones, ch ? ", 1.0f" : "1.0f");
  /* A float32 altitude at the ground, length(p) - R, is often -1e-4 km: a
   * viewer there is on the ground (the sigmoid's header clamps it too),
   * not inside the planet, whose far side's air a downward ray had
   * crossed (T 0.89 for a ray into the ground, 0.18 at mu -0.01). */
  sf_cw_emit(w, "  h_km = @max(h_km, 0.0f);\n");
  sf_cw_emit(w,
             "  @vec4 e = skyfit_ray_enter(%F, %F, h_km, mu, 0.0f, 0.0f);\n"
             "  if (e.w < 0.0f || !(t1 > e.w)) return %C%s);\n"
             "  if (e.w > 0.0f) {\n"
             "    h_km = e.x;\n"
             "    mu = e.y;\n"
             "    t0 = @max(t0 - e.w, 0.0f);\n"
             "    t1 = t1 - e.w;\n"
             "  }\n",
             atm->bottom_radius_km, atm->top_radius_km - atm->bottom_radius_km, n, ones);
  sf_cw_need(w, SF_HELPER_RAY_ENTER);
  sf_cw_emit(w, "  @vec4 seg = skyfit_air_clip(%F, %F, h_km, mu, t0, t1);\n", atm->bottom_radius_km,
             atm->top_radius_km - atm->bottom_radius_km);
  sf_cw_need(w, SF_HELPER_AIR_CLIP);
  for (int i = 0; i < atm->n_constituents; ++i)
    sf_cw_emit(w, "  float d%d = 0.0f;  /* %s, km */\n", i, atm->constituents[i].name);
  sf_cw_emit(w, "  if (seg.y > seg.x) {\n");
  if (b->kind == SF_BASELINE_NAIVE) emit_naive_depths(w, b);
  else if (b->kind == SF_BASELINE_CHAPMAN) sf_emit_chapman_columns(w, atm);
  else if (b->kind == SF_BASELINE_FLAT) sf_emit_flat_columns_closest(w, atm);
  else if (b->kind == SF_BASELINE_SPLINE) emit_spline_depths(w, b);
  else emit_taylor_depths(w, b);
  sf_cw_emit(w, "  }\n");
  /* A constituent that neither scatters nor absorbs is in no channel's
   * sum: its column, set above, would be unread (C's -Wall -Werror had
   * refused the header); GLSL has no such warning, nor (void). */
  for (int i = 0; w->lang == SF_CODE_C && i < atm->n_constituents; ++i)
    if (!sf_emit_sky_dims_any(atm, i))
      sf_cw_emit(w, "  (void)d%d;  /* %s: no extinction */\n", i, atm->constituents[i].name);
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

typedef struct baseline_error {
  const sf_baseline *baseline;
  double sum_sq, worst;
  long count;
} baseline_error;

/* One full ray against the reference; in_rmse 0: the maximum only. */
static void baseline_error_at(baseline_error *e, double h, double mu, int in_rmse) {
  const sf_atmosphere *atm = e->baseline->atmosphere;
  double depth[SF_MAX_CONSTITUENTS], want[SF_MAX_CHANNELS], got[SF_MAX_CHANNELS];
  sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
  sf_transmittance_from_depth(atm, depth, want);
  sf_baseline_transmittance(e->baseline, h, mu, 0.0, INFINITY, got);
  for (int ch = 0; ch < atm->n_channels; ++ch) {
    double d = fabs(got[ch] - want[ch]);
    if (in_rmse) {
      e->sum_sq += d * d;
      ++e->count;
    }
    if (d > e->worst) e->worst = d;
  }
}

static void tangent_visit(void *ctx, double h, double mu) { baseline_error_at(ctx, h, mu, 0); }

void sf_baseline_measure(const sf_baseline *b, const sf_scene_domain *domain, double *rmse,
                         double *max_abs) {
  const sf_atmosphere *atm = b->atmosphere;
  enum { NH = 64, NMU = 384 };
  baseline_error e = {b, 0.0, 0.0, 0};
  for (int i = 0; i < NH; ++i) {
    double h = domain->h_min_km + (domain->h_max_km - domain->h_min_km) * i / (NH - 1);
    for (int j = 0; j < NMU; ++j)
      baseline_error_at(&e, h, domain->mu_min + (domain->mu_max - domain->mu_min) * j / (NMU - 1), 1);
  }
  /* The rays grazing the ground and the boundaries of the shells that
   * stand for non-exponential constituents, where these models err most
   * or jump, enter the maximum. */
  sf_tangent_sweep(atm->bottom_radius_km, 0.0, domain->h_min_km, domain->h_max_km, domain->mu_min,
                   domain->mu_max, tangent_visit, &e);
  for (int c = 0; c < atm->n_constituents; ++c) {
    double H, d0, shell[2];
    if (sf_constituent_exponential(&atm->constituents[c], &H, &d0)) continue;
    sf_flat_shell_of(atm, c, &shell[0], &shell[1]);
    for (int k = 0; k < 2; ++k)
      if (shell[k] > 0.0)
        sf_tangent_sweep(atm->bottom_radius_km, shell[k], domain->h_min_km, domain->h_max_km, domain->mu_min,
                         domain->mu_max, tangent_visit, &e);
  }
  *rmse = e.count ? sqrt(e.sum_sq / e.count) : 0.0;
  *max_abs = e.worst;
}
