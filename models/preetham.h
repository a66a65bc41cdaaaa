/* The published Preetham, Shirley & Smits 1999 daylight model (Appendix 2;
 * ../shared/data/preetham1999.md; seed 000 eq. 33-34), as a baseline:
 * turbidity -> Perez coefficients of luminance Y and chromaticity x, y
 * (linear in T), zenith values (Y_z in kcd/m^2, x_z, y_z), and the sky
 *   Q(theta, gamma) = Q_z F_Q(theta, gamma) / F_Q(0, theta_s),  Q = Y, x, y.
 * Angles in radians: theta_s sun zenith, theta view zenith, gamma view-sun. */
#ifndef SKYFIT_MODELS_PREETHAM_H
#define SKYFIT_MODELS_PREETHAM_H

#include "models/perez.h"

enum { SF_PREETHAM_Y = 0, SF_PREETHAM_X = 1, SF_PREETHAM_Y_CHROMA = 2 };

/* The five Perez coefficients A..E of quantity q (SF_PREETHAM_*) at T. */
void sf_preetham_coefficients(int q, double turbidity, double out[SF_PEREZ_N_COEFFS]);
/* Zenith luminance Y_z (kcd/m^2) and chromaticities x_z, y_z. */
double sf_preetham_zenith_luminance(double turbidity, double sun_zenith);
double sf_preetham_zenith_x(double turbidity, double sun_zenith);
double sf_preetham_zenith_y(double turbidity, double sun_zenith);

/* Everything that depends only on (T, theta_s). */
typedef struct sf_preetham_sky {
  double turbidity, sun_zenith;
  double coeffs[3][SF_PEREZ_N_COEFFS];   /* Y, x, y */
  double zenith[3];                      /* Y_z, x_z, y_z */
  double f_zenith[3];                    /* F_Q(0, theta_s) */
} sf_preetham_sky;

void sf_preetham_sky_init(sf_preetham_sky *s, double turbidity, double sun_zenith);
/* Y (kcd/m^2), x, y in a view direction. */
void sf_preetham_sky_yxy(const sf_preetham_sky *s, double theta, double gamma, double yxy[3]);
/* The same as linear sRGB (kcd/m^2 scale): XYZ = (x Y / y, Y, (1-x-y) Y / y)
 * through the IEC 61966-2-1 XYZ -> linear sRGB (D65) matrix
 * (../shared/data/xyz_to_srgb.csv). */
void sf_preetham_sky_rgb(const sf_preetham_sky *s, double theta, double gamma, double rgb[3]);

#endif
