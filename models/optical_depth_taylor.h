/* Gałaj's Taylor-formula transmittance approximation (seed 002 §IV.F,
 * eq. 12-17; SPEC §7.6 with a = b = 0.45) as an optical-depth model. For an
 * exponential constituent d0*exp(-h/H), the density integral from the ray's
 * closest approach P_O outwards is approximated by replacing the altitude
 * h(t) = sqrt(d^2 + t^2) - r along the line (d its distance from the centre,
 * t the distance from P_O) with its Taylor expansion of order 1 + a about
 * tau_b = t_min + b (t_max - t_min), and the Jacobian by its value there.
 * Segments combine two such integrals (eq. 13: P_O between the ends, a sum;
 * eq. 14: both ends on one side, a difference). Other constituents: NAN.
 *
 * Degenerate cases and what this code does:
 * - d = 0 (vertical rays): the kink of h(t) = |t| - r is at the planet's
 *   centre, never on a segment (t_min = r > 0); h' = 1, h'' = 0 there and the
 *   formula is exact: H (1 - exp(-dh/H)).
 * - h'(tau_b) = 0 needs tau_b = 0, i.e. t_max = 0 (the line only touches the
 *   top sphere: no segment is left) or b = 0 (rejected: b must be in (0, 1]).
 *   Should it still happen, the piece falls back to length * density at
 *   tau_b (the exact limit for a vanishing piece) instead of dividing by 0.
 * - Rays from space, or parts above the top: the segment is first clipped to
 *   the air (|t| <= t_max), as the reference does; ends are clamped into
 *   [t_min, t_max] against rounding.
 * - Overflow: for lines that miss the ground (t_min = 0) h~(t_min) is about
 *   -(1 - a) tau_b^2 / (2 d) < 0, so exp(-h~/H) grows like
 *   exp((1 - a) b^2 (R - r) / H): 4x for Earth's Rayleigh layer, 1e4x for Mie,
 *   past the double range for H below about 0.016 km. A piece that is not
 *   finite is replaced by its exact upper bound, length * the density at the
 *   end nearer P_O; finite values are left as the formula gives them.
 * - Differences of nearly equal exponentials are formed with expm1 of the
 *   exact difference of the two expanded altitudes, so short pieces keep
 *   their relative precision.
 * With a in [0, 1] the expanded altitude increases on [t_min, t_max]
 * (its vertex lies at t <= 0), so every piece is >= 0.
 * Near the horizon the published formula itself fails (README, limitations):
 * on a line grazing the ground tau_b lies ~509 km out and h~(t_min) is
 * -(1 - a) tau_b^2 / (2d) ~ -11 km, so the Mie column comes out 1.6e3-5e3x
 * and the Rayleigh column 1.4-2.2x the exact one; T ~ 0 where the reference
 * has 0.655 (10 m up). That is eq. 17 with a = b = 0.45, kept as published. */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_TAYLOR_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_TAYLOR_H

#include "models/atmosphere.h"

/* seed 002 §VI: the grid-searched expansion order and point (SPEC §7.6). */
#define SF_TAYLOR_A 0.45
#define SF_TAYLOR_B 0.45

/* Density integral (km) of exp(-h/H) over t in [t0, t1] along the ray (r, mu)
 * with r = bottom_radius and R = top_radius in eq. 12. Returns NAN when a is
 * outside [0, 1] or b outside (0, 1]. */
double sf_taylor_exponential_segment(double bottom_radius, double top_radius,
                                     double scale_height_km, double a, double b,
                                     double r, double mu, double t0, double t1);

/* Density integral (km) of each constituent over t in [t0, t1] along the ray
 * (r, mu); out has atm->n_constituents entries. Returns the number of
 * exponential constituents; the others (and all, for a bad a or b) get NAN. */
int sf_optical_depth_taylor_segment(const sf_atmosphere *atm, double r, double mu,
                                    double t0, double t1, double a, double b,
                                    double *out);

#endif
