#include "models/optical_depth_raymarch.h"

#include <math.h>

#include "models/air_segment.h"
#include "models/ray_geometry.h"

static void add_densities(const sf_atmosphere *atm, double r, double mu, double t,
                          double weight, double *out) {
  double h = sf_ray_radius_at(r, mu, t) - atm->bottom_radius_km;
  for (int i = 0; i < atm->n_constituents; ++i)
    out[i] += weight * sf_constituent_density(&atm->constituents[i], h);
}

int sf_optical_depth_raymarch_segment(const sf_atmosphere *atm, double r, double mu,
                                      double t0, double t1, int steps,
                                      sf_raymarch_rule rule, double *out) {
  int n = atm->n_constituents;
  if (steps < 1 || (rule != SF_RAYMARCH_MIDPOINT && rule != SF_RAYMARCH_TRAPEZOID)) {
    for (int i = 0; i < n; ++i) out[i] = NAN;
    return 0;
  }
  for (int i = 0; i < n; ++i) out[i] = 0.0;
  if (!sf_air_segment_clip(atm->bottom_radius_km, atm->top_radius_km, r, mu, &t0, &t1))
    return n;
  double step = (t1 - t0) / steps;
  if (rule == SF_RAYMARCH_MIDPOINT) {
    for (int k = 0; k < steps; ++k)
      add_densities(atm, r, mu, t0 + (k + 0.5) * step, step, out);
  } else {
    add_densities(atm, r, mu, t0, 0.5 * step, out);
    for (int k = 1; k < steps; ++k) add_densities(atm, r, mu, t0 + k * step, step, out);
    add_densities(atm, r, mu, t1, 0.5 * step, out);
  }
  return n;
}
