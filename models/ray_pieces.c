#include "models/ray_pieces.h"

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

int sf_ray_breakpoints(const sf_atmosphere *atm, double r, double mu, double t0,
                       double t1, double *breaks) {
  int n = 2;
  breaks[0] = t0;
  breaks[1] = t1;
  n = sf_ray_breaks_insert(breaks, n, -r * mu);
  for (int k = 0; k < atm->n_kinks; ++k) {
    double t_near, t_far;
    double radius = atm->bottom_radius_km + atm->kink_altitudes_km[k];
    if (sf_ray_sphere_intersections(r, mu, radius, &t_near, &t_far)) {
      n = sf_ray_breaks_insert(breaks, n, t_near);
      n = sf_ray_breaks_insert(breaks, n, t_far);
    }
  }
  return n;
}
