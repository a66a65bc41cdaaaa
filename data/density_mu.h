/* Where the multiple-scattering density G (data/precompute_multiple.h,
 * step 1) is sampled in the view cosine mu on its ground half: linearly in
 * mu, from the local horizon (x = 1) to straight down (x = 0), at the
 * positions Bruneton's ground half uses (pos = (n/2 - 1)(1 - x),
 * data/table_params.h). The sky half keeps Bruneton's mapping.
 *
 * Why not Bruneton's: his ground-half x is linear in the distance to the
 * ground, d ~ h / |mu| for a low point, which suits the radiance L (a ray
 * integral, about proportional to d) but not G, a phase-convolved angular
 * average that varies smoothly with mu. Near the ground his first interval
 * spans most of the downward directions (0.25 km up: mu -1 to -0.22; 1 km:
 * -1 to -0.36), and G interpolated linearly in d there is read as if the
 * ray were far steeper than it is: the gather of step 3 along a ray from 10
 * km looking down (mu -0.7, default atmosphere, default tables, order 2
 * alone) came out -2.8 % (blue) against an independent quadrature of
 * order 2 (tests/order2_reference.h), -0.9 % with this mapping. */
#ifndef SKYFIT_DATA_DENSITY_MU_H
#define SKYFIT_DATA_DENSITY_MU_H

/* mu of the ground-half unit coordinate x in [0, 1] at altitude h (km above
 * the bottom radius R), and back (x clamped into [0, 1]). */
double sf_density_mu_ground_from_x(double R, double h, double x);
double sf_density_x_from_mu_ground(double R, double h, double mu);

#endif
