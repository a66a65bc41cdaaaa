#include "data/sky_lookup.h"

#include <math.h>
#include <string.h>

#include "data/table_interp.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"

void sf_sky_tables_of_set(sf_sky_tables *sky, const sf_atmosphere *atm, const sf_table_set *set) {
  memset(sky, 0, sizeof *sky);
  sky->atm = atm;
  sky->params = set->params;
  sky->transmittance = &set->transmittance;
  sky->n_single = set->n_single;
  for (int k = 0; k < set->n_single; ++k) {
    sky->single_constituent[k] = set->single_constituent[k];
    sky->single[k] = &set->single[k];
  }
  sky->multiple = set->multiple.data ? &set->multiple : NULL;   /* none: transmittance only */
}

int sf_sky_enter_atmosphere(const sf_atmosphere *atm, double h, double *r, double *mu, double *mu_s, double nu) {
  double Rt = atm->top_radius_km;
  *r = atm->bottom_radius_km + h;
  if (*r <= Rt) return 1;
  double t_enter, mu_e, mu_s_e;   /* from the closest approach: no cancellation far out */
  if (!sf_ray_enter_from_above(*r, *mu, *mu_s, nu, Rt, &t_enter, &mu_e, &mu_s_e)) return 0;
  *mu = mu_e;
  *mu_s = mu_s_e;
  *r = Rt;
  return 1;
}

void sf_sky_lookup(const sf_sky_tables *sky, double h_km, double mu, double mu_s, double nu,
                   sf_sky_sample *out) {
  const sf_atmosphere *atm = sky->atm;
  int nch = atm->n_channels;
  memset(out, 0, sizeof *out);
  nu = sf_clamp_nu(mu, mu_s, nu);
  double r;
  if (!sf_sky_enter_atmosphere(atm, h_km, &r, &mu, &mu_s, nu)) return;
  out->in_atmosphere = 1;
  sf_scattering_coord c = {r - atm->bottom_radius_km, mu, mu_s, nu,
                           sf_ray_hits_sphere_from_above(r, mu, atm->bottom_radius_km)};
  double pos[4];
  sf_params_scattering_pos(&sky->params, &c, pos);
  /* geometric in mu_s (data/table_interp.h): the light of a sun below the
   * horizon fades exponentially as it sinks */
  int mu_s_axis = sky->params.kind == SF_PARAM_BRUNETON ? 0 : 2;
  for (int k = 0; k < sky->n_single; ++k) {
    sf_grid_view g = sf_grid_view_of(sky->single[k]);
    sf_grid_interp_geometric(&g, mu_s_axis, pos, out->single[k]);
    double phase = sf_phase_value(&atm->constituents[sky->single_constituent[k]].phase, nu);
    for (int ch = 0; ch < nch; ++ch) out->radiance[ch] += phase * out->single[k][ch];
  }
  if (sky->multiple) {
    sf_grid_view g = sf_grid_view_of(sky->multiple);
    sf_grid_interp_geometric(&g, mu_s_axis, pos, out->multiple);
    for (int ch = 0; ch < nch; ++ch) out->radiance[ch] += out->multiple[ch];
  }
}

/* Transmittance to the top from (h, mu), mu at or above the horizon. */
static void to_top(const sf_sky_tables *sky, double h, double mu, double *out) {
  double pos[4] = {0, 0, 0, 0};
  sf_params_transmittance_pos(&sky->params, h, mu, pos);
  sf_grid_view g = sf_grid_view_of(sky->transmittance);
  sf_grid_interp(&g, pos, out);
}

void sf_sky_transmittance(const sf_sky_tables *sky, double h_km, double mu, double *transmittance) {
  const sf_atmosphere *atm = sky->atm;
  int nch = atm->n_channels;
  for (int ch = 0; ch < nch; ++ch) transmittance[ch] = 1.0;
  double r, mu_s = 0.0;
  if (!sf_sky_enter_atmosphere(atm, h_km, &r, &mu, &mu_s, 0.0)) return;
  double R = atm->bottom_radius_km, h = r - R;
  int ground = sf_ray_hits_sphere_from_above(r, mu, R);
  if (sky->params.kind == SF_PARAM_LEENMAN || !ground) {
    double pos[4] = {0, 0, 0, 0};
    sf_params_transmittance_pos(&sky->params, h, mu, pos);
    sf_grid_view g = sf_grid_view_of(sky->transmittance);
    sf_grid_interp(&g, pos, transmittance);
    return;
  }
  /* T(x -> ground) = T(ground -> top, reversed) / T(x -> top, reversed) */
  double t_near, t_far;
  double d = sf_ray_sphere_intersections(r, mu, R, &t_near, &t_far) && t_near > 0.0 ? t_near : 0.0;
  double mu_g = (r * mu + d) / R;
  mu_g = mu_g > 1.0 ? 1.0 : (mu_g < -1.0 ? -1.0 : mu_g);
  double a[SF_MAX_CHANNELS], b[SF_MAX_CHANNELS];
  to_top(sky, 0.0, -mu_g, a);
  to_top(sky, h, -mu, b);
  for (int ch = 0; ch < nch; ++ch) transmittance[ch] = b[ch] > 0.0 ? fmin(1.0, a[ch] / b[ch]) : 0.0;
}
