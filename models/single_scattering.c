#include "models/single_scattering.h"

#include <math.h>
#include <stddef.h>

#include "models/optical_depth.h"
#include "models/quadrature.h"
#include "models/ray_geometry.h"
#include "models/ray_pieces.h"
#include "models/sun_shadow.h"

double sf_clamp_nu(double mu, double mu_s, double nu) {
  double spread = sqrt(fmax(0.0, (1.0 - mu * mu) * (1.0 - mu_s * mu_s)));
  double lo = mu * mu_s - spread, hi = mu * mu_s + spread;
  return nu < lo ? lo : (nu > hi ? hi : nu);
}

typedef struct scattering_ray {
  const sf_atmosphere *atm;
  const sf_view_ray *ray;
  double mu_s, nu;
  int n_scattering;
  int scattering[SF_MAX_CONSTITUENTS];   /* indices of scattering constituents */
  double inner_tol;
  sf_sun_line ground;   /* the sun lines against the ground: the shadow */
  /* The piece being integrated starts at piece_start, and the optical depth
   * from the ray's start to there is piece_depth: the view transmittance to
   * a point then needs only the smooth stretch from piece_start. */
  double piece_start;
  double piece_depth[SF_MAX_CONSTITUENTS];
} scattering_ray;

/* Optical depth from the point at distance t towards the sun; returns 0 if
 * the planet hides the sun there. */
static int sun_optical_depth(const scattering_ray *s, double t, double *depth) {
  const sf_atmosphere *atm = s->atm;
  const sf_view_ray *ray = s->ray;
  if (sf_sun_line_hidden(&s->ground, t)) return 0;
  double rp = sf_ray_radius_at(ray->r, ray->mu, t);
  double mu_sun = (ray->r * s->mu_s + t * s->nu) / rp;
  mu_sun = mu_sun > 1.0 ? 1.0 : (mu_sun < -1.0 ? -1.0 : mu_sun);
  double t_near, t_far;
  for (int i = 0; i < atm->n_constituents; ++i) depth[i] = 0.0;
  if (sf_ray_sphere_intersections(rp, mu_sun, atm->top_radius_km, &t_near, &t_far) && t_far > 0.0)
    sf_optical_depth_segment_tol(atm, rp, mu_sun, 0.0, t_far, s->inner_tol, depth);
  return 1;
}

static void scattered_light_at(void *ctx, double t, double *values) {
  const scattering_ray *s = ctx;
  const sf_atmosphere *atm = s->atm;
  const sf_view_ray *ray = s->ray;
  int nch = atm->n_channels;
  double view_depth[SF_MAX_CONSTITUENTS], sun_depth[SF_MAX_CONSTITUENTS];
  if (!sun_optical_depth(s, t, sun_depth)) {
    for (int k = 0; k < s->n_scattering * nch; ++k) values[k] = 0.0;
    return;
  }
  sf_optical_depth_segment_tol(atm, ray->r, ray->mu, s->piece_start, t, s->inner_tol, view_depth);
  for (int i = 0; i < atm->n_constituents; ++i) view_depth[i] += s->piece_depth[i];
  double transmittance[SF_MAX_CHANNELS];
  for (int ch = 0; ch < nch; ++ch) {
    double tau = 0.0;
    for (int i = 0; i < atm->n_constituents; ++i)
      tau += sf_extinction(atm, i, ch) * (view_depth[i] + sun_depth[i]);
    transmittance[ch] = exp(-tau);
  }
  double h = sf_ray_radius_at(ray->r, ray->mu, t) - atm->bottom_radius_km;
  for (int k = 0; k < s->n_scattering; ++k) {
    double density = sf_constituent_density(&atm->constituents[s->scattering[k]], h);
    for (int ch = 0; ch < nch; ++ch) values[k * nch + ch] = density * transmittance[ch];
  }
}

/* Points along the view ray where the sun ray from there is tangent to the
 * sphere of radius R (models/sun_shadow.h): there T(p -> sun) has a corner
 * (R a density kink) or a jump (R the ground: the planet's shadow). */
static int add_sun_tangent_points(const scattering_ray *s, double radius, double *breaks, int n) {
  sf_sun_line line = sf_sun_line_make(s->ray->r, s->ray->mu, s->mu_s, s->nu, radius);
  double t[2];
  int n_t = sf_sun_line_tangent_distances(&line, t);
  for (int k = 0; k < n_t; ++k) n = sf_ray_breaks_insert(breaks, n, t[k]);
  return n;
}

void sf_single_scattering_tol(const sf_atmosphere *atm, const sf_view_ray *ray,
                              double mu_s, double nu, double rel_tol, double *out) {
  int nch = atm->n_channels;
  for (int k = 0; k < atm->n_constituents * nch; ++k) out[k] = 0.0;
  if (!(ray->t1 > ray->t0)) return;
  double nu_clamped = sf_clamp_nu(ray->mu, mu_s, nu);
  scattering_ray s = {atm, ray, mu_s, nu_clamped, 0, {0}, rel_tol * 0.1,
                      sf_sun_line_make(ray->r, ray->mu, mu_s, nu_clamped, atm->bottom_radius_km), ray->t0, {0}};
  for (int i = 0; i < atm->n_constituents; ++i)
    if (sf_constituent_scatters(&atm->constituents[i], nch)) s.scattering[s.n_scattering++] = i;
  if (s.n_scattering == 0) return;

  double breaks[SF_MAX_RAY_BREAKS];
  int n = sf_ray_breakpoints(atm, ray->r, ray->mu, ray->t0, ray->t1, breaks);
  n = add_sun_tangent_points(&s, atm->bottom_radius_km, breaks, n);
  for (int k = 0; k < atm->n_kinks; ++k)
    n = add_sun_tangent_points(&s, atm->bottom_radius_km + atm->kink_altitudes_km[k], breaks, n);

  double sum[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS] = {0};
  for (int p = 0; p + 1 < n; ++p) {
    s.piece_start = breaks[p];
    sf_integrate_adaptive(scattered_light_at, &s, breaks[p], breaks[p + 1],
                          s.n_scattering * nch, rel_tol, NULL, sum);
    double piece[SF_MAX_CONSTITUENTS];
    sf_optical_depth_segment_tol(atm, ray->r, ray->mu, breaks[p], breaks[p + 1], s.inner_tol, piece);
    for (int i = 0; i < atm->n_constituents; ++i) s.piece_depth[i] += piece[i];
  }
  for (int k = 0; k < s.n_scattering; ++k) {
    const sf_constituent *c = &atm->constituents[s.scattering[k]];
    for (int ch = 0; ch < nch; ++ch)
      out[s.scattering[k] * nch + ch] = atm->sun_irradiance[ch] * c->scattering[ch] * sum[k * nch + ch];
  }
}

void sf_single_scattering(const sf_atmosphere *atm, const sf_view_ray *ray, double mu_s,
                          double nu, double *out) {
  sf_single_scattering_tol(atm, ray, mu_s, nu, SF_SINGLE_SCATTERING_REL_TOL, out);
}
