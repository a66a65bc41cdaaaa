/* Schuler's approximation of the Chapman function (seed 000 eq. 22-25,
 * Schuler 2012) as an optical-depth model (SPEC §7.6): the column of an
 * exponential constituent d0*exp(-h/H) from a point to infinity is
 * H * d0 * tau_Ch, with tau_Ch of seed 000 eq. 24 (written in units of the
 * scale height, c = sqrt(x), x = radius / H, eq. 25). A segment is the
 * difference of two such rays in the same direction. Only exponential
 * constituents (sf_constituent_exponential); others get NAN.
 *
 * Known accuracy (derived in tests/test_optical_depth_approx.c): straight up
 * tau_Ch = c/(1+c), i.e. low by 1/(1+sqrt(x)) (3.4 % for Earth's Rayleigh
 * layer, 1.4 % for Mie); horizontal tau_Ch = c = sqrt(x), while the true
 * Chapman function there is sqrt(pi x / 2) (1 + 3/(8x) + ...), i.e. low by
 * 1 - sqrt(2/pi) = 20.2 % (25 % at worst, a few degrees off the horizon). */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_CHAPMAN_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_CHAPMAN_H

#include "models/atmosphere.h"

/* seed 000 eq. 24, first case: tau_Ch of the ray from radius `radius` along
 * upward zenith cosine cos_up >= 0 to infinity, in units of H times the
 * density at bottom_radius (multiply by H * d0 for km). */
double sf_chapman_tau_up(double bottom_radius, double scale_height_km, double radius,
                         double cos_up);

/* Density integral (km) of exp(-h/H) over t in [t0, t1] along the ray
 * (r, mu), the segment first restricted to the air as the reference does.
 * Rising pieces are tau_Ch(a) - tau_Ch(b); falling pieces are taken in the
 * reversed direction (seed 000 §5 after O'Neil 2004: both reversed rays look
 * up); a piece through the closest approach P uses eq. 24's second case,
 * 2 sqrt(x0) exp(r/h0 - x0) - tau_Ch(a reversed), minus tau_Ch(b). */
double sf_chapman_exponential_segment(double bottom_radius, double top_radius,
                                      double scale_height_km, double r, double mu,
                                      double t0, double t1);

/* Density integral (km) of each constituent over t in [t0, t1] along the ray
 * (r, mu); out has atm->n_constituents entries. Returns the number of
 * exponential constituents; the others get NAN. */
int sf_optical_depth_chapman_segment(const sf_atmosphere *atm, double r, double mu,
                                     double t0, double t1, double *out);

#endif
