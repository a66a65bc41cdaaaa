#include "models/perez.h"

#include <math.h>

double sf_perez_f(const double c[SF_PEREZ_N_COEFFS], double cos_theta, double gamma) {
  double cg = cos(gamma);
  return (1.0 + c[0] * exp(c[1] / cos_theta)) * (1.0 + c[2] * exp(c[3] * gamma) + c[4] * cg * cg);
}

double sf_perez_f_grad(const double c[SF_PEREZ_N_COEFFS], double cos_theta, double gamma,
                       double cos_gamma, double grad[SF_PEREZ_N_COEFFS]) {
  double e_theta = exp(c[1] / cos_theta);
  double e_gamma = exp(c[3] * gamma);
  double zenith_part = 1.0 + c[0] * e_theta;
  double sun_part = 1.0 + c[2] * e_gamma + c[4] * cos_gamma * cos_gamma;
  grad[0] = e_theta * sun_part;
  grad[1] = c[0] * e_theta / cos_theta * sun_part;
  grad[2] = zenith_part * e_gamma;
  grad[3] = zenith_part * c[2] * gamma * e_gamma;
  grad[4] = zenith_part * cos_gamma * cos_gamma;
  return zenith_part * sun_part;
}
