#include "models/ciede2000.h"

#include <math.h>

#include "util/constants.h"

static double deg(double rad) { return rad * (180.0 / SF_PI); }
static double rad(double d) { return d * (SF_PI / 180.0); }

/* Sharma et al. 2005 eq. 4-5: h' = atan2(b, a') in [0, 360), 0 when a' = b = 0 */
static double hue_deg(double b, double a_prime) {
  if (b == 0.0 && a_prime == 0.0) return 0.0;
  double h = deg(atan2(b, a_prime));
  return h < 0.0 ? h + 360.0 : h;
}

double sf_ciede2000(const double lab1[3], const double lab2[3]) {
  const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
  const double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
  /* eq. 2-3 */
  double C1 = hypot(a1, b1), C2 = hypot(a2, b2);
  double C_mean = 0.5 * (C1 + C2);
  double C7 = pow(C_mean, 7.0);
  double G = 0.5 * (1.0 - sqrt(C7 / (C7 + pow(25.0, 7.0))));
  double a1p = (1.0 + G) * a1, a2p = (1.0 + G) * a2;
  double C1p = hypot(a1p, b1), C2p = hypot(a2p, b2);
  double h1p = hue_deg(b1, a1p), h2p = hue_deg(b2, a2p);
  /* eq. 8-10 */
  double dLp = L2 - L1;
  double dCp = C2p - C1p;
  double dhp;
  if (C1p * C2p == 0.0) dhp = 0.0;
  else if (fabs(h2p - h1p) <= 180.0) dhp = h2p - h1p;
  else if (h2p - h1p > 180.0) dhp = h2p - h1p - 360.0;
  else dhp = h2p - h1p + 360.0;
  double dHp = 2.0 * sqrt(C1p * C2p) * sin(rad(0.5 * dhp));
  /* eq. 12-14 */
  double Lp_mean = 0.5 * (L1 + L2);
  double Cp_mean = 0.5 * (C1p + C2p);
  double hp_mean;
  if (C1p * C2p == 0.0) hp_mean = h1p + h2p;
  else if (fabs(h1p - h2p) <= 180.0) hp_mean = 0.5 * (h1p + h2p);
  else if (h1p + h2p < 360.0) hp_mean = 0.5 * (h1p + h2p + 360.0);
  else hp_mean = 0.5 * (h1p + h2p - 360.0);
  /* eq. 15-21 */
  double T = 1.0 - 0.17 * cos(rad(hp_mean - 30.0)) + 0.24 * cos(rad(2.0 * hp_mean)) +
             0.32 * cos(rad(3.0 * hp_mean + 6.0)) - 0.20 * cos(rad(4.0 * hp_mean - 63.0));
  double d_theta = 30.0 * exp(-((hp_mean - 275.0) / 25.0) * ((hp_mean - 275.0) / 25.0));
  double Cp7 = pow(Cp_mean, 7.0);
  double R_C = 2.0 * sqrt(Cp7 / (Cp7 + pow(25.0, 7.0)));
  double l50 = (Lp_mean - 50.0) * (Lp_mean - 50.0);
  double S_L = 1.0 + 0.015 * l50 / sqrt(20.0 + l50);
  double S_C = 1.0 + 0.045 * Cp_mean;
  double S_H = 1.0 + 0.015 * Cp_mean * T;
  double R_T = -sin(rad(2.0 * d_theta)) * R_C;
  /* eq. 22, kL = kC = kH = 1 */
  double tL = dLp / S_L, tC = dCp / S_C, tH = dHp / S_H;
  return sqrt(tL * tL + tC * tC + tH * tH + R_T * tC * tH);
}
