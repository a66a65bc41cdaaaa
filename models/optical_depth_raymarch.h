/* N-step raymarched optical depth (SPEC §7.6 "naive" baseline): the density
 * integral along a ray segment by the composite midpoint rule (seed 000's
 * naive model, §11.2.6 / §11.3.1 use a Riemann sum) or the composite
 * trapezoid rule (seed 000 §5 Nishita/O'Neil, seed 002 §III, seed 004). Works
 * for every density profile; converges as 1/N^2 where the density is smooth
 * along the segment and as 1/N across kinks or jumps. */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_RAYMARCH_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_RAYMARCH_H

#include "models/atmosphere.h"

typedef enum sf_raymarch_rule {
  SF_RAYMARCH_MIDPOINT = 0,   /* N samples at the centres of N equal steps */
  SF_RAYMARCH_TRAPEZOID       /* N + 1 samples at the step ends, ends halved */
} sf_raymarch_rule;

/* Density integral (km) of each constituent over t in [t0, t1] along the ray
 * (r, mu), with the segment first restricted to the air (nothing above the
 * top radius, nothing past the ground) and then cut into `steps` equal steps.
 * out has atm->n_constituents entries. Returns atm->n_constituents, or 0 with
 * every entry NAN when steps < 1 or the rule is unknown. */
int sf_optical_depth_raymarch_segment(const sf_atmosphere *atm, double r, double mu,
                                      double t0, double t1, int steps,
                                      sf_raymarch_rule rule, double *out);

#endif
