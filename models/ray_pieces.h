/* Splitting a ray segment into pieces on which every density is smooth:
 * at the ray's closest approach to the planet centre (where the radius, as a
 * function of distance, turns around) and wherever it crosses the sphere of a
 * density kink. Quadrature on each piece then converges at full order.
 *
 * And where it crosses the decay shells, altitudes 512 H 4^j (H the
 * smallest exponential scale height of any layer, j = 0, 1, ...) below the
 * top: in an atmosphere many scale heights deep, a piece from the ground
 * to the top puts every Gauss-Kronrod node where the density has long
 * vanished, and the adaptive rule, seeing zero and no error, stops (a
 * vertical Rayleigh depth of 7.946 for 8.000 with the top 1e5 km up).
 * From a shell 512 H up the piece's first node lies within ~1 H of its
 * low end. Earth's 100 km are below the first shell (614 km for the
 * Mie's 1.2 km): its rays are split as before. */
#ifndef SKYFIT_MODELS_RAY_PIECES_H
#define SKYFIT_MODELS_RAY_PIECES_H

#include "models/atmosphere.h"

#define SF_MAX_DECAY_SHELLS 12
#define SF_MAX_RAY_BREAKS (2 * SF_MAX_KINKS + 2 * SF_MAX_DECAY_SHELLS + 8)

/* Fills breaks with t0, the sorted split points strictly inside (t0, t1),
 * and t1; returns their count (>= 2). */
int sf_ray_breakpoints(const sf_atmosphere *atm, double r, double mu, double t0,
                       double t1, double *breaks);

/* Inserts t into the sorted breaks if strictly inside (breaks[0],
 * breaks[n-1]) and not already there; returns the new count. */
int sf_ray_breaks_insert(double *breaks, int n, double t);

#endif
