#include "models/tangent_sweep.h"

#include <math.h>

#include "models/ray_geometry.h"

long sf_tangent_sweep(double bottom_radius_km, double sphere_h_km, double h_min_km, double h_max_km,
                      double mu_min, double mu_max, sf_tangent_visit visit, void *ctx) {
  static const double offset[] = {-1e-6, 1e-6};
  double lo = fmax(h_min_km, sphere_h_km), sphere_radius = bottom_radius_km + sphere_h_km;
  long visited = 0;
  for (int i = 0; i < SF_TANGENT_SWEEP_ROWS && lo <= h_max_km; ++i) {
    double u = (double)i / (SF_TANGENT_SWEEP_ROWS - 1), h = lo + (h_max_km - lo) * u * u;
    if (!(h > sphere_h_km)) continue;
    double mu_t = sf_horizon_mu(bottom_radius_km + h, sphere_radius);
    for (int j = 0; j < 2; ++j) {
      double mu = mu_t + offset[j];
      if (mu < mu_min || mu > mu_max) continue;
      visit(ctx, h, mu);
      ++visited;
    }
  }
  return visited;
}
