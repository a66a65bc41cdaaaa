#include "codegen/emit_sky_naive.h"

#include "codegen/baselines.h"
#include "codegen/emit_sky_frame.h"

void sf_emit_sky_naive(sf_code_writer *w, const sf_sky_naive *m) {
  const sf_atmosphere *atm = m->atm;
  const int nc = atm->n_constituents, nk = atm->n_channels;
  const double R = atm->bottom_radius_km, H = atm->top_radius_km - atm->bottom_radius_km;
  sf_cw_emit(w,
             "/* naive sky: single scattering by a %d-step midpoint raymarch of the view ray, the sun's\n"
             " * optical depth at each step by a %d-step one, no multiple scattering (seed 000 §11.2.6,\n"
             " * SPEC 7.6 naive). */\n",
             m->view_steps, m->sun_steps);
  sf_emit_sky_open(w, atm, "naive");
  for (int i = 0; i < nc; ++i) {
    if (sf_emit_sky_dims_any(atm, i))
      sf_cw_emit(w, "  float v%d = 0.0f, rho%d, sun%d;  /* %s */\n", i, i, i, atm->constituents[i].name);
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
             "    if (!(msp < 0.0f && g.x <= g.y)) {  /* else the planet hides the sun */\n"
             "      float ds = @max(skyfit_sphere_hits(rp, msp, %F, %F - hp).y, 0.0f) / %F;\n",
             R, R, R + H, H, (double)m->sun_steps);
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
  for (int k = 0; k < nk; ++k) {
    sf_cw_emit(w, "      l%d += @exp(-(0.0f", k);
    for (int i = 0; i < nc; ++i) {
      double e = sf_extinction(atm, i, k);
      if (e != 0.0) sf_cw_emit(w, " + %F * (v%d + 0.5f * rho%d * dt + sun%d * ds)", e, i, i, i);
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
