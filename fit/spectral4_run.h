/* `skyfit fit spectral4` end to end (SPEC §7.3): the spectral reference of
 * the scene's atmosphere (reference tables at 360-830 nm / 5 nm, cached),
 * the fit with Rayleigh and ozone only (aerosols removed, seed 003 §5.4.3),
 * and the evaluation of the fitted weights, plain RGB at 680/550/440 nm and
 * 4 uniformly spaced wavelengths, with and without aerosols.
 *
 * Radiance scale: every radiance is multiplied by 6 / Y_sun (the sun's CIE
 * luminance), SPEC §12's "sun irradiance 6", and by the sample's exposure
 * (16 with the sun below the horizon, 2 in space, else 1), before the loss
 * and before tone mapping for ΔE2000.
 *
 * ---- The weights file ("model": "spectral4", "quantity": "sky_radiance") --
 * Header as SPEC §8: "atmosphere" is the scene's atmosphere (canonical JSON)
 * and its hash; "domain" the scene's domain. "params" (row-major arrays):
 *   "wavelengths_nm"  [4]     l_1 < l_2 < l_3 < l_4
 *   "weights_nm"      [4]     w_i, the partition widths of seed 003 eq. 5.10
 *   "to_xyz"          [3, 4]  M_xyz[c][i] = cmf_c(l_i) w_i (eq. 5.12): XYZ =
 *                             M_xyz (L(l_1), ..., L(l_4))^T
 *   "to_linear_srgb"  [3, 4]  M_srgb = xyz_to_srgb . M_xyz: linear sRGB
 *   "sun_irradiance"  [4]     the sun at l_i (the spectral counterpart's
 *                             units: as bright as the atmosphere's RGB sun)
 *   "ground_albedo"   [4]
 *   "scattering"      [n_constituents, 4]  beta_s of each constituent at l_i,
 *   "absorption"      [n_constituents, 4]  beta_a, 1/km; rows in the order of
 *                             "atmosphere"."constituents" (names, phase
 *                             functions and density profiles are there)
 * A renderer computes its sky at the 4 wavelengths with these coefficients
 * (one vec4 per quantity) and multiplies by "to_linear_srgb".
 * "metrics": "loss" (eq. 5.13 at the fit), "grid_loss",
 * "evaluations" (Nelder-Mead; no timings, so that the file is byte-identical
 * from run to run and for any thread count), and per
 * method ("spectral4", "rgb_680_550_440", "uniform4") and atmosphere
 * ("without_aerosols", "with_aerosols"): {"mean_delta_e2000",
 * "p99_delta_e2000", "max_delta_e2000", "samples"}; plus "rgb_scale",
 * "uniform4_wavelengths_nm", "uniform4_weights_nm".
 * "training": {"seed": 0 (deterministic), "epochs" (the Nelder-Mead
 * evaluations, each a pass over every sample), "loss": "mse_linear_srgb",
 * ...}. */
#ifndef SKYFIT_FIT_SPECTRAL4_RUN_H
#define SKYFIT_FIT_SPECTRAL4_RUN_H

#include <cjson/cJSON.h>

#include "data/precompute_options.h"
#include "data/table_params.h"
#include "fit/spectral4_eval.h"
#include "fit/spectral4_fit.h"
#include "fit/spectral4_samples.h"
#include "models/scene_file.h"

/* SPEC §12 / seed 000 §11.4 */
#define SF_SPECTRAL4_SUN_LUMINANCE 6.0
/* The 4 uniformly spaced wavelengths baseline over seed 003's visible range
 * 390-780 nm (§5.4.1): partition centres, widths 97.5 nm. */
#define SF_UNIFORM4_MIN_NM 390.0
#define SF_UNIFORM4_MAX_NM 780.0

enum { SF_SPECTRAL4_METHODS = 3 };  /* fitted, plain RGB, uniform 4 */

typedef struct sf_spectral4_run_options {
  double min_nm, max_nm, step_nm;    /* reference wavelengths */
  sf_table_resolution res;
  int orders;
  double stop_fraction;
  const char *cache_dir;             /* NULL: no cache */
  int n_threads;
  sf_progress_fn progress;
  void *progress_ctx;
  void (*note)(void *ctx, const char *message);
  void *note_ctx;
  sf_spectral4_grid train, eval;
  sf_spectral4_fit_options fit;
} sf_spectral4_run_options;

/* 360-830/5 nm; tables 128x32, 16x64x16x8 (Bruneton); all orders as the
 * RGB tables take them (data/table_set.h: up to 64, stopping once the orders
 * left would add < 5e-4 of the sky in every wavelength; up to 12 stopping
 * once an order added < 1e-4 had left 1.3e-4 at 360 nm); training 16 suns x 24 mu x
 * 12 phi; evaluation 47 suns (every 2°) x 32 mu x 16 phi. */
void sf_spectral4_run_options_default(sf_spectral4_run_options *o);

typedef struct sf_spectral4_report {
  sf_spectral4_fit_result fit;
  double rgb_scale, rgb_loss, uniform_loss;
  sf_color_method methods[SF_SPECTRAL4_METHODS];
  int has_aerosols;                                  /* 0: both evaluations equal */
  sf_delta_e_stats stats[2][SF_SPECTRAL4_METHODS];   /* [0] without, [1] with aerosols */
  size_t n_train;
  int highest_order[2];
  int tables_cached[2];
  double reference_seconds, train_seconds, fit_seconds, eval_seconds;
  double sun_luminance;
} sf_spectral4_report;

/* The scene's inputs as sf_spectral4_run reads them, checked before any
 * work or output: an atmosphere whose wavelengths cover the reference's,
 * a sun the eye sees, a sun range that meets the fit's. SF_ERR_INPUT with
 * the key and the problem. */
int sf_spectral4_check_scene(const sf_scene *scene, const sf_spectral4_run_options *o, sf_error *err);

/* The domain its weights file states: the scene's, its suns within the
 * fit's range. */
void sf_spectral4_weights_domain(const sf_scene *scene, sf_scene_domain *domain);

/* Runs everything; *doc_out (caller deletes) is the weights document. */
int sf_spectral4_run(const sf_scene *scene, const sf_spectral4_run_options *o, sf_spectral4_report *rep,
                     cJSON **doc_out, sf_error *err);

#endif
