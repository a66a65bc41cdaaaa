/* Reference single scattering (SPEC §6), Bruneton's convention: radiance
 * without the phase function,
 *   E_sun * beta_s * integral of density(p) T(viewer -> p) T(p -> sun) ds
 * along the view ray, per scattering constituent and channel; T(p -> sun) is 0
 * where the planet hides the sun (its shadow). The sun is a point source. */
#ifndef SKYFIT_MODELS_SINGLE_SCATTERING_H
#define SKYFIT_MODELS_SINGLE_SCATTERING_H

#include "models/atmosphere.h"
#include "models/view_ray.h"

#define SF_SINGLE_SCATTERING_REL_TOL 1e-7

/* The sun direction of a query: clamps nu into the range mu and mu_s allow
 * (SPEC §3) and returns the clamped value. */
double sf_clamp_nu(double mu, double mu_s, double nu);

/* out[i * n_channels + ch] for every constituent i (0 for those that do not
 * scatter), over the stretch of view ray ray. */
void sf_single_scattering(const sf_atmosphere *atm, const sf_view_ray *ray, double mu_s,
                          double nu, double *out);

/* Same with an explicit relative tolerance for the outer integral. */
void sf_single_scattering_tol(const sf_atmosphere *atm, const sf_view_ray *ray,
                              double mu_s, double nu, double rel_tol, double *out);

#endif
