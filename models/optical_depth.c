#include "models/optical_depth.h"

#include <math.h>
#include <stddef.h>

#include "models/quadrature.h"
#include "models/ray_geometry.h"
#include "models/ray_pieces.h"

typedef struct density_ray {
  const sf_atmosphere *atm;
  double r, mu;
} density_ray;

static void densities_along_ray(void *ctx, double t, double *values) {
  const density_ray *ray = ctx;
  const sf_atmosphere *atm = ray->atm;
  double h = sf_ray_radius_at(ray->r, ray->mu, t) - atm->bottom_radius_km;
  for (int i = 0; i < atm->n_constituents; ++i)
    values[i] = sf_constituent_density(&atm->constituents[i], h);
}

void sf_optical_depth_segment_tol(const sf_atmosphere *atm, double r, double mu,
                                  double t0, double t1, double rel_tol, double *out) {
  for (int i = 0; i < atm->n_constituents; ++i) out[i] = 0.0;
  if (!(t1 > t0)) return;
  /* Only the part inside the top sphere has air. */
  double t_near, t_far;
  if (!sf_ray_sphere_intersections(r, mu, atm->top_radius_km, &t_near, &t_far)) return;
  if (t_near > t0) t0 = t_near;
  if (t_far < t1) t1 = t_far;
  if (!(t1 > t0)) return;

  double breaks[SF_MAX_RAY_BREAKS];
  int n = sf_ray_breakpoints(atm, r, mu, t0, t1, breaks);
  density_ray ray = {atm, r, mu};
  for (int p = 0; p + 1 < n; ++p) {
    /* Altitudes computed from radii near 6000 km are only resolved to
     * ~1e-12 km, so a density is uncertain by |d density/dh| * 1e-12 (<= ~1e-12
     * for any scale height >= 1 km). A relative tolerance cannot be met where
     * the integral itself is of that size (a sliver of the ozone tent's
     * corner): the absolute floor SF_DENSITY_RESOLUTION per km of path stops
     * there, at an optical-thickness error far below 1e-9. */
    double floor_tol[SF_MAX_CONSTITUENTS];
    for (int i = 0; i < atm->n_constituents; ++i)
      floor_tol[i] = SF_DENSITY_RESOLUTION * (breaks[p + 1] - breaks[p]);
    sf_integrate_adaptive(densities_along_ray, &ray, breaks[p], breaks[p + 1],
                          atm->n_constituents, rel_tol, floor_tol, out);
  }
}

void sf_optical_depth_segment(const sf_atmosphere *atm, double r, double mu,
                              double t0, double t1, double *out) {
  sf_optical_depth_segment_tol(atm, r, mu, t0, t1, SF_OPTICAL_DEPTH_REL_TOL, out);
}

int sf_optical_depth_ray(const sf_atmosphere *atm, double h_km, double mu,
                         sf_ray_end end, double *out) {
  for (int i = 0; i < atm->n_constituents; ++i) out[i] = 0.0;
  double r = atm->bottom_radius_km + h_km;
  /* a viewer in space: the ray from where it enters (models/ray_geometry.h) */
  double skipped, mu_entry;
  if (r > atm->top_radius_km) {
    if (!sf_ray_enter_from_above(r, mu, 0.0, 0.0, atm->top_radius_km, &skipped, &mu_entry, NULL)) return 0;
    r = atm->top_radius_km;
    mu = mu_entry;
  }
  double t_enter, t_exit;
  int hits_ground;
  if (!sf_ray_atmosphere_segment(r, mu, atm->bottom_radius_km, atm->top_radius_km,
                                 &t_enter, &t_exit, &hits_ground))
    return 0;
  if (hits_ground && end == SF_RAY_END_TOP) return -1;
  sf_optical_depth_segment(atm, r, mu, t_enter, t_exit, out);
  return 0;
}

void sf_transmittance_from_depth(const sf_atmosphere *atm, const double *depth,
                                 double *transmittance) {
  for (int ch = 0; ch < atm->n_channels; ++ch) {
    double tau = 0.0;
    for (int i = 0; i < atm->n_constituents; ++i) tau += sf_extinction(atm, i, ch) * depth[i];
    transmittance[ch] = exp(-tau);
  }
}
