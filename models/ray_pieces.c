#include "models/ray_pieces.h"

#include <math.h>

#include "models/ray_geometry.h"

int sf_ray_breaks_insert(double *breaks, int n, double t) {
  if (!(t > breaks[0] && t < breaks[n - 1]) || n >= SF_MAX_RAY_BREAKS) return n;
  int i = n - 1;
  while (breaks[i - 1] > t) --i;
  if (breaks[i - 1] == t) return n;
  for (int j = n; j > i; --j) breaks[j] = breaks[j - 1];
  breaks[i] = t;
  return n + 1;
}

/* The smallest scale height of any layer's exponential term (km);
 * INFINITY without one. */
static double smallest_scale_height(const sf_atmosphere *atm) {
  double H = INFINITY;
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    for (int l = 0; l < c->n_layers; ++l)
      if (c->layers[l].exp_term != 0.0 && c->layers[l].exp_scale_per_km < 0.0)
        H = fmin(H, -1.0 / c->layers[l].exp_scale_per_km);
  }
  return H;
}

/* Both crossings of the sphere of the given radius, into breaks. */
static int insert_sphere(double *breaks, int n, double r, double mu, double radius) {
  double t_near, t_far;
  if (sf_ray_sphere_intersections(r, mu, radius, &t_near, &t_far)) {
    n = sf_ray_breaks_insert(breaks, n, t_near);
    n = sf_ray_breaks_insert(breaks, n, t_far);
  }
  return n;
}

int sf_ray_breakpoints(const sf_atmosphere *atm, double r, double mu, double t0,
                       double t1, double *breaks) {
  int n = 2;
  breaks[0] = t0;
  breaks[1] = t1;
  n = sf_ray_breaks_insert(breaks, n, -r * mu);
  for (int k = 0; k < atm->n_kinks; ++k) n = insert_sphere(breaks, n, r, mu, atm->bottom_radius_km + atm->kink_altitudes_km[k]);
  double depth = atm->top_radius_km - atm->bottom_radius_km, shell = 512.0 * smallest_scale_height(atm);
  for (int j = 0; j < SF_MAX_DECAY_SHELLS && shell < depth; ++j, shell *= 4.0)
    n = insert_sphere(breaks, n, r, mu, atm->bottom_radius_km + shell);
  return n;
}
