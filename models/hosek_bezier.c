#include "models/hosek_bezier.h"

#include <math.h>

#include "util/constants.h"

double sf_bezier_x_of_elevation(double elevation_rad) {
  double e = elevation_rad < 0.0 ? 0.0 : elevation_rad > 0.5 * SF_PI ? 0.5 * SF_PI : elevation_rad;
  return cbrt(e / (0.5 * SF_PI));
}

void sf_bezier_weights(double x, double w[SF_BEZIER_POINTS]) {
  double u = 1.0 - x;
  double x2 = x * x, u2 = u * u;
  w[0] = u2 * u2 * u;
  w[1] = 5.0 * u2 * u2 * x;
  w[2] = 10.0 * u2 * u * x2;
  w[3] = 10.0 * u2 * x2 * x;
  w[4] = 5.0 * u * x2 * x2;
  w[5] = x2 * x2 * x;
}

double sf_bezier_eval(const double *p, int stride, double x) {
  double w[SF_BEZIER_POINTS];
  sf_bezier_weights(x, w);
  double sum = 0.0;
  for (int j = 0; j < SF_BEZIER_POINTS; ++j) sum += w[j] * p[j * stride];
  return sum;
}
