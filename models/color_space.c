#include "models/color_space.h"

#include <math.h>

/* IEC 61966-2-1 (sRGB), data/physical/xyz_to_srgb.csv */
const double sf_xyz_to_linear_srgb_matrix[3][3] = {
    {3.2406, -1.5372, -0.4986},
    {-0.9689, 1.8758, 0.0415},
    {0.0557, -0.2040, 1.0570},
};

static void mat3_apply(const double m[3][3], const double v[3], double out[3]) {
  double r[3];
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  for (int i = 0; i < 3; ++i) out[i] = r[i];
}

void sf_linear_srgb_to_xyz_matrix(double inv[3][3]) {
  const double (*m)[3] = sf_xyz_to_linear_srgb_matrix;
  double c[3][3]; /* cofactors */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      c[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
    }
  double det = m[0][0] * c[0][0] + m[0][1] * c[0][1] + m[0][2] * c[0][2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) inv[i][j] = c[j][i] / det;
}

void sf_xyz_to_linear_srgb(const double xyz[3], double rgb[3]) {
  mat3_apply(sf_xyz_to_linear_srgb_matrix, xyz, rgb);
}

void sf_linear_srgb_to_xyz(const double rgb[3], double xyz[3]) {
  double inv[3][3];
  sf_linear_srgb_to_xyz_matrix(inv);
  mat3_apply((const double(*)[3])inv, rgb, xyz);
}

void sf_srgb_white_xyz(double white[3]) {
  const double one[3] = {1.0, 1.0, 1.0};
  sf_linear_srgb_to_xyz(one, white);
}

/* CIE 15:2004 eq. 8.3: delta = 6/29 */
static double lab_f(double t) {
  const double delta = 6.0 / 29.0;
  if (t > delta * delta * delta) return cbrt(t);
  return t / (3.0 * delta * delta) + 4.0 / 29.0;
}

void sf_xyz_to_lab(const double xyz[3], const double white_xyz[3], double lab[3]) {
  double fx = lab_f(xyz[0] / white_xyz[0]);
  double fy = lab_f(xyz[1] / white_xyz[1]);
  double fz = lab_f(xyz[2] / white_xyz[2]);
  lab[0] = 116.0 * fy - 16.0;
  lab[1] = 500.0 * (fx - fy);
  lab[2] = 200.0 * (fy - fz);
}

void sf_linear_lab(const double linear_srgb[3], double lab[3]) {
  double xyz[3], white[3];
  sf_linear_srgb_to_xyz(linear_srgb, xyz);
  sf_srgb_white_xyz(white);
  sf_xyz_to_lab(xyz, white, lab);
}

void sf_display_lab(const double linear_srgb[3], double exposure, double lab[3]) {
  double shown[3];
  /* seed 000 §11.5: t(x) = 1 - exp(-x); -expm1 keeps small values exact */
  for (int i = 0; i < 3; ++i) shown[i] = -expm1(-exposure * linear_srgb[i]);
  sf_linear_lab(shown, lab);
}

double sf_standard_exposure(double sun_elevation_deg, int viewer_in_space) {
  if (sun_elevation_deg < 0.0) return 16.0;
  return viewer_in_space ? 2.0 : 1.0;
}
