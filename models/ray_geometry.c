#include "models/ray_geometry.h"

#include <math.h>

#define REAL double
#define SUFFIX
#define SQRT sqrt
#define NEXTAFTER nextafter
#include "models/ray_geometry_impl.inc"
#undef REAL
#undef SUFFIX
#undef SQRT
#undef NEXTAFTER

#define REAL float
#define SUFFIX _f
#define SQRT sqrtf
#define NEXTAFTER nextafterf
#include "models/ray_geometry_impl.inc"
#undef REAL
#undef SUFFIX
#undef SQRT
#undef NEXTAFTER

double sf_ray_mu_at(double r, double mu, double t) {
  double rt = sf_ray_radius_at(r, mu, t);
  if (rt <= 0.0) return mu;
  double m = (r * mu + t) / rt;
  return m > 1.0 ? 1.0 : (m < -1.0 ? -1.0 : m);
}
