#include "models/hosek.h"

#include <math.h>

double sf_hosek_chi(double g, double cos_gamma) {
  return (1.0 + cos_gamma * cos_gamma) / pow(1.0 + g * g - 2.0 * g * cos_gamma, 1.5);
}

double sf_hosek_f(const double c[SF_HOSEK_N_COEFFS], double cos_theta, double gamma) {
  double cg = cos(gamma);
  return (1.0 + c[0] * exp(c[1] / (cos_theta + 0.01))) *
         (c[2] + c[3] * exp(c[4] * gamma) + c[5] * cg * cg + c[6] * sf_hosek_chi(c[7], cg) +
          c[8] * sqrt(cos_theta));
}

double sf_hosek_f_grad(const double c[SF_HOSEK_N_COEFFS], double cos_theta, double gamma,
                       double cos_gamma, double grad[SF_HOSEK_N_COEFFS]) {
  double e_theta = exp(c[1] / (cos_theta + 0.01));
  double e_gamma = exp(c[4] * gamma);
  double denom = 1.0 + c[7] * c[7] - 2.0 * c[7] * cos_gamma;
  double chi = (1.0 + cos_gamma * cos_gamma) / (denom * sqrt(denom));   /* denom^(3/2) */
  /* d chi / d g = chi * (-3/2) (2 g - 2 cos gamma) / denom */
  double dchi_dg = -3.0 * chi * (c[7] - cos_gamma) / denom;
  double root = sqrt(cos_theta);
  double zenith_part = 1.0 + c[0] * e_theta;
  double sun_part = c[2] + c[3] * e_gamma + c[5] * cos_gamma * cos_gamma + c[6] * chi + c[8] * root;
  grad[0] = e_theta * sun_part;
  grad[1] = c[0] * e_theta / (cos_theta + 0.01) * sun_part;
  grad[2] = zenith_part;
  grad[3] = zenith_part * e_gamma;
  grad[4] = zenith_part * c[3] * gamma * e_gamma;
  grad[5] = zenith_part * cos_gamma * cos_gamma;
  grad[6] = zenith_part * chi;
  grad[7] = zenith_part * c[6] * dchi_dg;
  grad[8] = zenith_part * root;
  return zenith_part * sun_part;
}
