/* Splitting a ray segment into pieces on which every density is smooth:
 * at the ray's closest approach to the planet centre (where the radius, as a
 * function of distance, turns around) and wherever it crosses the sphere of a
 * density kink. Quadrature on each piece then converges at full order. */
#ifndef SKYFIT_MODELS_RAY_PIECES_H
#define SKYFIT_MODELS_RAY_PIECES_H

#include "models/atmosphere.h"

#define SF_MAX_RAY_BREAKS (2 * SF_MAX_KINKS + 8)

/* Fills breaks with t0, the sorted split points strictly inside (t0, t1),
 * and t1; returns their count (>= 2). */
int sf_ray_breakpoints(const sf_atmosphere *atm, double r, double mu, double t0,
                       double t1, double *breaks);

/* Inserts t into the sorted breaks if strictly inside (breaks[0],
 * breaks[n-1]) and not already there; returns the new count. */
int sf_ray_breaks_insert(double *breaks, int n, double t);

#endif
