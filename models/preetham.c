#include "models/preetham.h"

#include <math.h>

#include "util/constants.h"

/* preetham1999.md "Distribution coefficients": value = slope T + offset. */
static const double coefficient_slope[3][SF_PEREZ_N_COEFFS] = {
    {0.1787, -0.3554, -0.0227, 0.1206, -0.0670},
    {-0.0193, -0.0665, -0.0004, -0.0641, -0.0033},
    {-0.0167, -0.0950, -0.0079, -0.0441, -0.0109}};
static const double coefficient_offset[3][SF_PEREZ_N_COEFFS] = {
    {-1.4630, 0.4275, 5.3251, -2.5771, 0.3703},
    {-0.2592, 0.0008, 0.2125, -0.8989, 0.0452},
    {-0.2608, 0.0092, 0.2102, -1.6537, 0.0529}};

/* preetham1999.md "Zenith chromaticity": rows T^2, T, 1; columns th^3..1. */
static const double zenith_x_matrix[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                             {-0.02903, 0.06377, -0.03202, 0.00394},
                                             {0.11693, -0.21196, 0.06052, 0.25886}};
static const double zenith_y_matrix[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                             {-0.04214, 0.08970, -0.04153, 0.00516},
                                             {0.15346, -0.26756, 0.06670, 0.26688}};

/* IEC 61966-2-1 XYZ -> linear sRGB, 4 decimals (xyz_to_srgb.csv). */
static const double xyz_to_srgb[3][3] = {{3.2406, -1.5372, -0.4986},
                                         {-0.9689, 1.8758, 0.0415},
                                         {0.0557, -0.2040, 1.0570}};

void sf_preetham_coefficients(int q, double turbidity, double out[SF_PEREZ_N_COEFFS]) {
  for (int k = 0; k < SF_PEREZ_N_COEFFS; ++k)
    out[k] = coefficient_slope[q][k] * turbidity + coefficient_offset[q][k];
}

double sf_preetham_zenith_luminance(double turbidity, double sun_zenith) {
  double chi = (4.0 / 9.0 - turbidity / 120.0) * (SF_PI - 2.0 * sun_zenith);
  return (4.0453 * turbidity - 4.9710) * tan(chi) - 0.2155 * turbidity + 2.4192;
}

static double zenith_chromaticity(const double m[3][4], double turbidity, double sun_zenith) {
  double rows[3] = {turbidity * turbidity, turbidity, 1.0};
  double cols[4] = {sun_zenith * sun_zenith * sun_zenith, sun_zenith * sun_zenith, sun_zenith, 1.0};
  double sum = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) sum += rows[r] * m[r][c] * cols[c];
  return sum;
}

double sf_preetham_zenith_x(double turbidity, double sun_zenith) {
  return zenith_chromaticity(zenith_x_matrix, turbidity, sun_zenith);
}

double sf_preetham_zenith_y(double turbidity, double sun_zenith) {
  return zenith_chromaticity(zenith_y_matrix, turbidity, sun_zenith);
}

void sf_preetham_sky_init(sf_preetham_sky *s, double turbidity, double sun_zenith) {
  s->turbidity = turbidity;
  s->sun_zenith = sun_zenith;
  s->zenith[SF_PREETHAM_Y] = sf_preetham_zenith_luminance(turbidity, sun_zenith);
  s->zenith[SF_PREETHAM_X] = sf_preetham_zenith_x(turbidity, sun_zenith);
  s->zenith[SF_PREETHAM_Y_CHROMA] = sf_preetham_zenith_y(turbidity, sun_zenith);
  for (int q = 0; q < 3; ++q) {
    sf_preetham_coefficients(q, turbidity, s->coeffs[q]);
    s->f_zenith[q] = sf_perez_f(s->coeffs[q], 1.0, sun_zenith);
  }
}

void sf_preetham_sky_yxy(const sf_preetham_sky *s, double theta, double gamma, double yxy[3]) {
  double cos_theta = cos(theta);
  for (int q = 0; q < 3; ++q)
    yxy[q] = s->zenith[q] * sf_perez_f(s->coeffs[q], cos_theta, gamma) / s->f_zenith[q];
}

void sf_preetham_sky_rgb(const sf_preetham_sky *s, double theta, double gamma, double rgb[3]) {
  double yxy[3];
  sf_preetham_sky_yxy(s, theta, gamma, yxy);
  double Y = yxy[0], x = yxy[1], y = yxy[2];
  double xyz[3] = {x * Y / y, Y, (1.0 - x - y) * Y / y};
  for (int c = 0; c < 3; ++c)
    rgb[c] = xyz_to_srgb[c][0] * xyz[0] + xyz_to_srgb[c][1] * xyz[1] + xyz_to_srgb[c][2] * xyz[2];
}
