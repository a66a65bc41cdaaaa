/* Reference optical depth (SPEC §6): the integral of each constituent's
 * density along a ray segment, in km. Multiply by a constituent's extinction
 * for its optical thickness. Computed by adaptive Gauss-Kronrod quadrature
 * on pieces split at the ray's closest approach to the planet centre and
 * wherever the ray crosses a density kink, so every piece is smooth. */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_H

#include "models/atmosphere.h"

/* Relative tolerance the reference aims for per constituent; the tests hold
 * it to 1e-9 against an independent integrator. */
#define SF_OPTICAL_DEPTH_REL_TOL 1e-11
/* Absolute density resolution the quadrature stops at (see optical_depth.c). */
#define SF_DENSITY_RESOLUTION 1e-13

typedef enum sf_ray_end {
  SF_RAY_END_NEAREST = 0,   /* the ground if the ray hits it, else the top */
  SF_RAY_END_TOP            /* the top boundary; the ray must not hit the ground */
} sf_ray_end;

/* Density integral of every constituent over t in [t0, t1] along the ray
 * (r, mu); out has atm->n_constituents entries. Parts of the segment above the
 * top radius contribute nothing. The segment must not pass below the ground. */
void sf_optical_depth_segment(const sf_atmosphere *atm, double r, double mu,
                              double t0, double t1, double *out);

/* Same, with an explicit relative tolerance (for callers that need less). */
void sf_optical_depth_segment_tol(const sf_atmosphere *atm, double r, double mu,
                                  double t0, double t1, double rel_tol, double *out);

/* From the viewer at altitude h (km above the bottom; may be above the top)
 * along mu to the ray's end. Viewers outside the atmosphere start where the
 * ray enters it; a ray that never enters gives zeros. Returns 0, or -1 if
 * end is SF_RAY_END_TOP and the ray hits the ground first. */
int sf_optical_depth_ray(const sf_atmosphere *atm, double h_km, double mu,
                         sf_ray_end end, double *out);

/* Transmittance per channel exp(-sum_i extinction_i * depth_i). */
void sf_transmittance_from_depth(const sf_atmosphere *atm, const double *depth,
                                 double *transmittance);

#endif
