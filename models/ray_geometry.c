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

int sf_ray_enter_from_above(double r, double mu, double mu_s, double nu, double top, double *t_enter, double *mu_e,
                            double *mu_s_e) {
  if (!(r > top) || !(mu < 0.0)) return 0;
  /* s^2 = top^2 - p^2 as the discriminant forms it: from the closest
   * approach far out, (top - r)(top + r) + (r mu)^2 near the sphere, where
   * top - p had cancelled (a viewer 1e-12 km above the top, mu -1e-7, had
   * seen its column 7.5e-3 off) */
  double disc = sf_ray_sphere_discriminant(r, mu, top);
  if (!(disc > 0.0)) return 0;   /* a ray that only touches the sphere has no path inside */
  double s = sqrt(disc);
  /* the near root as c / q, q = s - r mu > 0: -r mu - s cancels when grazing */
  *t_enter = (r - top) * (r + top) / (s - r * mu);
  *mu_e = -s / top;
  if (mu_s_e) {
    double m = (r * (mu_s - mu * nu) - s * nu) / top;
    *mu_s_e = m > 1.0 ? 1.0 : (m < -1.0 ? -1.0 : m);
  }
  return 1;
}
