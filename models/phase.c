#include "models/phase.h"

#include <math.h>
#include <stddef.h>

#include "util/constants.h"

double sf_phase_rayleigh(double nu) { return 3.0 / (16.0 * SF_PI) * (1.0 + nu * nu); }

double sf_phase_isotropic(void) { return 1.0 / (4.0 * SF_PI); }

/* (1 + g^2 - 2 g nu)^{3/2}, written as k*sqrt(k) with k >= (1 - |g|)^2 > 0. */
static double hg_denominator(double g, double nu) {
  double k = 1.0 + g * g - 2.0 * g * nu;
  return k * sqrt(k);
}

/* seed 004 eq. 4, with the 1/(4 pi) that normalises it */
double sf_phase_henyey_greenstein(double g, double nu) {
  return (1.0 - g * g) / (4.0 * SF_PI * hg_denominator(g, nu));
}

/* seed 004 eq. 6; 3/(8 pi) (1-g^2)(1+nu^2) / ((2+g^2)(1+g^2-2g nu)^{3/2}) is
 * normalised for every |g| < 1 and is Rayleigh's at g = 0. */
double sf_phase_cornette_shanks(double g, double nu) {
  return 3.0 / (8.0 * SF_PI) * (1.0 - g * g) * (1.0 + nu * nu) /
         ((2.0 + g * g) * hg_denominator(g, nu));
}

/* seed 004 eq. 5 */
double sf_phase_double_henyey_greenstein(double g1, double g2, double f, double nu) {
  return (1.0 - f) * sf_phase_henyey_greenstein(g1, nu) + f * sf_phase_henyey_greenstein(g2, nu);
}

double sf_phase_value(const sf_phase *p, double nu) {
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH: return sf_phase_rayleigh(nu);
    case SF_PHASE_ISOTROPIC: return sf_phase_isotropic();
    case SF_PHASE_HENYEY_GREENSTEIN: return sf_phase_henyey_greenstein(p->g, nu);
    case SF_PHASE_CORNETTE_SHANKS: return sf_phase_cornette_shanks(p->g, nu);
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN:
      return sf_phase_double_henyey_greenstein(p->g1, p->g2, p->f, nu);
    case SF_PHASE_NONE: break;
  }
  return 0.0;
}

const char *sf_phase_kind_name(sf_phase_kind kind) {
  switch (kind) {
    case SF_PHASE_RAYLEIGH: return "rayleigh";
    case SF_PHASE_ISOTROPIC: return "isotropic";
    case SF_PHASE_HENYEY_GREENSTEIN: return "henyey_greenstein";
    case SF_PHASE_CORNETTE_SHANKS: return "cornette_shanks";
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: return "double_henyey_greenstein";
    case SF_PHASE_NONE: break;
  }
  return NULL;
}
