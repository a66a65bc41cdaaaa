/* Multiple scattering by scattering orders (SPEC §6; Bruneton & Neyret 2008,
 * Bruneton 2017 "ComputeScatteringDensity / ComputeIndirectIrradiance /
 * ComputeMultipleScattering"), ground albedo included. For order k >= 2:
 *
 *  1. Scattering density. At every point of the scattering grid, the light
 *     arriving from each direction w_i — the radiance of order k-1 seen
 *     along w_i (for k = 2: single scattering times each constituent's
 *     phase) plus, where w_i hits the ground, the ground's Lambertian
 *     reflection T(x -> ground) albedo/pi E_{k-2}(ground) (E_0: the sun's
 *     direct irradiance) — is convolved with each scattering constituent's
 *     phase function:  G_c(x, w) = integral of L_in(x, w_i) P_c(w . w_i) dw_i.
 *     The density of order k is J_k = sum_c beta_s,c density_c(x) G_c; the
 *     tables keep G_c, without the density, because G_c is smooth in
 *     altitude and density_c is applied exactly where J is used. G is
 *     sampled on the grid's mu positions with its own ground half, linear
 *     in mu (data/density_mu.h): G is smooth in the direction, where the
 *     grid's ground half, linear in the distance to the ground, is made
 *     for the radiance along a ray.
 *  2. Indirect irradiance of order k-1 on a horizontal surface, E_{k-1} =
 *     integral over the upper hemisphere of L_{k-1} cos(theta) dw: at the
 *     ground for the next order's ground term, and at every altitude for the
 *     irradiance table (Bruneton's irradiance texture: sum of orders 1..N-1,
 *     the direct sun excluded).
 *  3. Radiance of order k: L_k(x, v) = integral along the view ray of
 *     T(x -> p) J_k(p, v) dt.
 *
 * All orders are computed on an internal grid in Bruneton's
 * parameterisation at the output's scattering resolution over the full
 * domain (its horizon-aware mu keeps the sky/ground jump sharp in the
 * lookups of step 1); the output table is sum_k L_k at its own entries (for
 * a Leenman output or one restricted to a scene's domain, step 3 is done
 * once more at the output's entries with sum_k G_k, which is the same sum
 * since step 3 is linear).
 *
 * Quadrature: directions in step 1 are Gauss-Legendre in mu, split at the
 * horizon (SF_DENSITY_DIRS_UP above, SF_DENSITY_DIRS_DOWN below), times
 * SF_DENSITY_DIRS_PHI uniform azimuths; the sum is normalised by the same
 * quadrature of the phase function alone, so that forward-peaked phase
 * functions (Mie) conserve energy despite the coarse directions. The
 * azimuths matter most in daylight: with 16 (22.5 deg apart) the red
 * multiple scattering of a ground viewer looking at the horizon under a sun
 * 1-3 deg up came out 15-23 % below the path tracer's, as the sun's Mie
 * aureole fell between them; 32 bring it within 1-7 % (the path tracer's 2
 * sigma 4-6 %), 64 gain about a point more, 24 mu directions above the
 * horizon nothing (4M paths per point; default tables, 12 orders). Step 3
 * uses the view-ray nodes of data/ray_quadrature.h; lookups are
 * multilinear.
 *
 * Above the horizon the mu directions are two Gauss panels:
 * SF_DENSITY_DIRS_HORIZON of them within SF_DENSITY_HORIZON_BAND of the
 * horizon's mu (about 4.6 deg), the rest over the sky beyond. In the
 * planet's shadow all the light arriving at a point comes from the sunlit
 * air over the terminator, seen in a band 1-5 deg above the local horizon
 * towards the sun, 4-7 decades brighter than the zenith (40 km, sun -9.2
 * deg, blue single scattering: 4e-3 at 2 deg up, 1e-3 at 5, 2.7e-5 at 12,
 * 3.7e-9 at the zenith). One panel of 12 over the whole sky put one or two
 * nodes in that band, and order 2 came out 8-10 % bright in the blue (20
 * km, sun -8 deg: 5.01e-6 against 4.60e-6 from an independent quadrature of
 * exact single scattering and 4.58e-6 +- 0.04e-6 from the path tracer's
 * order 2; tests/test_multiple_order2_shadow.c), the sky there (all
 * orders) +8.5 % against the path tracer, now -0.2 %. At the same cost,
 * against 48 directions above the horizon, 12 below and 64 azimuths
 * (default tables, 7 orders, 1960 views at 0-50 km, ground albedo 0): RMS
 * error of the multiple scattering with the sun below the horizon, red /
 * green / blue, 2.3 / 3.1 / 5.2 % -> 1.4 / 0.5 / 0.6 % (red's rest is the
 * azimuths), the sun up 0.69 / 0.42 / 0.31 % -> 0.78 / 0.33 / 0.11 %; of
 * the bands tried (0.06-0.3 wide, 4-6 nodes) this one was best overall. */
#ifndef SKYFIT_DATA_PRECOMPUTE_MULTIPLE_H
#define SKYFIT_DATA_PRECOMPUTE_MULTIPLE_H

#include "data/precompute_options.h"
#include "data/scattering_setup.h"
#include "data/table.h"
#include "data/table_params.h"
#include "util/error.h"

#define SF_DENSITY_DIRS_UP 12
#define SF_DENSITY_DIRS_HORIZON 5         /* of the 12, within the band: */
#define SF_DENSITY_HORIZON_BAND 0.08      /* in mu above the horizon's */
#define SF_DENSITY_DIRS_DOWN 6
#define SF_DENSITY_DIRS_PHI 32
#define SF_IRRADIANCE_DIRS_MU 8
#define SF_IRRADIANCE_DIRS_PHI 16
#define SF_GROUND_IRRADIANCE_SAMPLES 256
#define SF_MULTIPLE_MAX_ORDERS 64

typedef struct sf_multiple_options {
  int orders;              /* highest order, >= 1 (1: no multiple scattering) */
  double stop_fraction;    /* > 0: stop after the first order k >= 3 after
                              which the orders left (the geometric tail of
                              the last two: report.remaining_fraction)
                              would add less than this fraction of the sky
                              radiance so far in every channel, and add the
                              orders after the last as that geometric tail;
                              0: exactly the orders up to `orders` */
} sf_multiple_options;

typedef struct sf_multiple_report {
  int highest_order;                           /* last order computed */
  double added_fraction[SF_MULTIPLE_MAX_ORDERS + 1];   /* [k], k >= 2: the
                  largest over the channels of order k's sum over the internal
                  grid divided by the sky radiance's (orders 1..k) */
  double order_total[SF_MULTIPLE_MAX_ORDERS + 1];      /* [k]: sum of L_k over
                                                          the internal grid and
                                                          the channels */
  double remaining_fraction[SF_MULTIPLE_MAX_ORDERS + 1];   /* [k], k >= 2: the
                  largest over the channels of what orders > k would add, as
                  a geometric tail (INFINITY for k = 2, or where the orders
                  do not shrink), over the sky radiance (orders 1..k) */
  double single_total;     /* the same sum of single scattering with phases */
  double ground_irradiance_total[SF_MULTIPLE_MAX_ORDERS + 1];  /* [k]: sum of
                                    E_k over the ground samples, k >= 1 */
} sf_multiple_report;

/* The internal grid's parameters for an output with parameters p: Bruneton
 * at p's scattering resolution (mu made even). */
void sf_multiple_internal_params(const sf_table_params *p, sf_table_params *internal);

/* single: s->n_scattering single-scattering tables on the internal grid
 * (sf_precompute_single with the internal parameters). Fills multiple
 * (initialised with sf_params_scattering_desc(p, atm, "multiple")) and
 * irradiance (sf_params_irradiance_desc); report may be NULL. */
int sf_precompute_multiple(const sf_scattering_setup *s, const sf_table_params *p,
                           const sf_table *single, const sf_multiple_options *mo,
                           const sf_precompute_options *opt, sf_table *multiple, sf_table *irradiance,
                           sf_multiple_report *report, sf_error *err);

#endif
