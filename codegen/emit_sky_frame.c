#include "codegen/emit_sky_frame.h"

#include "codegen/emit_phase.h"

int sf_emit_sky_scatters(const sf_atmosphere *atm, int i, int k) {
  return atm->constituents[i].scattering[k] != 0.0 && atm->constituents[i].phase.kind != SF_PHASE_NONE;
}

int sf_emit_sky_scatters_any(const sf_atmosphere *atm, int i) {
  for (int k = 0; k < atm->n_channels; ++k)
    if (sf_emit_sky_scatters(atm, i, k)) return 1;
  return 0;
}

int sf_emit_sky_dims_any(const sf_atmosphere *atm, int i) {
  for (int k = 0; k < atm->n_channels; ++k)
    if (sf_extinction(atm, i, k) != 0.0) return 1;
  return 0;
}

void sf_emit_sky_open(sf_code_writer *w, const sf_atmosphere *atm, const char *name) {
  const int nk = atm->n_channels;
  const double R = atm->bottom_radius_km, H = atm->top_radius_km - atm->bottom_radius_km;
  sf_cw_emit(w,
             "@fn %V skyfit_%s_sky_radiance(float h_km, float mu, float mu_s, float nu) {\n"
             "  mu = @min(@max(mu, -1.0f), 1.0f);\n"   /* as the fitted models: |mu| 1.1 had given NaN */
             "  mu_s = @min(@max(mu_s, -1.0f), 1.0f);\n"
             "  nu = skyfit_clamp_nu(mu, mu_s, nu);\n"
             "  @vec4 e = skyfit_ray_enter(%F, %F, @max(h_km, 0.0f), mu, mu_s, nu);\n",
             nk, name, R, H);
  for (int k = 0; k < nk; ++k) sf_cw_emit(w, "  float l%d = 0.0f;\n", k);
  sf_cw_emit(w,
             "  if (e.w >= 0.0f) {\n"
             "  float hv = e.x, m = e.y, ms = e.z;\n"
             "  @vec4 seg = skyfit_air_clip(%F, %F, hv, m, 0.0f, 3.4e38f);\n"
             "  if (seg.y > seg.x) {\n"
             "  float r = %F + hv;\n",
             R, H, R);
  for (int i = 0; i < atm->n_constituents; ++i)
    if (sf_emit_sky_scatters_any(atm, i)) sf_emit_phase(w, i, &atm->constituents[i].phase);
  sf_cw_need(w, SF_HELPER_RAY_ENTER | SF_HELPER_AIR_CLIP | SF_HELPER_CLAMP_NU);
}

void sf_emit_sky_close(sf_code_writer *w, const sf_atmosphere *atm, const char *sun_factor) {
  const int nk = atm->n_channels;
  for (int k = 0; k < nk; ++k) sf_cw_emit(w, "  l%d *= %s%F;\n", k, sun_factor, atm->sun_irradiance[k]);
  sf_cw_emit(w, "  }\n  }\n  return %C", nk);
  for (int k = 0; k < nk; ++k) sf_cw_emit(w, k ? ", l%d" : "l%d", k);
  sf_cw_emit(w, ");\n}\n\n");
}
