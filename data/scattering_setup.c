#include "data/scattering_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/ray_geometry.h"
#include "models/sun_shadow.h"

int sf_scattering_setup_init(sf_scattering_setup *s, const sf_atmosphere *atm,
                             const sf_precompute_options *opt, sf_error *err) {
  memset(s, 0, sizeof *s);
  s->atm = atm;
  for (int i = 0; i < atm->n_constituents; ++i)
    if (sf_constituent_scatters(&atm->constituents[i], atm->n_channels)) s->scattering[s->n_scattering++] = i;
  sf_gauss_rule_init(&s->rule, SF_SCATTERING_NODES);
  for (int ch = 0; ch < atm->n_channels; ++ch)
    for (int i = 0; i < atm->n_constituents; ++i) s->extinction[ch][i] = sf_extinction(atm, i, ch);
  return sf_depth_grid_build(&s->sun_depth, atm, SF_DEPTH_GRID_MU, SF_DEPTH_GRID_H, opt, err);
}

void sf_scattering_setup_free(sf_scattering_setup *s) {
  sf_depth_grid_free(&s->sun_depth);
  memset(s, 0, sizeof *s);
}

int sf_sun_depth(const sf_scattering_setup *s, double r, double mu_sun, double *depth) {
  if (sf_ray_hits_sphere_from_above(r, mu_sun, s->atm->bottom_radius_km)) return 0;
  sf_depth_grid_lookup(&s->sun_depth, r, mu_sun, depth);
  return 1;
}

double sf_ray_end_distance(const sf_atmosphere *atm, double r, double mu, int hits_ground) {
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  if (hits_ground) {
    if (mu >= 0.0) return 0.0;
    double above = (r - R) * (r + R);
    double disc = r * r * mu * mu - above;
    double denom = -r * mu + sqrt(disc > 0.0 ? disc : 0.0);
    return denom > 0.0 ? above / denom : 0.0;
  }
  double inside = (Rt - r) * (Rt + r);
  if (inside < 0.0) inside = 0.0;
  double root = sqrt(inside + r * r * mu * mu);
  return mu > 0.0 ? inside / (r * mu + root) : root - r * mu;
}

int sf_sun_tangent_points(const sf_atmosphere *atm, double r, double mu, double mu_s, double nu,
                          double *out) {
  double roots[2 * (SF_MAX_KINKS + 1)];
  int n_roots = 0;
  for (int k = -1; k < atm->n_kinks; ++k) {   /* the ground, then the kinks */
    double rho = atm->bottom_radius_km + (k < 0 ? 0.0 : atm->kink_altitudes_km[k]);
    sf_sun_line line = sf_sun_line_make(r, mu, mu_s, nu, rho);
    n_roots += sf_sun_line_tangent_distances(&line, roots + n_roots);
  }
  /* The line towards the sun touches the sphere at a root, but the sun ray
   * (a half-line) only does if it descends first: the sun's zenith cosine
   * there is <= 0. At the other roots nothing changes. */
  int n = 0;
  for (int k = 0; k < n_roots; ++k) {
    double t = roots[k];
    double radius = sf_ray_radius_at(r, mu, t);
    if (!(radius > 0.0)) continue;
    if ((r * mu_s + t * nu) / radius <= 1e-9) out[n++] = t;
  }
  return n;
}

int sf_view_row_alloc(sf_view_row *row, const sf_scattering_setup *s) {
  memset(row, 0, sizeof *row);
  if (sf_ray_nodes_alloc(&row->nodes, &s->rule, s->atm->n_constituents)) return -1;
  size_t cap = (size_t)row->nodes.capacity;
  row->transmittance = malloc(sizeof(double) * cap * (size_t)(s->atm->n_channels + 1));
  row->sun_at = malloc(sizeof(sf_depth_grid_radius) * cap);
  if (!row->transmittance || !row->sun_at) {
    sf_view_row_free(row);
    return -1;
  }
  row->inv_radius = row->transmittance + cap * (size_t)s->atm->n_channels;
  return 0;
}

void sf_view_row_free(sf_view_row *row) {
  sf_ray_nodes_free(&row->nodes);
  free(row->transmittance);
  free(row->sun_at);
  memset(row, 0, sizeof *row);
}

void sf_view_row_fill(sf_view_row *row, const sf_scattering_setup *s, double h, double mu,
                      int hits_ground) {
  const sf_atmosphere *atm = s->atm;
  row->r = atm->bottom_radius_km + h;
  row->mu = mu;
  row->hits_ground = hits_ground;
  row->length = sf_ray_end_distance(atm, row->r, mu, hits_ground);
  sf_ray_nodes_fill(&row->nodes, atm, &s->rule, row->r, mu, 0.0, row->length, NULL, 0);
  int nc = atm->n_constituents, nch = atm->n_channels;
  for (int q = 0; q < row->nodes.n; ++q) {
    sf_setup_transmittance(s, row->nodes.depth + (size_t)q * nc, row->transmittance + (size_t)q * nch);
    row->inv_radius[q] = 1.0 / row->nodes.radius[q];
    sf_depth_grid_at_radius(&s->sun_depth, row->nodes.radius[q], &row->sun_at[q]);
  }
}
