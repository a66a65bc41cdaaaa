#include "models/sun_shadow.h"

#include <math.h>

sf_sun_line sf_sun_line_make(double r, double mu, double mu_s, double nu, double rho) {
  sf_sun_line line;
  line.a = (1.0 - nu) * (1.0 + nu);
  line.b = 2.0 * r * (mu - mu_s * nu);
  line.c = (r - rho) * (r + rho) - r * r * mu_s * mu_s;
  line.r_mu_s = r * mu_s;
  line.nu = nu;
  return line;
}

double sf_sun_line_clearance(const sf_sun_line *line, double t) { return (line->a * t + line->b) * t + line->c; }

int sf_sun_line_hidden(const sf_sun_line *line, double t) {
  return line->r_mu_s + t * line->nu < 0.0 && sf_sun_line_clearance(line, t) < 0.0;
}

int sf_sun_line_tangent_distances(const sf_sun_line *line, double out[2]) {
  double a = line->a, b = line->b, c = line->c;
  if (a == 0.0) {   /* nu = +-1: the sun line is the view line */
    if (b == 0.0) return 0;
    out[0] = -c / b;
    return 1;
  }
  double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return 0;
  /* the large root from q, the small one as c / q (Numerical Recipes 5.6) */
  double q = -0.5 * (b + (b >= 0.0 ? sqrt(disc) : -sqrt(disc)));
  int n = 0;
  out[n++] = q / a;
  if (q != 0.0) out[n++] = c / q;
  return n;
}
