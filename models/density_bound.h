/* Guaranteed upper bounds of a constituent's density over an altitude range:
 * the majorants that make delta and ratio tracking exact (a majorant below
 * the true extinction anywhere would bias the path tracer). */
#ifndef SKYFIT_MODELS_DENSITY_BOUND_H
#define SKYFIT_MODELS_DENSITY_BOUND_H

#include "models/atmosphere.h"

/* max of sf_constituent_density(c, h) over h in [h_lo, h_hi] (h_hi may be
 * INFINITY). Exact up to rounding: within one layer the profile
 * exp_term*exp(s h) + linear*h + constant is convex or concave, so its
 * maximum lies at an end of the range, at a layer boundary, or at its one
 * stationary point; the clamp to [0, 1] is monotone and is applied last. */
double sf_constituent_max_density(const sf_constituent *c, double h_lo, double h_hi);

#endif
