/* The analytic optical-depth baselines of SPEC §7.6 as emitted transmittance
 * models: functions of the atmosphere alone, no weights file.
 *  - naive:   N-step midpoint raymarch of every constituent's density
 *             (models/optical_depth_raymarch.h, SF_RAYMARCH_MIDPOINT);
 *  - chapman: Schuler's Chapman approximation, seed 000 eq. 22-25
 *             (models/optical_depth_chapman.h);
 *  - taylor:  Gałaj's Taylor transmittance, seed 002 eq. 17, a = b = 0.45
 *             (models/optical_depth_taylor.h);
 *  - flat:    Leenman's flat / DR-1 model, seed 000 §10.2-10.5, eq. 51, 53, 59
 *             and §11.3.3 (models/optical_depth_flat.h, SF_FLAT_DESCENT_CLOSEST:
 *             a descending ray's eq. 53 about its closest point c, Fig. 11's
 *             "full view ray from c without the part behind the viewer"; the
 *             ground point as midpoint on lines that hit the ground). eq. 53
 *             at the viewer (SF_FLAT_DESCENT_VIEWER), the density of the
 *             viewer for the whole line, had missed the dense air near c:
 *             T 0.51 off from 15 km, 0.97 from 100 km, and 1 (a negative
 *             column, clamped) on every segment ending before c;
 *  - spline:  Gałaj's spline transmittance, seed 002 §IV.E, Hermite meshes
 *             of 50 x 20 points (models/optical_depth_spline.h; the meshes
 *             become constant float arrays, codegen/baseline_spline.h).
 * Leenman's "raymarched" model (seed 000 §11.2.10) is no transmittance
 * baseline: it raymarches the *scattering* integral (eq. 54-57, 5 steps)
 * with the flat model's optical depths; it is the sky-radiance baseline
 * raymarched-sky (codegen/emit_sky_raymarched.h), whose columns are the
 * flat baseline's (sf_emit_flat_columns_closest).
 * Chapman, Taylor and spline exist only for exponential constituents; any other
 * (the ozone tent) is the constant shell of seed 000 §10.5 / eq. 59 with
 * the exact chord through it (models/optical_depth_flat.h), so the emitted
 * transmittance includes every constituent.
 *
 * Each baseline `name` emits, in both languages (N = number of channels):
 *   vecN skyfit_<name>_transmittance(float h_km, float mu)
 *       the ray from the viewer to the ground or out of the atmosphere
 *       (a viewer above the top starts where the ray enters; 1 if never);
 *   vecN skyfit_<name>_transmittance_segment(float h_km, float mu, float t_km)
 *       the first t_km of that ray;
 *   vecN skyfit_<name>_transmittance_between(float h_km, float mu, float t0, float t1)
 *       the part [t0, t1] of it (the two above call it). */
#ifndef SKYFIT_CODEGEN_BASELINES_H
#define SKYFIT_CODEGEN_BASELINES_H

#include <stddef.h>

#include "codegen/code_writer.h"
#include "models/atmosphere.h"
#include "models/optical_depth_spline.h"
#include "models/scene_file.h"
#include "util/error.h"

typedef enum sf_baseline_kind {
  SF_BASELINE_NAIVE = 0,
  SF_BASELINE_CHAPMAN,
  SF_BASELINE_TAYLOR,
  SF_BASELINE_FLAT,
  SF_BASELINE_SPLINE,
  SF_BASELINE_COUNT          /* the number of kinds, not a kind */
} sf_baseline_kind;

#define SF_BASELINE_DEFAULT_STEPS 16

typedef struct sf_baseline {
  sf_baseline_kind kind;
  int steps;                      /* naive only, >= 1 */
  const sf_atmosphere *atmosphere;
  /* spline only: made from atmosphere by the caller with
   * sf_spline_model_make (SF_SPLINE_HEIGHT_POINTS x SF_SPLINE_DISTANCE_POINTS),
   * freed by the caller after the baseline's last use */
  const sf_spline_model *spline;
} sf_baseline;

/* "naive", "chapman", "taylor", "flat", "spline" -> kind; -1 for anything else. */
int sf_baseline_kind_parse(const char *name);
const char *sf_baseline_kind_name(sf_baseline_kind kind);
/* One line saying what the model is, for the emitted header comment. */
void sf_baseline_describe(const sf_baseline *b, char *out, size_t n);

/* Checks that the baseline can be emitted for its atmosphere (1-4
 * channels, steps >= 1, an exponential constituent for all but "naive",
 * a spline model for "spline"); SF_ERR_INPUT naming the problem otherwise. */
int sf_baseline_check(const sf_baseline *b, sf_error *err);

/* Writes the three functions above into w (which records the helpers and
 * vector types they use). */
void sf_emit_baseline(sf_code_writer *w, const sf_baseline *b);

/* The expression of constituent c's density at the float variable h (km
 * above the ground): its layers by cumulative width, clamped to [0, 1]
 * (models/atmosphere.h); for the naive sky too (codegen/emit_sky_naive.h). */
void sf_emit_constituent_density(sf_code_writer *w, const sf_constituent *c);

/* The flat model's pieces (seed 000 eq. 51) in float32, behind their own
 * guard: skyfit_flat_up and skyfit_flat_up_diff; emitted with the flat
 * baseline and the raymarched sky. */
void sf_emit_flat_helpers(sf_code_writer *w);

/* Statements setting float d<i> (declared 0 by the caller) to the flat
 * model's column (km) of every constituent over the piece seg = (t0, t1,
 * altitude at t0, altitude at t1), seg.y > seg.x, of the line (h_km, mu):
 * a skyfit_air_clip(...) of the ray, or a piece of the line through the
 * ground (the raymarched sky's sun columns). Descent
 * SF_FLAT_DESCENT_CLOSEST (models/optical_depth_flat.h), whose columns add
 * up along a ray; shells for the non-exponential constituents. Needs
 * sf_emit_flat_helpers. The flat baseline's columns, and the raymarched
 * sky's (codegen/emit_sky_raymarched.h). */
void sf_emit_flat_columns_closest(sf_code_writer *w, const sf_atmosphere *atm);

/* The same with Schuler's Chapman approximation (seed 000 eq. 22-25), the
 * Chapman baseline's depths; atm must have an exponential constituent.
 * For Schuler's sky's sun columns (codegen/emit_sky_naive.h). */
void sf_emit_chapman_columns(sf_code_writer *w, const sf_atmosphere *atm);

/* The same model in double precision through models/ (what the emitted
 * float code approximates): density integral (km) of every constituent
 * over [t0, t1] along the ray from radius r, and the transmittance per
 * channel. t1 may be INFINITY (the whole ray). */
void sf_baseline_depth(const sf_baseline *b, double r, double mu, double t0, double t1,
                       double *depth);
void sf_baseline_transmittance(const sf_baseline *b, double h_km, double mu, double t0,
                               double t1, double *transmittance);

/* Transmittance error of the (double) baseline against the reference
 * (models/optical_depth.h) over domain, every channel: RMSE (seed 000
 * eq. 61) over a 64 x 384 grid in (h, mu), and the largest absolute error
 * over that grid and the tangent sweeps (models/tangent_sweep.h) of the
 * ground and of the ozone-like shells' boundaries. */
void sf_baseline_measure(const sf_baseline *b, const sf_scene_domain *domain, double *rmse,
                         double *max_abs);

#endif
