#include "data/sky_lookup.h"

#include <math.h>
#include <string.h>

#include "data/sunlit_ray.h"
#include "data/table_interp.h"
#include "models/atmosphere_file.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "util/constants.h"

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
  /* the memo holds F of the set's own atmosphere (that of its tables): a
   * view given another atmosphere computes F at every lookup */
  if (set->single_sunlit && sf_sample_memo_record_len(set->single_sunlit) == set->n_single * atm->n_channels &&
      sf_atmosphere_hash(atm) == set->atmosphere_hash)
    sky->sunlit = set->single_sunlit;
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

/* How much of a lookup's single scattering is interpolated through the
 * sunlit air (1: all of it). The planet's shadow can reach a table's ray
 * while the sun is less than acos(R / R_top) above the viewer's horizon,
 * the depression of the horizon seen from the top (10.1 deg for Earth's
 * 100 km of air, 24.6 deg for 100 km over a 1000 km planet): all of it
 * below that elevation, none 4 deg above, linear in the elevation between,
 * where the samples' own interpolation had cost about a fifteenth as much
 * (F at 17 points; the 16 samples' F now come from the set's memo,
 * data/sample_memo.h). */
#define SUNLIT_BLEND_RAD (4.0 * SF_PI / 180.0)

static double sunlit_weight(const sf_atmosphere *atm, double mu_s) {
  double shadow_reach = acos(atm->bottom_radius_km / atm->top_radius_km);
  double elevation = asin(fmax(-1.0, fmin(1.0, mu_s)));
  return fmin(1.0, fmax(0.0, (shadow_reach + SUNLIT_BLEND_RAD - elevation) / SUNLIT_BLEND_RAD));
}

/* How much of a lookup's single scattering is interpolated through the
 * sunlit air for its altitude's sake (1: all of it). Between the table's
 * last two altitudes (93.7 and 100 km by default) the samples' linear
 * interpolation in rho cannot follow a ray that keeps to the thin air
 * there: its light goes as its length times a density that falls by
 * e^(6.3 km / 8 km) across the cell, and the samples at the top hold rays
 * of almost no air (Bruneton's mu squeezes every upward ray into the
 * horizontal one there; Leenman's upward rays there have no length). From
 * 99 km, sun 20 deg up, 60 deg up it came out +35.7 %, straight up
 * +40.9 %, whatever the channel, sun azimuth or mu count, falling about
 * threefold per doubling of the altitude count (16, 32, 64, 128: +109,
 * +36, +12, +3 %). F follows the density and the length, so the samples
 * over F interpolate well (within 0.01 % there). A ray that dips into
 * dense air is not the top's: its samples' own interpolation does well
 * (from 99 km, 5 deg down: +1.3 %; from 92.55 km, passing 1 km above the
 * ground: -2.5 %, and +0.04 % through F since F follows such rays through
 * their lowest point, data/sunlit_ray.h; +14.6 % before). So the weight
 * goes by the ray's lowest altitude: 1 in the top cell, 0 at the sample
 * below it, linear between; and only where the table reaches the top of
 * the atmosphere, whose rays shrink to nothing. */
static double top_cell_weight(const sf_sky_tables *sky, const sf_scattering_coord *c) {
  const sf_table_params *p = &sky->params;
  double R = p->bottom_radius_km, r = R + c->h;
  if (p->h_max_km < p->top_radius_km - R) return 0.0;
  sf_scattering_coord low = *c;
  if (c->hits_ground) low.h = 0.0;
  else if (c->mu < 0.0) low.h = fmax(0.0, sqrt(sf_ray_closest_radius_sq(r, c->mu)) - R);
  double pos[4];
  sf_params_scattering_pos(p, &low, pos);
  double pos_h = pos[p->kind == SF_PARAM_BRUNETON ? 3 : 0];
  return fmin(1.0, fmax(0.0, pos_h - (p->res.scattering_h - 3)));
}

/* F (data/sunlit_ray.h) of every single table at the grid sample at
 * offset (in samples) of view g: from the set's memo where it holds it,
 * else computed (and offered to the memo). Either way the same function
 * of the same sample, so the same bits. */
static void sunlit_at_sample(const sf_sky_tables *sky, const sf_grid_view *g, long offset,
                             double out[][SF_MAX_CHANNELS]) {
  int n = sky->n_single, nch = sky->atm->n_channels;
  double record[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  if (sky->sunlit && sf_sample_memo_get(sky->sunlit, offset, record)) {
    for (int k = 0; k < n; ++k)
      for (int ch = 0; ch < nch; ++ch) out[k][ch] = record[k * nch + ch];
    return;
  }
  long at = offset;
  double pos[4];
  for (int k = 0; k < 4; ++k) {
    pos[k] = (double)(at % g->size[k]);
    at /= g->size[k];
  }
  sf_scattering_coord c;
  sf_params_scattering_coord(&sky->params, pos, &c);
  sf_sunlit_ray(sky->atm, &sky->params, sky->transmittance, n, sky->single_constituent, &c, out);
  if (!sky->sunlit) return;
  for (int k = 0; k < n; ++k)
    for (int ch = 0; ch < nch; ++ch) record[k * nch + ch] = out[k][ch];
  sf_sample_memo_put(sky->sunlit, offset, record);
}

/* The single scattering of every table at c (position pos): the samples
 * divided by F at their own coordinates, interpolated (geometrically along
 * mu_s, data/table_interp.h), times F at c. The ratio varies slowly where
 * the samples themselves change by decades or drop to 0 between two
 * (data/sunlit_ray.h): at 20 km, sun 8 deg down, the zenith came out
 * -26.5 % and 17 deg up across the sun -14.7 %, now within 0.1 % of the
 * exact quadrature (default tables; tests/test_single_shadow_lookup.c).
 * A sample whose ray holds no sunlit air (F = 0) says nothing of the
 * ratio: it is left out and the other corners' weights count for it; with
 * F = 0 at c the result is 0. */
static void single_of_sunlit(const sf_sky_tables *sky, const sf_scattering_coord *c, const double *pos,
                             int mu_s_axis, double out[][SF_MAX_CHANNELS]) {
  int nch = sky->atm->n_channels, n = sky->n_single, bit = 1 << mu_s_axis;
  double f_at[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS], f_lo[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];
  double f_hi[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];
  double sum[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS], weight[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];
  sf_sunlit_ray(sky->atm, &sky->params, sky->transmittance, n, sky->single_constituent, c, f_at);
  for (int k = 0; k < n; ++k)
    for (int ch = 0; ch < nch; ++ch) sum[k][ch] = weight[k][ch] = 0.0;
  sf_grid_view g = sf_grid_view_of(sky->single[0]);   /* the single tables share one layout */
  long offsets[16];
  double weights[16];
  sf_grid_corners(&g, pos, offsets, weights);
  for (int lo = 0; lo < 16; ++lo) {
    int hi = lo | bit;
    if ((lo & bit) || (weights[lo] == 0.0 && weights[hi] == 0.0)) continue;
    if (weights[lo] != 0.0) sunlit_at_sample(sky, &g, offsets[lo], f_lo);
    if (weights[hi] != 0.0) sunlit_at_sample(sky, &g, offsets[hi], f_hi);
    for (int k = 0; k < n; ++k) {
      const float *v_lo = sky->single[k]->data + offsets[lo] * nch;
      const float *v_hi = sky->single[k]->data + offsets[hi] * nch;
      for (int ch = 0; ch < nch; ++ch) {
        double w_lo = weights[lo] != 0.0 && f_lo[k][ch] > 0.0 ? weights[lo] : 0.0;
        double w_hi = weights[hi] != 0.0 && f_hi[k][ch] > 0.0 ? weights[hi] : 0.0, w = w_lo + w_hi;
        if (w == 0.0) continue;
        double f = w_hi / w, a = w_lo > 0.0 ? v_lo[ch] / f_lo[k][ch] : 0.0;
        double b = w_hi > 0.0 ? v_hi[ch] / f_hi[k][ch] : 0.0;
        sum[k][ch] += w * (a > 0.0 && b > 0.0 && f > 0.0 && f < 1.0 ? a * pow(b / a, f) : (1.0 - f) * a + f * b);
        weight[k][ch] += w;
      }
    }
  }
  for (int k = 0; k < n; ++k)
    for (int ch = 0; ch < nch; ++ch)
      out[k][ch] = weight[k][ch] > 0.0 ? f_at[k][ch] * sum[k][ch] / weight[k][ch] : 0.0;
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
  /* through the sunlit air where the sun is low enough for the planet's
   * shadow to cross a ray of the table, blended into the samples' own
   * interpolation above, and where the ray keeps to the top altitude cell */
  double w_sunlit = sky->transmittance ? fmax(sunlit_weight(atm, mu_s), top_cell_weight(sky, &c)) : 0.0;
  if (sky->n_single > 0 && w_sunlit > 0.0) single_of_sunlit(sky, &c, pos, mu_s_axis, out->single);
  if (sky->n_single > 0 && w_sunlit < 1.0) {
    double plain[SF_MAX_CHANNELS];
    for (int k = 0; k < sky->n_single; ++k) {
      sf_grid_view g = sf_grid_view_of(sky->single[k]);
      sf_grid_interp_geometric(&g, mu_s_axis, pos, plain);
      for (int ch = 0; ch < nch; ++ch)
        out->single[k][ch] = w_sunlit * out->single[k][ch] + (1.0 - w_sunlit) * plain[ch];
    }
  }
  for (int k = 0; k < sky->n_single; ++k) {
    double phase = sf_phase_value(&atm->constituents[sky->single_constituent[k]].phase, nu);
    for (int ch = 0; ch < nch; ++ch) out->radiance[ch] += phase * out->single[k][ch];
  }
  if (sky->multiple) {
    sf_grid_view g = sf_grid_view_of(sky->multiple);
    sf_grid_interp_geometric(&g, mu_s_axis, pos, out->multiple);
    for (int ch = 0; ch < nch; ++ch) out->radiance[ch] += out->multiple[ch];
  }
}

int sf_transmittance_table_to_top(const sf_table_params *p, const sf_table *transmittance, double h, double mu,
                                  double *out) {
  double pos[4] = {0, 0, 0, 0};
  int status = sf_params_transmittance_pos(p, h, mu, pos);
  sf_grid_view g = sf_grid_view_of(transmittance);
  sf_grid_interp(&g, pos, out);
  return status;
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
    sf_transmittance_table_to_top(&sky->params, sky->transmittance, h, mu, transmittance);
    return;
  }
  /* T(x -> ground) = T(ground -> top, reversed) / T(x -> top, reversed) */
  double t_near, t_far;
  double d = sf_ray_sphere_intersections(r, mu, R, &t_near, &t_far) && t_near > 0.0 ? t_near : 0.0;
  double mu_g = (r * mu + d) / R;
  mu_g = mu_g > 1.0 ? 1.0 : (mu_g < -1.0 ? -1.0 : mu_g);
  double a[SF_MAX_CHANNELS], b[SF_MAX_CHANNELS];
  sf_transmittance_table_to_top(&sky->params, sky->transmittance, 0.0, -mu_g, a);
  sf_transmittance_table_to_top(&sky->params, sky->transmittance, h, -mu, b);
  for (int ch = 0; ch < nch; ++ch) transmittance[ch] = b[ch] > 0.0 ? fmin(1.0, a[ch] / b[ch]) : 0.0;
}
