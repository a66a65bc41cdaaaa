#include "codegen/emit_sky_raymarched.h"

#include <stddef.h>

#include "codegen/baselines.h"
#include "codegen/emit_sky_frame.h"
#include "models/atmosphere_file.h"

static const char *const component[4] = {"x", "y", "z", "w"};

int sf_sky_raymarched_emittable(const sf_sky_raymarched *m, const char **why) {
  const sf_atmosphere *atm = m->atm;
  if (atm->n_channels > 4) *why = "emitted code returns vec1-vec4: at most 4 channels";
  else if (atm->n_constituents > 4) *why = "its columns travel in a vec4: at most 4 constituents";
  else if (m->depths != SF_RAYMARCHED_DEPTHS_FLAT) *why = "only the flat model's depths are emitted";
  else if (m->steps < 1) *why = "steps must be >= 1";
  else return 1;
  return 0;
}

/* skyfit_raymarched_line_columns: the flat model's column (km) of every
 * constituent over the piece seg (as skyfit_air_clip gives it) of the line
 * (h_km, mu), in a vec4; skyfit_raymarched_columns: over [t0, t1] of the
 * ray; skyfit_raymarched_sun_columns: from altitude h along the sun's
 * cosine c to the top, along the line, the planet ignored, c raised to the
 * horizon's where the planet hides the sun (the grazing ray, continuous
 * across the shadow's edge: models/sky_raymarched.c). */
static void emit_columns(sf_code_writer *w, const sf_atmosphere *atm) {
  const double R = atm->bottom_radius_km, H = atm->top_radius_km - atm->bottom_radius_km;
  /* Guarded so the flat and the raymarched sky of one atmosphere share
   * them; the guard names the atmosphere (its hash), these functions
   * holding its numbers: two headers of two atmospheres (one prefix) fail
   * to compile on the names, as other clashing headers do, where one
   * guard had left the second's sky on the first's air, silently. */
  char hash[17];
  sf_atmosphere_hash_hex(atm, hash);
  sf_cw_emit(w, "#ifndef SKYFIT_HELPER_RAYMARCHED_COLUMNS_%s\n#define SKYFIT_HELPER_RAYMARCHED_COLUMNS_%s\n"
                "@fn @vec4 skyfit_raymarched_line_columns(float h_km, float mu, @vec4 seg) {\n",
             hash, hash);
  for (int i = 0; i < atm->n_constituents; ++i)
    sf_cw_emit(w, "  float d%d = 0.0f;  /* %s, km */\n", i, atm->constituents[i].name);
  sf_cw_emit(w, "  if (seg.y > seg.x) {\n");
  sf_emit_flat_columns_closest(w, atm);
  sf_cw_emit(w, "  }\n  return @vec4(");
  for (int i = 0; i < 4; ++i) {
    if (i < atm->n_constituents) sf_cw_emit(w, i ? ", d%d" : "d%d", i);
    else sf_cw_emit(w, ", 0.0f");
  }
  sf_cw_emit(w,
             ");\n}\n\n"
             "@fn @vec4 skyfit_raymarched_columns(float h_km, float mu, float t0, float t1) {\n"
             "  return skyfit_raymarched_line_columns(h_km, mu, skyfit_air_clip(%F, %F, h_km, mu, t0, t1));\n"
             "}\n\n"
             "@fn @vec4 skyfit_raymarched_sun_columns(float h, float c) {\n"
             "  float rp = %F + h;\n"
             "  c = @max(c, -@sqrt(@max(h, 0.0f) * (rp + %F)) / rp);\n"
             "  float t_top = @max(skyfit_sphere_hits(rp, c, %F, %F - h).y, 0.0f);\n"
             "  return skyfit_raymarched_line_columns(h, c, @vec4(0.0f, t_top, h, %F));\n"
             "}\n#endif\n\n",
             R, H, R, R, R + H, H, H);
  sf_cw_need(w, SF_HELPER_AIR_CLIP | SF_HELPER_SPHERE_HITS);
}

static void emit_exp_mean(sf_code_writer *w) {
  sf_cw_emit(w,
             "#ifndef SKYFIT_HELPER_EXP_MEAN\n#define SKYFIT_HELPER_EXP_MEAN\n"
             "/* (e^-a - e^-b) / (b - a), the mean of e^-x over [a, b] (seed 000 eq. 47),\n"
             " * without the quotient's cancellation where a and b meet. */\n"
             "@fn float skyfit_exp_mean(float a, float b) {\n"
             "  float d = @abs(b - a);\n"
             "  return @exp(-@min(a, b)) * (d > 0.0f ? -skyfit_expm1(-d) / d : 1.0f);\n"
             "}\n#endif\n\n");
  sf_cw_need(w, SF_HELPER_EXPM1);
}

/* float <prefix><k> = sum_i extinction_i,k (v<i> + <sun>.<i>) per channel. */
static void emit_depths(sf_code_writer *w, const sf_atmosphere *atm, const char *indent, const char *prefix,
                        const char *sun) {
  for (int k = 0; k < atm->n_channels; ++k) {
    sf_cw_emit(w, "%s%s%d = 0.0f", indent, prefix, k);
    for (int i = 0; i < atm->n_constituents; ++i) {
      double e = sf_extinction(atm, i, k);
      if (e != 0.0) sf_cw_emit(w, " + %F * (v%d + %s.%s)", e, i, sun, component[i]);
    }
    sf_cw_emit(w, ";\n");
  }
}

void sf_emit_sky_raymarched(sf_code_writer *w, const sf_sky_raymarched *m, const char *name) {
  const sf_atmosphere *atm = m->atm;
  const int nc = atm->n_constituents, nk = atm->n_channels;
  const double R = atm->bottom_radius_km;
  sf_emit_flat_helpers(w);
  emit_exp_mean(w);
  emit_columns(w, atm);
  sf_cw_emit(w,
             "/* %s sky: single scattering in %d equal step(s) of the view ray, split where the\n"
             " * sun ray grazes the ground or passes closest to it, each integrated in closed form with\n"
             " * the flat model's optical depths; no multiple scattering (seed 000 %s). */\n",
             name, m->steps, m->steps == 1 ? "§10.1-10.4, §11.2.9, eq. 52, 55" : "§10.4, §11.2.10, eq. 55");
  sf_emit_sky_open(w, atm, name);
  /* models/sun_shadow.h: the sun ray from distance t passes the centre at
   * d, d^2 - R^2 = qa t^2 + qb t + qc, ahead of the point where rms + t nu < 0 */
  sf_cw_emit(w,
             "  float rms = r * ms;\n"
             "  float qa = (1.0f - nu) * (1.0f + nu), qb = 2.0f * r * (m - ms * nu);\n"
             "  float qc = hv * (r + %F) - rms * rms;\n"
             "  /* the shadow's edges inside the stretch, in order (3.4e38: none) */\n"
             "  float u0 = 3.4e38f, u1 = 3.4e38f;\n"
             "  float disc = qb * qb - 4.0f * qa * qc;\n"
             "  if (qa > 0.0f && disc >= 0.0f) {\n"
             "    float q = -0.5f * (qb + (qb >= 0.0f ? @sqrt(disc) : -@sqrt(disc)));\n"
             "    u0 = q / qa;\n"
             "    if (q != 0.0f) u1 = qc / q;\n"
             "  } else if (qa == 0.0f && qb != 0.0f) {\n"
             "    u0 = -qc / qb;\n"
             "  }\n"
             "  if (!(u0 > seg.x && u0 < seg.y && rms + u0 * nu < 0.0f)) u0 = 3.4e38f;\n"
             "  if (!(u1 > seg.x && u1 < seg.y && rms + u1 * nu < 0.0f)) u1 = 3.4e38f;\n"
             "  /* and where the sun line passes closest to the ground, whence they grow */\n"
             "  float u2 = qa > 0.0f ? -qb / (2.0f * qa) : 3.4e38f;\n"
             "  if (!(u2 > seg.x && u2 < seg.y)) u2 = 3.4e38f;\n"
             "  float edge0 = @min(@min(u0, u1), u2), edge2 = @max(@max(u0, u1), u2);\n"
             "  float edge1 = @max(@min(u0, u1), @min(@max(u0, u1), u2));\n",
             R);
  for (int i = 0; i < nc; ++i)
    if (sf_emit_sky_dims_any(atm, i)) sf_cw_emit(w, "  float v%d = 0.0f;  /* %s, km from the viewer */\n", i,
                                              atm->constituents[i].name);
  /* the depth viewer -> point -> sun at the stretch's start */
  sf_cw_emit(w, "  @vec4 sun = skyfit_raymarched_sun_columns(seg.z, @min(@max((rms + seg.x * nu) / (%F + seg.z), "
                "-1.0f), 1.0f));\n", R);
  emit_depths(w, atm, "  float ", "da", "sun");
  sf_cw_emit(w,
             "  float a = seg.x, dt = (seg.y - seg.x) / %F, k_step = 1.0f;\n"
             "  for (int s = 0; s < %d; ++s) {\n"
             "    float b = k_step >= %F ? seg.y : seg.x + k_step * dt;\n"
             "    if (edge0 < b) {\n"
             "      b = edge0;\n"
             "      edge0 = edge1;\n"
             "      edge1 = edge2;\n"
             "      edge2 = 3.4e38f;\n"
             "    } else {\n"
             "      k_step += 1.0f;\n"
             "    }\n"
             "    if (a < seg.y) {\n"
             "      @vec4 col = skyfit_raymarched_columns(hv, m, a, b);\n",
             (double)m->steps, m->steps + 3, (double)m->steps);
  for (int i = 0; i < nc; ++i)
    if (sf_emit_sky_dims_any(atm, i)) sf_cw_emit(w, "      v%d += col.%s;\n", i, component[i]);
  sf_cw_emit(w,
             "      float hb = skyfit_altitude_at(%F, hv, m, b);\n"
             "      sun = skyfit_raymarched_sun_columns(hb, @min(@max((rms + b * nu) / (%F + hb), -1.0f), 1.0f));\n",
             R, R);
  emit_depths(w, atm, "      float ", "db", "sun");
  sf_cw_emit(w,
             "      float tm = 0.5f * (a + b);\n"
             "      if (!(rms + tm * nu < 0.0f && (qa * tm + qb) * tm + qc < 0.0f)) {  /* else in the shadow */\n");
  for (int k = 0; k < nk; ++k) {
    sf_cw_emit(w, "        l%d += (0.0f", k);
    for (int i = 0; i < nc; ++i)
      if (sf_emit_sky_scatters(atm, i, k))
        sf_cw_emit(w, " + %F * p%d * col.%s", atm->constituents[i].scattering[k], i, component[i]);
    sf_cw_emit(w, ") * skyfit_exp_mean(da%d, db%d);\n", k, k);
  }
  sf_cw_emit(w, "      }\n");
  for (int k = 0; k < nk; ++k) sf_cw_emit(w, "      da%d = db%d;\n", k, k);
  sf_cw_emit(w, "      a = b;\n    }\n  }\n");
  sf_emit_sky_close(w, atm, "");
  sf_cw_need(w, SF_HELPER_ALTITUDE_AT | SF_HELPER_SPHERE_HITS);
}
