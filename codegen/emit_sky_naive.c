#include "codegen/emit_sky_naive.h"

#include "codegen/baselines.h"
#include "codegen/emit_sky_frame.h"

static const char *const component[4] = {"x", "y", "z", "w"};

int sf_sky_naive_emittable(const sf_sky_naive *m, const char **why) {
  const sf_atmosphere *atm = m->atm;
  if (atm->n_channels > 4) *why = "emitted code returns vec1-vec4: at most 4 channels";
  else if (m->view_steps < 1 || (m->sun == SF_SKY_SUN_RAYMARCH && m->sun_steps < 1)) *why = "steps must be >= 1";
  else if (m->sun == SF_SKY_SUN_CHAPMAN && atm->n_constituents > 4)
    *why = "its sun columns travel in a vec4: at most 4 constituents";
  else if (m->sun == SF_SKY_SUN_CHAPMAN && sf_atmosphere_exponential_count(atm) == 0)
    *why = "Schuler's approximation needs an exponential constituent";
  else return 1;
  return 0;
}

/* skyfit_schuler_sun_columns(h, c): the Chapman baseline's column (km) of
 * every constituent from altitude h along the cosine c to the top. */
static void emit_schuler_sun_columns(sf_code_writer *w, const sf_atmosphere *atm) {
  const double R = atm->bottom_radius_km, H = atm->top_radius_km - atm->bottom_radius_km;
  sf_cw_emit(w, "@fn @vec4 skyfit_schuler_sun_columns(float h_km, float mu) {\n");
  for (int i = 0; i < atm->n_constituents; ++i)
    sf_cw_emit(w, "  float d%d = 0.0f;  /* %s, km */\n", i, atm->constituents[i].name);
  sf_cw_emit(w,
             "  @vec4 seg = skyfit_air_clip(%F, %F, h_km, mu, 0.0f, 3.4e38f);\n"
             "  if (seg.y > seg.x) {\n",
             R, H);
  sf_emit_chapman_columns(w, atm);
  sf_cw_emit(w, "  }\n  return @vec4(");
  for (int i = 0; i < 4; ++i) {
    if (i < atm->n_constituents) sf_cw_emit(w, i ? ", d%d" : "d%d", i);
    else sf_cw_emit(w, ", 0.0f");
  }
  sf_cw_emit(w, ");\n}\n\n");
  sf_cw_need(w, SF_HELPER_AIR_CLIP);
}

void sf_emit_sky_naive(sf_code_writer *w, const sf_sky_naive *m) {
  const sf_atmosphere *atm = m->atm;
  const int nc = atm->n_constituents, nk = atm->n_channels, schuler = m->sun == SF_SKY_SUN_CHAPMAN;
  const double R = atm->bottom_radius_km, H = atm->top_radius_km - atm->bottom_radius_km;
  if (schuler) {
    emit_schuler_sun_columns(w, atm);
    sf_cw_emit(w,
               "/* schuler sky: single scattering by a %d-step midpoint raymarch of the view ray, the sun's\n"
               " * optical depth at each step by Schuler's Chapman approximation (seed 000 eq. 22-25; eq. 59\n"
               " * shells for the others), no multiple scattering (seed 000 §11.2.7). */\n",
               m->view_steps);
  } else {
    sf_cw_emit(w,
               "/* naive sky: single scattering by a %d-step midpoint raymarch of the view ray, the sun's\n"
               " * optical depth at each step by a %d-step one, no multiple scattering (seed 000 §11.2.6,\n"
               " * SPEC 7.6 naive). */\n",
               m->view_steps, m->sun_steps);
  }
  sf_emit_sky_open(w, atm, schuler ? "schuler" : "naive");
  for (int i = 0; i < nc; ++i) {
    if (sf_emit_sky_dims_any(atm, i) && !schuler)
      sf_cw_emit(w, "  float v%d = 0.0f, rho%d, sun%d;  /* %s */\n", i, i, i, atm->constituents[i].name);
    else if (sf_emit_sky_dims_any(atm, i))
      sf_cw_emit(w, "  float v%d = 0.0f, rho%d;  /* %s */\n", i, i, atm->constituents[i].name);
    else if (sf_emit_sky_scatters_any(atm, i))
      sf_cw_emit(w, "  float rho%d;  /* %s */\n", i, atm->constituents[i].name);
  }
  sf_cw_emit(w,
             "  float h = 0.0f, view_k = 0.5f;  /* (no int-to-float cast is spelled alike in C and GLSL) */\n"
             "  float dt = (seg.y - seg.x) / %F;\n"
             "  for (int s = 0; s < %d; ++s) {\n"
             "    float t = seg.x + view_k * dt;\n"
             "    view_k += 1.0f;\n"
             "    float hp = skyfit_altitude_at(%F, hv, m, t);\n"
             "    float msp = @min(@max((r * ms + t * nu) / (%F + hp), -1.0f), 1.0f);\n"
             "    h = hp;\n",
             (double)m->view_steps, m->view_steps, R, R);
  for (int i = 0; i < nc; ++i) {
    if (!sf_emit_sky_dims_any(atm, i) && !sf_emit_sky_scatters_any(atm, i)) continue;
    sf_cw_emit(w, "    rho%d = ", i);
    sf_emit_constituent_density(w, &atm->constituents[i]);
    sf_cw_emit(w, ";\n");
  }
  sf_cw_emit(w,
             "    float rp = %F + hp;\n"
             "    @vec2 g = skyfit_sphere_hits(rp, msp, %F, -hp);\n"
             "    if (!(msp < 0.0f && g.x <= g.y)) {  /* else the planet hides the sun */\n",
             R, R);
  if (schuler) {
    sf_cw_emit(w, "      @vec4 sun = skyfit_schuler_sun_columns(hp, msp);\n");
  } else {
    sf_cw_emit(w, "      float ds = @max(skyfit_sphere_hits(rp, msp, %F, %F - hp).y, 0.0f) / %F;\n", R + H, H,
               (double)m->sun_steps);
    for (int i = 0; i < nc; ++i)
      if (sf_emit_sky_dims_any(atm, i)) sf_cw_emit(w, "      sun%d = 0.0f;\n", i);
    sf_cw_emit(w,
               "      float sun_k = 0.5f;\n"
               "      for (int j = 0; j < %d; ++j) {\n"
               "        h = skyfit_altitude_at(%F, hp, msp, sun_k * ds);\n"
               "        sun_k += 1.0f;\n",
               m->sun_steps, R);
    for (int i = 0; i < nc; ++i) {
      if (!sf_emit_sky_dims_any(atm, i)) continue;
      sf_cw_emit(w, "        sun%d += ", i);
      sf_emit_constituent_density(w, &atm->constituents[i]);
      sf_cw_emit(w, ";\n");
    }
    sf_cw_emit(w, "      }\n");
  }
  for (int k = 0; k < nk; ++k) {
    sf_cw_emit(w, "      l%d += @exp(-(0.0f", k);
    for (int i = 0; i < nc; ++i) {
      double e = sf_extinction(atm, i, k);
      if (e == 0.0) continue;
      if (schuler) sf_cw_emit(w, " + %F * (v%d + 0.5f * rho%d * dt + sun.%s)", e, i, i, component[i]);
      else sf_cw_emit(w, " + %F * (v%d + 0.5f * rho%d * dt + sun%d * ds)", e, i, i, i);
    }
    sf_cw_emit(w, ")) * (0.0f");
    for (int i = 0; i < nc; ++i)
      if (sf_emit_sky_scatters(atm, i, k)) sf_cw_emit(w, " + %F * p%d * rho%d", atm->constituents[i].scattering[k], i, i);
    sf_cw_emit(w, ");\n");
  }
  sf_cw_emit(w, "    }\n");
  for (int i = 0; i < nc; ++i)
    if (sf_emit_sky_dims_any(atm, i)) sf_cw_emit(w, "    v%d += rho%d * dt;\n", i, i);
  sf_cw_emit(w, "  }\n");
  sf_emit_sky_close(w, atm, "dt * ");
  sf_cw_need(w, SF_HELPER_ALTITUDE_AT | SF_HELPER_SPHERE_HITS);
}
