/* The ground-level sky fit of SPEC §7.2 for a whole sun range: Perez
 * ("preetham") or Hosek coefficients per sun elevation and channel, fitted
 * to the reference sky radiance from the tables, then their dependence on
 * elevation fitted Hosek's way (a quintic Bezier in (elevation/(pi/2))^(1/3),
 * 6 control points per coefficient and for the scale,
 * models/hosek_sky_model.h), so one model covers the scene's sun range.
 *
 * 1. Samples: n_elevations suns, equally spaced in x = (e/(pi/2))^(1/3)
 *    over [e_min, e_max] (e_min >= 0: Perez and Hosek hold only for a sun
 *    above the horizon), each a grid of view directions
 *    (fit/sky_radiance_samples.h). Residuals are normalised per elevation
 *    and channel by the RMS reference radiance there, so low suns count as
 *    much as high ones.
 * 2. Per elevation and channel (fit/fit_sky_config.h), a multi-start:
 *    the published set (Hosek 2012 dataset, resp. Preetham 1999 luminance
 *    coefficients) at turbidities 2, 4 and 7 with its linear part rescaled
 *    to the data, and the previous elevation's solution. The lowest final
 *    cost wins; the report counts which start won. Hosek's scale R is held
 *    at the reference zenith radiance (it is degenerate with C, D, F, G, I);
 *    Perez's K is free.
 * 3. Bezier control points: one Ceres fit of all control points of a
 *    channel against the radiance samples of 3 n_elevations - 2 suns, the
 *    fit suns and two between each neighbouring pair (equal steps in x, a
 *    third of step 1's: SF_SKY_CURVE_STEPS), normalised as in step 1,
 *    given to Ceres as their Gram matrix (fit/sky_bezier_gram.h: the same
 *    bits on any CPU; Hosek's R curve is held at its least-squares fit
 *    to the zenith radiances), from
 *    four starts: the linear least-squares curve through the per-elevation
 *    values, and constant curves holding the values of the elevations at
 *    1/4, 1/2 and 3/4 of the range (the first can swing far off between
 *    the elevations it passes through; the report counts the winners).
 *    Bounds on the control points (models' physical bounds) bound the curve
 *    (a Bezier curve lies in the convex hull of its control points).
 *    Why suns between the fit suns: at the fit suns alone nothing held the
 *    curves between them. A sun's fit has nearly flat directions (Hosek's
 *    A near -1 against C, D, F, I near +-100), along which the control
 *    points moved freely; with few suns (6 suns: 6 values for 6 control
 *    points each) the curves then swung between the suns, Hosek's E above
 *    7 where the suns had it near 0, and D e^(E gamma) grew e^(7 pi) over
 *    the sky. On small tables (tests/small_sky_tables.h) Hosek at 6, 7 and
 *    11 suns had RMSE 3.5, 0.58 and 0.024 (published Hosek 0.0042), and
 *    6e6 at 6 suns on an 8 x 12 view grid; with the suns between, 0.0013,
 *    0.0012, 0.00099 and 0.0015 (tests/test_sky_elevation_few_suns.c). On
 *    the default tables Hosek 0.000976 -> 0.000973, Preetham 0.00183 ->
 *    0.00180, for 1.4 and 1.3 times the fit's time. Step 4's held-out suns
 *    (the midpoints) are none of step 3's. Bounding Hosek's E to <= 0
 *    instead (e^(E gamma) <= 1 on the whole curve) stopped the blow-up
 *    but not the swings, and cost the default fit 2 % and some small-table
 *    fits 3x.
 * 4. Metrics over the domain: RMSE (relative, normalised as in step 1)
 *    at each fit elevation and, held out, at the midpoints in x between
 *    them, over view zenith angles at the midpoints of 4 n_theta equal
 *    steps of [0, 90] deg (the fit's rows stop short of the horizon), the
 *    RMSE at the held-out elevations alone, the largest error over those
 *    and the horizon band (mu 0.03 down to 1e-4), and the published
 *    baselines on the same grid:
 *    Preetham 1999 (in linear sRGB) and Hosek 2012 RGB, each at its best
 *    turbidity (scan) with its best per-channel scale factor (closed form)
 *    to map its units onto ours — the most favourable reading of them. */
#ifndef SKYFIT_FIT_FIT_SKY_ELEVATION_H
#define SKYFIT_FIT_FIT_SKY_ELEVATION_H

#include "data/sky_lookup.h"
#include "fit/ceres_shim.h"
#include "fit/sky_bezier_gram.h"
#include "models/hosek_dataset.h"
#include "models/hosek_sky_model.h"
#include "util/error.h"

#define SF_SKY_MAX_ELEVATIONS 64
/* Step 3's suns per step between neighbouring fit suns (see there). */
#define SF_SKY_CURVE_STEPS 3
#define SF_SKY_MAX_STARTS 4

/* Step 3's iteration cap. Where a control point's best value lies on its
 * bound (Hosek's H at 0.999, Perez's B at 0), Ceres' Levenberg-Marquardt
 * step leaves the box and is clipped back onto it, so a step gains a fixed
 * fraction rho of what its model predicts (0.23 and 0.08 on the default
 * tables) and every successful step shrinks the trust region by
 * 1 / max(1/3, 1 - (2 rho - 1)^3) (1.16, 1.59): the cost falls
 * geometrically until |d cost| / cost < function_tolerance. On
 * skyfit-tables 7, at 200 the default build's Preetham b and Hosek g
 * stopped in that tail, 18 and 39 steps short of convergence (their costs
 * 1e-10 and 3.5e-5 relative above the converged ones), and the full-range
 * tables' Hosek r and g needed 359 and 743 (cost 20.376 -> 20.045); on
 * skyfit-tables 8 the default build's Hosek needs 520 (RMSE 0.000974 ->
 * 0.000965). 5000 gave the same fits. */
#define SF_SKY_ELEVATION_FIT_MAX_ITERATIONS 1000

typedef struct sf_sky_elevation_options {
  sf_sky_form form;
  double elevation_min_rad, elevation_max_rad;
  int n_elevations;          /* >= 6 (the curve has 6 control points); default
                                19: with 10, the curves swung between the fit
                                elevations (Mars' sky 0.0015 RMSE at them, 0.017
                                on random suns, green at 80 deg; 0.0022 with 19,
                                on the tables of the time) */
  int n_theta, n_phi;        /* view grid per elevation; default 16 x 24 */
  sf_lsq_options lsq;         /* steps 2 and 3 */
  int elevation_fit_max_iterations;   /* step 3's cap, in place of lsq's
                                (SF_SKY_ELEVATION_FIT_MAX_ITERATIONS) */
  void (*progress)(void *ctx, const char *stage, double fraction);
  void *progress_ctx;
} sf_sky_elevation_options;

void sf_sky_elevation_options_default(sf_sky_elevation_options *o, sf_sky_form form);
/* The e-th of o's n_elevations suns (step 1): equal steps in x = (e /
 * (pi/2))^(1/3) from elevation_min_rad to elevation_max_rad; *x its x. */
double sf_sky_fit_elevation(const sf_sky_elevation_options *o, int e, double *x);
/* The c-th of step 3's SF_SKY_CURVE_STEPS (n_elevations - 1) + 1 suns:
 * equal steps in x over the same range, a third of step 1's; c = 3 e is
 * fit sun e (the same bits); *x its x. */
double sf_sky_curve_elevation(const sf_sky_elevation_options *o, int c, double *x);

typedef struct sf_sky_elevation_report {
  int n_elevations, n_channels, n_samples;   /* n_samples: step 2's per channel */
  int n_curve_elevations;                    /* step 3's suns: 3 n_elevations - 2 */
  long n_metric_samples;                     /* step 4's grid */
  int n_metric_elevations;                   /* step 4's: 2 n_elevations - 1 */
  double elevation_rad[SF_SKY_MAX_ELEVATIONS];
  int n_starts;
  char start_names[SF_SKY_MAX_STARTS][32];
  int start_wins[SF_SKY_MAX_STARTS];      /* over all elevations and channels */
  int winner[SF_SKY_MAX_ELEVATIONS][SF_MAX_CHANNELS];
  double per_elevation_rmse;     /* the step-2 fits, before the Bezier */
  double rmse, rel_rmse, normalised_rmse, max_abs;   /* the final model */
  double held_out_rmse;          /* at step 4's held-out elevations alone */
  double worst_elevation_rad, worst_theta, worst_gamma;
  double global_initial_cost, global_final_cost;   /* summed over channels */
  int global_iterations;
  double global_initial_cost_channel[SF_MAX_CHANNELS];
  int global_iterations_channel[SF_MAX_CHANNELS];
  /* the kept start's fit stopped without converging (Ceres'
   * NO_CONVERGENCE: at elevation_fit_max_iterations, in practice; a usable
   * result), and how it stopped (a kept start is never SF_LSQ_FAILURE) */
  int global_at_cap_channel[SF_MAX_CHANNELS];
  sf_lsq_termination global_termination_channel[SF_MAX_CHANNELS];
  int global_channels_at_cap, global_max_iterations;
  /* which start of the elevation fit won: 0 the curve through the
   * per-elevation fits, 1..3 constant curves from elevations n/4, n/2, 3n/4 */
  int global_start_wins[4];
  double preetham_rmse, preetham_turbidity;      /* NAN unless 3 channels */
  double hosek_published_rmse, hosek_published_turbidity;
  double seconds;
} sf_sky_elevation_report;

/* published: the Hosek dataset (starts for Hosek, baseline for both); may
 * be NULL (Hosek then starts from its Perez-like default, no baseline).
 * rep is large: allocate it. */
int sf_fit_sky_elevation(const sf_sky_tables *sky, const sf_sky_elevation_options *o,
                         const sf_hosek_dataset *published, sf_elevation_sky_model *out,
                         sf_sky_elevation_report *rep, sf_error *err);

#endif
