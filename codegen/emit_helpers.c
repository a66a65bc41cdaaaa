#include "codegen/emit_helpers.h"

unsigned sf_helpers_closure(unsigned needed) {
  if (needed & (SF_HELPER_TAYLOR_PIECE | SF_HELPER_CHAPMAN_UP)) needed |= SF_HELPER_EXPM1;
  if (needed & SF_HELPER_SHELL_CHORD) needed |= SF_HELPER_SPHERE_HITS;
  if (needed & SF_HELPER_AIR_CLIP) needed |= SF_HELPER_SPHERE_HITS | SF_HELPER_ALTITUDE_AT;
  if (needed & SF_HELPER_RAY_ENTER) needed |= SF_HELPER_SPHERE_HITS;
  return needed;
}

static void guard_open(sf_code_writer *w, const char *name) {
  sf_cw_emit(w, "#ifndef SKYFIT_HELPER_%s\n#define SKYFIT_HELPER_%s\n", name, name);
}

static void guard_close(sf_code_writer *w) { sf_cw_emit(w, "#endif\n\n"); }

static void sphere_hits(sf_code_writer *w) {
  guard_open(w, "SPHERE_HITS");
  sf_cw_emit(w,
      "/* Distances (near, far) along the ray (r, mu) to the sphere of radius R;\n"
      " * near > far when the line misses it. R_minus_r is passed separately\n"
      " * (from altitudes, exact) because in float32 R - r loses the viewer's\n"
      " * altitude near the sphere. Discriminant (R - r)(R + r) + (r mu)^2, small\n"
      " * root c / q (SPEC §10; models/ray_geometry_impl.inc). */\n"
      "@fn @vec2 skyfit_sphere_hits(float r, float mu, float R, float R_minus_r) {\n"
      "  float disc = R_minus_r * (R + r) + (r * mu) * (r * mu);\n"
      "  if (disc < 0.0f) return @vec2(1.0f, -1.0f);\n"
      "  float root = @sqrt(disc);\n"
      "  float q = -(r * mu + (mu >= 0.0f ? root : -root));\n"
      "  float b = q != 0.0f ? -R_minus_r * (r + R) / q : 0.0f;\n"
      "  return q < b ? @vec2(q, b) : @vec2(b, q);\n"
      "}\n");
  guard_close(w);
}

static void air_clip(sf_code_writer *w) {
  guard_open(w, "AIR_CLIP");
  sf_cw_emit(w,
      "/* [t0, t1] along the ray from altitude h (above the sphere `bottom`)\n"
      " * with zenith cosine mu, restricted to the air: inside the top sphere\n"
      " * (altitude `thickness`) and before the ground (models/air_segment.c).\n"
      " * Returns (a, b, altitude at a, altitude at b); empty: b <= a. An end on\n"
      " * the top or the ground gets that altitude exactly. */\n"
      "@fn @vec4 skyfit_air_clip(float bottom, float thickness, float h, float mu, float t0, float t1) {\n"
      "  float r = bottom + h;\n"
      "  @vec2 s = skyfit_sphere_hits(r, mu, bottom + thickness, thickness - h);\n"
      "  if (!(t1 > t0) || s.x > s.y) return @vec4(t0, t0, h, h);\n"
      "  float a = t0, b = t1, ha = -1.0f, hb = -1.0f;\n"
      "  if (s.x > a) { a = s.x; ha = thickness; }\n"
      "  if (s.y < b) { b = s.y; hb = thickness; }\n"
      "  @vec2 g = skyfit_sphere_hits(r, mu, bottom, -h);\n"
      "  if (g.x < g.y) {\n"
      "    if (a <= g.x) {\n"
      "      if (g.x < b) { b = g.x; hb = 0.0f; }\n"
      "    } else if (a < g.y) {\n"
      "      a = g.y;\n"
      "      ha = 0.0f;\n"
      "    }\n"
      "  }\n"
      "  if (!(b > a)) return @vec4(a, a, h, h);\n"
      "  if (ha < 0.0f) ha = skyfit_altitude_at(bottom, h, mu, a);\n"
      "  if (hb < 0.0f) hb = skyfit_altitude_at(bottom, h, mu, b);\n"
      "  return @vec4(a, b, ha, hb);\n"
      "}\n");
  guard_close(w);
}

static void altitude_at(sf_code_writer *w) {
  guard_open(w, "ALTITUDE_AT");
  sf_cw_emit(w,
      "/* Altitude at distance t along the ray from altitude h (radius\n"
      " * bottom + h) with zenith cosine mu, as (h (r + bottom) + t (t + 2 r mu))\n"
      " * / (radius + bottom): no cancellation against the planet radius. */\n"
      "@fn float skyfit_altitude_at(float bottom, float h, float mu, float t) {\n"
      "  float r = bottom + h;\n"
      "  float along = t * (t + 2.0f * r * mu);\n"
      "  float r2 = r * r + along;\n"
      "  float radius = r2 > 0.0f ? @sqrt(r2) : 0.0f;\n"
      "  return (h * (r + bottom) + along) / (radius + bottom);\n"
      "}\n");
  guard_close(w);
}

static void shell_chord(sf_code_writer *w) {
  guard_open(w, "SHELL_CHORD");
  sf_cw_emit(w,
      "/* Length of [t0, t1] along the ray from altitude h between the\n"
      " * altitudes lo < hi (seed 000 §10.5, eq. 59: a shell of density 1). */\n"
      "@fn float skyfit_shell_chord(float bottom, float lo, float hi, float h, float mu, float t0, float t1) {\n"
      "  float r = bottom + h;\n"
      "  @vec2 outer = skyfit_sphere_hits(r, mu, bottom + hi, hi - h);\n"
      "  @vec2 inner = skyfit_sphere_hits(r, mu, bottom + lo, lo - h);\n"
      "  float a = @max(t0, outer.x), b = @min(t1, outer.y);\n"
      "  float chord = outer.x <= outer.y && b > a ? b - a : 0.0f;\n"
      "  a = @max(t0, inner.x);\n"
      "  b = @min(t1, inner.y);\n"
      "  if (inner.x <= inner.y && b > a) chord -= b - a;\n"
      "  return chord > 0.0f ? chord : 0.0f;\n"
      "}\n");
  guard_close(w);
}

static void expm1_helper(sf_code_writer *w) {
  guard_open(w, "EXPM1");
  sf_cw_emit(w,
      "/* exp(x) - 1 without cancellation near 0 (GLSL has no expm1): a\n"
      " * degree-6 Taylor polynomial below |x| = 0.1 (relative error < 3e-10),\n"
      " * exp(x) - 1 above (relative error < 2 ulp / 0.1). */\n"
      "@fn float skyfit_expm1(float x) {\n"
      "  if (@abs(x) < 0.1f)\n"
      "    return x * (1.0f + x * (0.5f + x * (%F + x * (%F + x * (%F + x * %F)))));\n"
      "  return @exp(x) - 1.0f;\n"
      "}\n",
      1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0);
  guard_close(w);
}

static void chapman_diff(sf_code_writer *w) {
  guard_open(w, "CHAPMAN_DIFF");
  sf_cw_emit(w,
      "/* seed 000 eq. 24-25 (Schuler 2012): tau_Ch(a) - tau_Ch(b), in units of H,\n"
      " * where tau_Ch of exp(-h/H) from the point at altitude h, radius r, along\n"
      " * upward zenith cosine c to infinity is exp(-h/H) C / (1 + C c), C = sqrt(r/H);\n"
      " * a = (h_a, r_a, c_a), b = a + (dh, dh, dc). Written as\n"
      " * exp(-h_a/H) [(g_a - g_b) - g_b expm1(-dh/H)], g = C / (1 + C c), with\n"
      " * g_a - g_b = (C_a C_b dc - dh / (H (C_a + C_b))) / ((1 + C_a c_a)(1 + C_b c_b)):\n"
      " * no difference of nearly equal values, so a short segment keeps its\n"
      " * float32 precision. */\n"
      "@fn float skyfit_chapman_diff(float H, float h_a, float r_a, float c_a, float dh, float dc) {\n"
      "  float C_a = @sqrt(r_a / H), C_b = @sqrt((r_a + dh) / H);\n"
      "  float den_a = 1.0f + C_a * c_a, den_b = 1.0f + C_b * (c_a + dc);\n"
      "  float dg = (C_a * C_b * dc - dh / (H * (C_a + C_b))) / (den_a * den_b);\n"
      "  return @exp(-h_a / H) * (dg - C_b / den_b * skyfit_expm1(-dh / H));\n"
      "}\n");
  guard_close(w);
}

static void taylor_piece(sf_code_writer *w) {
  guard_open(w, "TAYLOR_PIECE");
  sf_cw_emit(w,
      "/* seed 002 eq. 17 between distances u_lo <= u_hi from the line's closest\n"
      " * approach: H / h' exp(-h~(u_lo)/H) (1 - exp(-rise/H)), with h~ the\n"
      " * expansion of the altitude of order 1 + a about tau_b. line = (tau_b,\n"
      " * h(tau_b), h'(tau_b), a h''(tau_b) / 2); d = the line's distance from\n"
      " * the centre; len = u_hi - u_lo, passed apart because u = |t + r mu| of a\n"
      " * short segment far from the closest approach loses it in float32 (a\n"
      " * 1e-4 km segment at u ~ 3000 km). A piece that would overflow float32 is the exact bound\n"
      " * length * density at u_lo where the double one overflows too (exponent\n"
      " * past 709.78), else the largest float (its transmittance is 0 either\n"
      " * way). */\n"
      "@fn float skyfit_taylor_piece(@vec4 line, float d, float bottom, float H, float u_lo, float u_hi, float len) {\n"
      "  if (!(len > 0.0f)) return 0.0f;\n"
      "  if (!(line.z > 0.0f)) return len * @exp(-line.y / H);\n"
      "  float x = u_lo - line.x;\n"
      "  float h_lo = (line.w * x + line.z) * x + line.y;\n"
      "  float rise = len * (line.z + line.w * (u_lo + u_hi - 2.0f * line.x));\n"
      "  float ratio = H / line.z, f = -skyfit_expm1(-rise / H);\n"
      "  float e = -h_lo / H;\n"
      "  if (e > 80.0f) {\n"
      "    /* as the double reference: (H / h') exp(e) first, then times f */\n"
      "    float log_first = e + @log(ratio), log_piece = log_first + @log(f);\n"
      "    if (log_first > 709.78f || log_piece > 709.78f) {\n"
      "      float h_true = ((d - bottom) * (d + bottom) + u_lo * u_lo) / (@sqrt(d * d + u_lo * u_lo) + bottom);\n"
      "      return len * @exp(-h_true / H);\n"
      "    }\n"
      "    if (log_piece > 88.0f) return 3.4e38f;\n"
      "    return @exp(log_piece);\n"
      "  }\n"
      "  float piece = ratio * @exp(e) * f;\n"
      "  return piece > 0.0f ? piece : 0.0f;\n"
      "}\n");
  guard_close(w);
}

static void ray_enter(sf_code_writer *w) {
  guard_open(w, "RAY_ENTER");
  sf_cw_emit(w,
      "/* A viewer above the top of the atmosphere (altitude h_top above the\n"
      " * sphere R) moved to where its ray enters it (seed 000 §9.6.3): returns\n"
      " * (h, mu, mu_s, distance travelled); the distance is -1 when the ray\n"
      " * never enters (a ray that only touches the top has no path inside).\n"
      " * Viewers inside are returned as they are. The top's R_t - r comes from\n"
      " * altitudes (h_top - h), exact where r would cancel (SPEC §10). Far out\n"
      " * (r > 2 R_t) the discriminant R_t^2 - r^2 (1 - mu^2) is taken from the\n"
      " * ray's closest approach p as (R_t - p)(R_t + p): (R_t - r)(R_t + r) +\n"
      " * (r mu)^2, two terms of about r^2, cancels (a viewer 1e7 km away looking\n"
      " * straight down missed the planet). The entry cosine r mu + t =\n"
      " * -sqrt(disc) has no cancellation either (models/ray_geometry_impl.inc). */\n"
      "@fn @vec4 skyfit_ray_enter(float R, float h_top, float h, float mu, float mu_s, float nu) {\n"
      "  if (h <= h_top) return @vec4(h, mu, mu_s, 0.0f);\n"
      "  float r = R + h, Rt = R + h_top;\n"
      "  float disc;\n"
      "  if (r > 2.0f * Rt) {\n"
      "    float p = r * @sqrt(@max((1.0f - mu) * (1.0f + mu), 0.0f));\n"
      "    disc = (Rt - p) * (Rt + p);\n"
      "  } else {\n"
      "    disc = (h_top - h) * (Rt + r) + (r * mu) * (r * mu);\n"
      "  }\n"
      "  if (!(mu < 0.0f) || !(disc > 0.0f)) return @vec4(h, mu, mu_s, -1.0f);\n"
      "  float root = @sqrt(disc);\n"
      "  float t = (h - h_top) * ((r + Rt) / (root - r * mu));  /* the near root, c / q */\n"
      "  float m = -root / Rt, ms = (r * (mu_s - mu * nu) - root * nu) / Rt;\n"
      "  return @vec4(h_top, @min(@max(m, -1.0f), 1.0f), @min(@max(ms, -1.0f), 1.0f), t);\n"
      "}\n");
  guard_close(w);
}

static void asin_acos(sf_code_writer *w) {
  guard_open(w, "ASIN_ACOS");
  sf_cw_emit(w,
      "/* asin and acos to ~1e-7, the same arithmetic in C and GLSL (GLSL's own\n"
      " * asin/acos may be far less precise: Mesa's are ~1e-4). Cephes asinf:\n"
      " * a polynomial below |x| = 0.5, 2 asin(sqrt((1 - |x|) / 2)) above. */\n"
      "@fn float skyfit_asin_poly(float z) {\n"
      "  return (((%F * z + %F) * z + %F) * z + %F) * z + %F;\n"
      "}\n"
      "@fn float skyfit_asin(float x) {\n"
      "  float a = @min(@abs(x), 1.0f), r;\n"
      "  if (a > 0.5f) {\n"
      "    float z = 0.5f * (1.0f - a), s = @sqrt(z);\n"
      "    r = %F - 2.0f * (s + s * z * skyfit_asin_poly(z));\n"
      "  } else {\n"
      "    float z = a * a;\n"
      "    r = a + a * z * skyfit_asin_poly(z);\n"
      "  }\n"
      "  return x < 0.0f ? -r : r;\n"
      "}\n"
      "@fn float skyfit_acos(float x) {\n"
      "  float c = @min(@max(x, -1.0f), 1.0f);\n"
      "  if (c > 0.5f) {\n"
      "    float z = 0.5f * (1.0f - c), s = @sqrt(z);\n"
      "    return 2.0f * (s + s * z * skyfit_asin_poly(z));\n"
      "  }\n"
      "  return %F - skyfit_asin(c);\n"
      "}\n",
      4.2163199048e-2, 2.4181311049e-2, 4.5470025998e-2, 7.4953002686e-2, 1.6666752422e-1,
      1.5707963267948966, 1.5707963267948966);
  guard_close(w);
}

static void radius_at(sf_code_writer *w) {
  guard_open(w, "RADIUS_AT");
  sf_cw_emit(w,
      "/* Radius at distance t along the ray (r, mu), never negative. */\n"
      "@fn float skyfit_radius_at(float r, float mu, float t) {\n"
      "  float r2 = r * r + t * (t + 2.0f * r * mu);\n"
      "  return r2 > 0.0f ? @sqrt(r2) : 0.0f;\n"
      "}\n");
  guard_close(w);
}

static void clamp_nu(sf_code_writer *w) {
  guard_open(w, "CLAMP_NU");
  sf_cw_emit(w,
      "/* nu clamped into the range mu and mu_s allow (SPEC §3). */\n"
      "@fn float skyfit_clamp_nu(float mu, float mu_s, float nu) {\n"
      "  float spread = @sqrt(@max(0.0f, (1.0f - mu * mu) * (1.0f - mu_s * mu_s)));\n"
      "  return @min(@max(nu, mu * mu_s - spread), mu * mu_s + spread);\n"
      "}\n");
  guard_close(w);
}

void sf_emit_helpers(sf_code_writer *w, unsigned needed) {
  needed = sf_helpers_closure(needed);
  if (needed & SF_HELPER_SPHERE_HITS) sphere_hits(w);
  if (needed & SF_HELPER_ALTITUDE_AT) altitude_at(w);
  if (needed & SF_HELPER_AIR_CLIP) air_clip(w);
  if (needed & SF_HELPER_SHELL_CHORD) shell_chord(w);
  if (needed & SF_HELPER_EXPM1) expm1_helper(w);
  if (needed & SF_HELPER_CHAPMAN_UP) chapman_diff(w);
  if (needed & SF_HELPER_TAYLOR_PIECE) taylor_piece(w);
  if (needed & SF_HELPER_ASIN_ACOS) asin_acos(w);
  if (needed & SF_HELPER_RAY_ENTER) ray_enter(w);
  if (needed & SF_HELPER_RADIUS_AT) radius_at(w);
  if (needed & SF_HELPER_CLAMP_NU) clamp_nu(w);
}
