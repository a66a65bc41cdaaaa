#include "codegen/emit_selection_alias.h"

void sf_emit_selection_alias(sf_code_writer *w, const void *model) {
  const sf_selection_alias *a = model;
  int n = a->n_channels;
  sf_cw_emit(w, "/* the scene's selection under stable names: a renderer calls these */\n");
  if (a->transmittance[0])
    sf_cw_emit(w,
               "@fn %V skyfit_transmittance(float h_km, float mu) {\n"
               "  return skyfit_%s_transmittance(h_km, mu);\n"
               "}\n\n"
               "@fn %V skyfit_transmittance_segment(float h_km, float mu, float t_km) {\n"
               "  return skyfit_%s_transmittance_segment(h_km, mu, t_km);\n"
               "}\n\n",
               n, a->transmittance, n, a->transmittance);
  if (!a->sky_radiance[0]) return;
  sf_cw_emit(w, "@fn %V skyfit_sky_radiance(float h_km, float mu, float mu_s, float nu) {\n", n);
  if (a->sky_takes_altitude) {
    sf_cw_emit(w, "  return skyfit_%s_sky_radiance(h_km, mu, mu_s, nu);\n}\n\n", a->sky_radiance);
  } else {
    if (w->lang == SF_CODE_C) sf_cw_emit(w, "  (void)h_km;  /* a viewer on the ground */\n");
    sf_cw_emit(w, "  return skyfit_%s_sky_radiance(mu, mu_s, nu);\n}\n\n", a->sky_radiance);
  }
  if (a->sky_has_segment)
    sf_cw_emit(w,
               "@fn %V skyfit_sky_radiance_segment(float h_km, float mu, float mu_s, float nu, float t_km) {\n"
               "  return skyfit_%s_sky_radiance_segment(h_km, mu, mu_s, nu, t_km);\n"
               "}\n\n",
               n, a->sky_radiance);
}
