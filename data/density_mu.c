#include "data/density_mu.h"

#include "models/ray_geometry.h"

double sf_density_mu_ground_from_x(double R, double h, double x) {
  double mu_h = sf_horizon_mu(R + h, R);
  return -1.0 + x * (mu_h + 1.0);
}

double sf_density_x_from_mu_ground(double R, double h, double mu) {
  double mu_h = sf_horizon_mu(R + h, R);
  double x = (mu + 1.0) / (mu_h + 1.0);   /* mu_h > -1 at any finite r */
  return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}
