/* Leenman's flat / DR-1 optical depth (seed 000 §10.2-10.5, eq. 48-53, 59;
 * SPEC §7.6). An exponential constituent d0*exp(-h/H) seen from a point at
 * radius rho is replaced by a homogeneous shell of thickness H above that
 * point, filled with the point's density (eq. 51):
 *   tau_up(rho, cos) = d0 exp(-h/H) (sqrt((rho + H)^2 - rho^2 + rho^2 cos^2)
 *                                    - rho cos),             cos >= 0,
 * exact for vertical rays (H d0 exp(-h/H)), 2/sqrt(pi) = 12.8 % high for
 * horizontal ones (sqrt(2 rho H) against the Chapman sqrt(pi rho H / 2)).
 * Looking down (eq. 53, written with the point's radius and density):
 *   tau_down(rho, cos) = 2 tau_up(rho, 0) - tau_up(rho, -cos),  cos < 0.
 * A segment is a difference of two such values in the same direction, except
 * where the ray's line hits the ground: there both ends are taken in the
 * reversed direction with the ground point as the midpoint (seed 000
 * §11.3.3), tau_up(b, reversed) - tau_up(a, reversed), which is exact for
 * vertical rays; eq. 53 on such lines would subtract two huge columns.
 *
 * Any other (non-exponential) constituent, e.g. the ozone tent, becomes a
 * shell of density 1 (seed 000 §10.5, eq. 59) centred at the
 * density-weighted mean altitude with the width equal to the column
 * integral of the density over altitude (the default tent gives exactly
 * 17.5-32.5 km); its optical depth is the exact chord of the segment inside
 * that shell. */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_FLAT_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_FLAT_H

#include "models/atmosphere.h"

/* How a segment through the line's closest approach P (a ray that passes
 * below its start's horizontal but misses the ground) is estimated. */
typedef enum sf_flat_descent {
  /* seed 000 eq. 53 as written, at the segment's start a (its radius and
   * density): tau_down(a) - tau_up(b), and tau_down(a) - tau_down(b) for a
   * segment that ends before P. Under-counts the denser air near P; a
   * segment wholly before P can come out negative and is clamped to 0. */
  SF_FLAT_DESCENT_VIEWER = 0,
  /* eq. 53 with the closest point c as the midpoint: 2 tau_up(c, 0)
   * - tau_up(a, reversed) - tau_up(b); pieces before P reversed. Continuous
   * in both ends and never negative. */
  SF_FLAT_DESCENT_CLOSEST
} sf_flat_descent;

/* What the flat model needs besides the atmosphere: the shells of the
 * non-exponential constituents (altitudes in km above the bottom radius). */
typedef struct sf_flat_model {
  sf_flat_descent descent;
  int is_shell[SF_MAX_CONSTITUENTS];
  double shell_bottom_km[SF_MAX_CONSTITUENTS];
  double shell_top_km[SF_MAX_CONSTITUENTS];
} sf_flat_model;

/* seed 000 eq. 51: tau_up of exp(-h/H) (d0 = 1) from radius rho along upward
 * zenith cosine cos_up >= 0, in km. */
double sf_flat_tau_up(double bottom_radius, double scale_height_km, double rho,
                      double cos_up);
/* seed 000 eq. 53 at radius rho looking down along cos_down < 0, in km. */
double sf_flat_tau_down(double bottom_radius, double scale_height_km, double rho,
                        double cos_down);

/* The shell replacing a non-exponential density (seed 000 §10.5): mean
 * altitude +- half the column. Integrates the profile over [0, thickness],
 * split at the atmosphere's kinks. */
void sf_flat_shell_of(const sf_atmosphere *atm, int constituent, double *bottom_km,
                      double *top_km);

/* Fills model for atm (every non-exponential constituent gets its shell). */
void sf_flat_model_make(const sf_atmosphere *atm, sf_flat_descent descent,
                        sf_flat_model *model);

/* Density integral (km) of exp(-h/H) over t in [t0, t1] along the ray (r, mu),
 * the segment first restricted to the air as the reference does. */
double sf_flat_exponential_segment(double bottom_radius, double top_radius,
                                   double scale_height_km, sf_flat_descent descent,
                                   double r, double mu, double t0, double t1);

/* Length (km) of t in [t0, t1] along the ray (r, mu) where the radius is
 * between shell_bottom and shell_top (radii from the planet centre). */
double sf_flat_shell_chord(double shell_bottom_radius, double shell_top_radius,
                           double r, double mu, double t0, double t1);

/* Density integral (km) of each constituent over t in [t0, t1] along the ray
 * (r, mu); out has atm->n_constituents entries. Every constituent is
 * handled: returns atm->n_constituents. */
int sf_optical_depth_flat_segment(const sf_atmosphere *atm, double r, double mu,
                                  double t0, double t1, const sf_flat_model *model,
                                  double *out);

/* The same along the ray's line, the planet ignored: [t0, t1] clipped to
 * the top sphere only, so a line grazing or just crossing the ground gets
 * the column through its closest approach, continuous in mu across the
 * horizon (models/sky_raymarched.h: the sun's column at the shadow's
 * edge). A rising or through-P segment only (from a point to the top). */
int sf_optical_depth_flat_line_segment(const sf_atmosphere *atm, double r, double mu, double t0, double t1,
                                       const sf_flat_model *model, double *out);

#endif
