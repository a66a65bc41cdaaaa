/* The float32 hard-case sweep of every emitted model (issue 9, SPEC §10).
 *
 * For five atmospheres (Earth; scale heights x0.01 -> 0.08 / 0.012 km and
 * x0.08^-1 -> 100 / 15 km; every coefficient x1e-3 and x1e3) the C header
 * emitted by codegen/ (sf_codegen_write, as `skyfit codegen` writes it)
 * holds the five analytic baselines (naive, chapman, taylor, flat, spline;
 * full ray, segment, between), the two sky-radiance baselines (naive-sky,
 * raymarched-sky) and a sigmoid transmittance: for Earth the
 * shipped weights/default/{sigmoid, mlp-transmittance, mlp-scattering,
 * hosek, preetham}.json plus a spectral4 weights file written in its
 * documented format (its functions are 3x4 matrix products and constants:
 * the float32 question is the sum, not the fit); for the four extreme
 * atmospheres the sigmoid fitted here (fit/fit_sigmoid.h, Ceres, 24 x 48
 * rays, ~0.05 s). The MLPs and the ground-level skies are not refitted on
 * the extreme atmospheres (their training needs the scattering tables).
 * Their emitted code depends on the atmosphere only through the radii
 * (the same in all five) and the fitted numbers: an extreme atmosphere
 * changes only those numbers, and saturated, large-weight networks, the
 * float32 hazard such a fit brings, are checked in tests/test_mlp_sky.c.
 *
 * The header is compiled (cc -std=c99 -O2 -Wall -Wextra -Werror -pedantic,
 * ISO mode: no contraction) into a shared object and called in-process
 * through dlopen. Every public function of the header (the header is
 * scanned: skyfit_<model>_<quantity>[_segment|_between|_top],
 * skyfit_spectral4_*) gets the points of tests/hard_case_points.h, split
 * evenly over the case classes that apply to its arguments: domain-wide,
 * tangent rays (mu at the horizon cosine exactly, +-1e-6 relative, +-1..64
 * ulp), h = 0 looking down, the top looking up, space viewers missing /
 * grazing / entering, sun below the horizon and in the planet's shadow,
 * mu, mu_s, nu = +-1, segment ends (0, tiny, at the ray's end +-1e-6
 * relative, far beyond), T -> 0 (long grazing rays). Points per function:
 * SWEEP_POINTS_EARTH for Earth, SWEEP_POINTS_OTHER for the others (env
 * SKYFIT_SWEEP_POINTS overrides both, e.g. 1000000 for the full
 * sweep everywhere: ~5 min on one core).
 *
 * The error of a point: |T_f - T_d| for transmittance, |L_f - L_d| /
 * max(|L_d|, 1e-6, scale) for radiance (scale: the un-cancelled magnitude -
 * the largest channel; the eq. 44 full-ray radiance; spectral sums
 * sum_j |M_ij L_j|), against the same model in double
 * (tests/emitted_double_models.h). The emitted functions are discontinuous
 * where a ray starts or stops hitting the ground or the top, and near
 * tangency the float32 ground distance is uncertain by ~sqrt(eps32) of it:
 * there, the error modulo ill-conditioning counts (envelope_excess: the
 * distance to the model's own values over mu +-4 float ulp and ray
 * distances x (1 +- 1e-3)). Asserted, per function and class:
 *  1. every public function of the header is swept;
 *  2. zero NaN or Inf in any float32 output; transmittance in [0, 1],
 *     the scattering MLP's radiance >= 0;
 *  3. the error modulo ill-conditioning <= float_bound[model][class] at
 *     every point (functions of a distance t: all but OUTLIER_SHARE);
 *  4. transmittance models against the physical reference (exact optical
 *     depth, models/optical_depth.h, ~3e5 rays/s: the first PHYS_POINTS
 *     points per class; fitted models only inside their weights' domain):
 *     |T_f - T_ref| modulo the same ill-conditioning <= phys_bound.
 * Tables model x class are printed per atmosphere, and the maxima over
 * them. SKYFIT_SWEEP_CALIBRATE=1 reruns with all bounds 1e-6 to re-measure. */
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "emitted_library.h"
#include "codegen/baseline_part.h"
#include "codegen/codegen_file.h"
#include "codegen/fitted_part.h"
#include "emitted_double_models.h"
#include "fit/fit_sigmoid.h"
#include "hard_case_points.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/weights_file.h"
#include "spectral4_test_weights.h"

#define SWEEP_POINTS_EARTH 1000000L
#define SWEEP_POINTS_OTHER 50000L
#define PHYS_POINTS 1500          /* per class and transmittance function */
#define CHUNK 65536
#define MAX_FUNCTIONS 40
#define FLIP_ULP 4
#define N_ATMOSPHERES 5

/* Bound rows: one per model (its full, segment and between functions). */
enum model_row { ROW_NAIVE = 0, ROW_CHAPMAN, ROW_TAYLOR, ROW_FLAT, ROW_SPLINE, ROW_SIGMOID, ROW_MLP_T, ROW_MLP_S,
                 ROW_HOSEK, ROW_PREETHAM, ROW_SPECTRAL4, ROW_NAIVE_SKY, ROW_RAYMARCHED_SKY, ROW_FLAT_SKY,
                 ROW_SCHULER_SKY, ROW_COUNT };
static const char *const row_names[ROW_COUNT] = {"naive", "chapman", "taylor", "flat", "spline", "sigmoid",
                                                 "mlp-transmittance", "mlp-scattering", "hosek", "preetham",
                                                 "spectral4", "naive-sky", "raymarched-sky", "flat-sky",
                                                 "schuler-sky"};

/* Float32 header vs the same model in double, per model and class, max over
 * the five atmospheres, of the error modulo ill-conditioning (a(p) below).
 * Columns: domain tangent h0-down top-up space sun-shadow +-1 segment T->0
 * (0: the class does not apply). Set at ~3x the value measured with
 * SKYFIT_SWEEP_CALIBRATE at 1e5 points per function, rounded up, at least
 * 1e-5 (float32 carries 6e-8; a transmittance error below 1e-5 is invisible
 * and a regression past it is not). Where larger, why:
 *  - naive / chapman space, +-1 (1e-3): viewers up to 5 planet radii out,
 *    altitudes along a 30,000 km ray carry float32 cancellation ~ ulp(r^2)/2r;
 *  - taylor (3e-2): seed 002 eq. 17 evaluates exp of large arguments and
 *    differences of them; in the thin and dense atmospheres its float32
 *    result moves by ~1e-2;
 *  - flat tangent (2e-2): eq. 51/53 at the tangent point in the thin atmosphere;
 *  - spline (up to 0.3): the Hermite meshes in float32 for the thin
 *    atmosphere (scale height 0.08 km against a 100 km mesh), near the horizon;
 *  - segment class of the baselines (1e-2 .. 5e-2, plus rare outliers, see
 *    OUTLIER_SHARE): _between with an end at the ground point of a
 *    near-tangent ray, where the float32 ground distance is off by up to
 *    ~sqrt(eps32) of it and the function jumps (the piece past the ground is
 *    the far side of the line, models/air_segment.c).
 *  - hosek +-1 (1e-3): the float32 error of a fitted Hosek model depends on
 *    its coefficients, so it moves with a refit: the ±1 class measured
 *    below 3e-4 with one default fit and 6.5e-4 (one point in 1e6, the sun
 *    at the zenith) with the next;
 *  - preetham +-1 (3e-3): likewise; 1.14e-3 on another stream of 1e6
 *    points (the sun on the horizon, nu = 1 clamped), against the 1e-3
 *    this row had;
 *  - mlp-s +-1 (5e-5): likewise with its weights: below 1e-5 for the
 *    default network polished 30 steps, 1.5e-5 (2 points in 1e6: looking
 *    straight down, the sun at the nadir) polished 100;
 *  - mlp-s h0-down, top-up (1e-4): likewise; the default network refitted
 *    on skyfit-tables 6 measured 2.24e-5 and 2.43e-5 at 1e5 points (the
 *    one before 1.23e-5 and 8.9e-6, whose top-up bound was 2e-5; 1e6
 *    points found 2.85e-5 on 17 top-up points).
 *  - raymarched-sky (up to 2e-3): the flat model's columns in float32 (a
 *    difference of exp(-h/H) terms per piece, eq. 51) and the sun's
 *    grazing columns at the shadow's edge, whose float32 position moves
 *    the piece ends; measured 2.5e-4 (domain, space) and 5.9e-4 (shadow)
 *    at 1e5 points per function, ten times the naive sky's;
 *  - flat-sky (up to 5e-3): the same in one step; its shadow class
 *    measured 1.4e-3 in the thick atmosphere (a viewer at 6 km, the sun
 *    just below the horizon: one long piece whose end the float32 edge
 *    moves); T->0 as the raymarched sky's, where Earth's 1e6 points found
 *    2.0e-4 (a ground viewer 3e-6 below the horizon, a ray of metres) and
 *    the 1e5 calibration 2.5e-5;
 *  - schuler-sky (up to 3e-4): the naive sky's sums with the Chapman
 *    baseline's float32 sun columns; measured 8e-5 (top-up, +-1) at 1e5
 *    points, twice the naive sky's.
 * Radiance rows are relative errors (to max(|L|, 1e-6, the un-cancelled
 * scale)), transmittance rows absolute. */
static const double float_bound[ROW_COUNT][HC_COUNT] = {
    /*            domain  tangent h0-down top-up  space   sun     +-1     segment T->0 */
    /* naive */   {3e-4,  1e-5,   1e-5,   1e-5,   1e-3,   0,      1e-3,   1e-2,   1e-5},
    /* chapman */ {1e-5,  1e-5,   1e-5,   1e-5,   1e-4,   0,      5e-5,   1e-2,   2e-5},
    /* taylor */  {3e-2,  1e-5,   1e-2,   1e-5,   3e-2,   0,      1e-5,   3e-2,   3e-4},
    /* flat */    {5e-5,  2e-2,   1e-5,   1e-5,   5e-5,   0,      5e-5,   1e-2,   1e-5},
    /* spline */  {2e-2,  3e-1,   2e-2,   1e-5,   5e-2,   0,      1e-3,   5e-2,   5e-2},
    /* sigmoid */ {2e-4,  5e-4,   5e-5,   1e-5,   5e-4,   0,      5e-5,   5e-4,   5e-5},
    /* mlp-t */   {5e-5,  3e-4,   1e-4,   1e-5,   1e-4,   0,      1e-5,   5e-4,   1e-4},
    /* mlp-s */   {1e-4,  3e-4,   1e-4,   1e-4,   5e-5,   1e-4,   5e-5,   5e-4,   1e-4},
    /* hosek */   {3e-4,  5e-4,   5e-4,   0,      0,      2e-4,   1e-3,   0,      0},
    /* preetham */{1e-5,  5e-5,   1e-5,   0,      0,      1e-5,   3e-3,   0,      0},
    /* spectr4 */ {1e-6,  0,      0,      0,      0,      0,      0,      0,      1e-6},
    /* naive-s */ {1.5e-4,2e-5,   1e-5,   1e-4,   5e-5,   1e-4,   1e-4,   0,      5e-5},
    /* raym-s */  {1e-3,  2e-4,   1e-5,   5e-4,   1e-3,   2e-3,   5e-4,   0,      3e-4},
    /* flat-s */  {1e-3,  3e-4,   3e-5,   1e-5,   1e-3,   5e-3,   5e-4,   0,      3e-4},
    /* schul-s */ {2e-4,  3e-5,   2e-5,   3e-4,   1e-4,   2e-4,   3e-4,   0,      5e-5}};

/* Points of a class whose error modulo ill-conditioning may exceed the
 * bound, at most, for the functions of a distance t (segment, between,
 * eq. 44): an end of the piece at the ground point of a near-tangent ray
 * (the jump above) happens in every class; 0 for the others. */
#define OUTLIER_SHARE 1e-3

/* Float32 header vs the physical reference |T_f - T_ref| (transmittance
 * rows), max over the atmospheres, on the first PHYS_POINTS points of each
 * class; fitted models only inside the domain their weights file states.
 * ~1.5x the measured value, at least 1e-5, at most 1: these are the
 * models' own errors (the analytic baselines are rough near the horizon,
 * for space viewers and in the extreme atmospheres; the sigmoid fitted here
 * on the extreme atmospheres is poor), so a 1 states that the model can be
 * entirely wrong there, not a float32 problem. A 1 asserts nothing (a
 * transmittance in [0, 1] is always within 1 of another): where a model's
 * error is far below it, the bound is set from an independent statement
 * instead. mlp-transmittance (swept on Earth only, the shipped weights):
 * domain 2e-2, against the 0.0146 max_abs its weights file states over the
 * scene's domain (metrics.build_error; measured 1.21e-2 here); h0-down
 * 5e-3, +-1 1e-2, segment 0.2 (measured 2.1e-3, 4.2e-3, 0.106). Its
 * tangent and T->0 classes stay at 1: viewers below ~0.5 m, where float32
 * rounds R + h to the next radius (4.9e-4 km apart) and the horizon moves,
 * e.g. h 1.35e-4 km, mu -2.06018813e-4: 0.99936 for the physics' 0.952. */
static const double phys_bound[ROW_COUNT][HC_COUNT] = {
    /* naive */   {0.15,  1,      0.3,    1e-5,   1,      0,      0.15,   1,      0.4},
    /* chapman */ {0.9,   0.9,    0.2,    1e-5,   0.5,    0,      0.75,   0.5,    0.7},
    /* taylor */  {1,     1,      1,      1e-3,   1,      0,      0.7,    1,      1},
    /* flat */    {1,     1,      0.1,    1e-5,   1,      0,      0.75,   1,      1},
    /* spline */  {0.75,  1,      0.75,   1e-5,   0.9,    0,      0.75,   0.9,    0.9},
    /* sigmoid */ {1,     1,      1,      0.9,    1,      0,      1,      1,      1},
    /* mlp-t */   {2e-2,  1,      5e-3,   5e-4,   1,      0,      1e-2,   0.2,    1}};

enum physical_kind { PHYS_NONE = 0, PHYS_FULL, PHYS_TOP, PHYS_SEGMENT, PHYS_BETWEEN };

/* One public function of the header and the double model it must reproduce. */
typedef struct swept_function {
  char name[96];
  const char *args;   /* per argument: 'f' the next input, 'i' int of it, 'v' vec4 of p[0..3] */
  int n_out;
  hard_case_input input;
  emitted_double_fn eval, scale_eval;
  const void *ctx;
  double norm;
  int row;
  int physical;
  const sf_scene_domain *domain;   /* fitted models: compared with the physics only inside it */
} swept_function;

typedef struct class_stats {
  long count, nonfinite, flips;   /* flips: over the bound, accepted as ill-conditioned */
  long outliers;                   /* error modulo ill-conditioning over the bound */
  long out_of_range;               /* transmittance outside [0, 1], radiance MLP below 0 */
  double max_err;                  /* of the error modulo ill-conditioning */
  double raw_err;                  /* of the plain error */
  float worst[8];
  long phys_count, phys_flips;
  double phys_err;
  float phys_worst[8];
} class_stats;

typedef struct sweep_atmosphere {
  const char *name;
  sf_atmosphere atm;
  sf_baseline baselines[SF_BASELINE_COUNT];
  sf_spline_model spline;
  int n_fitted;
  sf_weights weights[8];
  sf_fitted_model *fitted[8];
} sweep_atmosphere;

typedef void (*sweep_eval_fn)(int fn, int n, const float *in, float *out);

static char tmp_dir[256];

static int run(const char *command) {
  fflush(stdout);
  int status = system(command);
  if (status != 0) printf("command failed (%d): %s\n", status, command);
  return status;
}

/* ---- the atmospheres ------------------------------------------------------- */

static void make_atmosphere(int which, sf_atmosphere *atm) {
  sf_atmosphere_default(atm);
  for (int c = 0; c < atm->n_constituents; ++c) {
    sf_constituent *con = &atm->constituents[c];
    for (int l = 0; l < con->n_layers; ++l) {
      double *k = &con->layers[l].exp_scale_per_km;
      if (which == 1) *k *= 100.0;   /* H: 8 km -> 0.08, 1.2 -> 0.012 */
      if (which == 2) *k *= 0.08;    /* H: 8 km -> 100, 1.2 -> 15 */
    }
    double f = which == 3 ? 1e-3 : which == 4 ? 1e3 : 1.0;
    for (int ch = 0; ch < atm->n_channels; ++ch) {
      con->scattering[ch] *= f;
      con->absorption[ch] *= f;
    }
  }
  sf_atmosphere_finalize(atm);
}

/* ---- weights files ---------------------------------------------------------------- */

static int fit_sigmoid_weights(const sf_atmosphere *atm, const char *path) {
  sf_scene_domain domain = {0.0, atm->top_radius_km - atm->bottom_radius_km, -1.0, 1.0, -1.0, 1.0};
  sf_sigmoid_fit_options o;
  sf_sigmoid_fit_options_default(&o);
  o.n_h = 24;
  o.n_mu = 48;
  sf_sigmoid_fit_report *rep = calloc(1, sizeof *rep);
  sf_sigmoid_model m;
  sf_error err;
  sf_error_clear(&err);
  int status = sf_fit_sigmoid(atm, &domain, &o, &m, rep, &err);
  if (status == SF_OK) {
    printf("sigmoid fitted here: full-ray rmse %.3g max_abs %.3g (%.2f s)\n", rep->rmse, rep->max_abs,
           rep->seconds);
    cJSON *doc = sf_weights_new("sigmoid", "transmittance", atm, &domain);
    double a[SF_MAX_CONSTITUENTS * 4 * SF_SIGMOID_N_COEFFS];
    int n = 0;
    for (int c = 0; c < m.n_constituents; ++c)
      for (int k = 0; k < m.n_channels; ++k)
        for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j) a[n++] = m.a[c][k][j];
    int shape[3] = {m.n_constituents, m.n_channels, SF_SIGMOID_N_COEFFS};
    sf_weights_add_input(doc, "h_km", 0.0, 1.0);
    sf_weights_add_input(doc, "mu", 0.0, 1.0);
    sf_weights_add_param(doc, "a", 3, shape, a);
    cJSON_AddNumberToObject(sf_weights_metrics(doc), "rmse", rep->rmse);
    cJSON_AddNumberToObject(sf_weights_metrics(doc), "max_abs", rep->max_abs);
    status = sf_weights_write(doc, path, &err);
    cJSON_Delete(doc);
  }
  if (status != SF_OK) printf("%s\n", err.message);
  free(rep);
  return status;
}

static int load_fitted(sweep_atmosphere *sa, const char *path, sf_codegen_part *part) {
  sf_error err;
  sf_error_clear(&err);
  int i = sa->n_fitted;
  if (sf_weights_load_file(path, NULL, &sa->weights[i], &err) != SF_OK ||
      sf_fitted_part(&sa->weights[i], &sa->fitted[i], part, &err) != SF_OK) {
    printf("%s\n", err.message);
    return -1;
  }
  sa->n_fitted = i + 1;
  return 0;
}

/* ---- the functions ------------------------------------------------------------------ */

static swept_function *add_fn(swept_function *fs, int *n, const char *name, const char *args, int n_out,
                              hard_case_input input, emitted_double_fn eval, const void *ctx, double norm, int row,
                              int physical) {
  if (*n >= MAX_FUNCTIONS) {   /* a new function past the array: say so, not overrun it */
    printf("add_fn: more than MAX_FUNCTIONS (%d) functions; raise it\n", MAX_FUNCTIONS);
    exit(1);
  }
  swept_function *f = &fs[(*n)++];
  memset(f, 0, sizeof *f);
  snprintf(f->name, sizeof f->name, "%s", name);
  f->args = args;
  f->n_out = n_out;
  f->input = input;
  f->eval = eval;
  f->ctx = ctx;
  f->norm = norm;
  f->row = row;
  f->physical = physical;
  return f;
}

static void add_fitted_functions(const sweep_atmosphere *sa, swept_function *fs, int *n) {
  for (int i = 0; i < sa->n_fitted; ++i) {
    const sf_fitted_model *m = sa->fitted[i];
    int first = *n;
    switch (m->kind) {
      case SF_FITTED_SIGMOID:
        add_fn(fs, n, "skyfit_sigmoid_transmittance", "ff", 3, HI_RAY, emitted_sigmoid_full, &m->sigmoid, 1.0,
               ROW_SIGMOID, PHYS_FULL);
        add_fn(fs, n, "skyfit_sigmoid_transmittance_segment", "fff", 3, HI_RAY_T, emitted_sigmoid_segment,
               &m->sigmoid, 1.0, ROW_SIGMOID, PHYS_SEGMENT);
        break;
      case SF_FITTED_SKY: {
        int hosek = m->sky.form == SF_SKY_FORM_HOSEK;
        add_fn(fs, n, hosek ? "skyfit_hosek_sky_radiance" : "skyfit_preetham_sky_radiance", "fff", 3, HI_GROUND,
               emitted_sky, &m->sky, 1e-6, hosek ? ROW_HOSEK : ROW_PREETHAM, PHYS_NONE)->scale_eval = emitted_sky;
        break;
      }
      case SF_FITTED_MLP_TRANSMITTANCE:
        add_fn(fs, n, "skyfit_mlp_transmittance", "ff", 3, HI_RAY, emitted_mlp_t, &m->mlp, 1.0, ROW_MLP_T,
               PHYS_FULL);
        add_fn(fs, n, "skyfit_mlp_transmittance_segment", "fff", 3, HI_RAY_T, emitted_mlp_t_segment, &m->mlp, 1.0,
               ROW_MLP_T, PHYS_SEGMENT);
        add_fn(fs, n, "skyfit_mlp_transmittance_top", "ff", 3, HI_RAY, emitted_mlp_t_top, &m->mlp, 1.0, ROW_MLP_T,
               PHYS_TOP);
        break;
      case SF_FITTED_MLP_SCATTERING:
        add_fn(fs, n, "skyfit_mlp_sky_radiance", "ffff", 3, HI_SKY, emitted_mlp_s, m, 1e-6, ROW_MLP_S, PHYS_NONE)
            ->scale_eval = emitted_mlp_s;
        /* the shipped networks share the atmosphere: linked, the segment is emitted and swept */
        CHECK(m->transmittance != NULL);
        if (m->transmittance)
          add_fn(fs, n, "skyfit_mlp_sky_radiance_segment", "fffff", 3, HI_SKY_T, emitted_mlp_s_segment, m, 1e-6,
                 ROW_MLP_S, PHYS_NONE)->scale_eval = emitted_mlp_s;
        break;
      case SF_FITTED_SPECTRAL4: {
        const sf_spectral4_emit *s = &m->spectral4;
        add_fn(fs, n, "skyfit_spectral4_to_linear_srgb", "v", 3, HI_VEC4, emitted_spectral_srgb, s, 1e-35,
               ROW_SPECTRAL4, PHYS_NONE)->scale_eval = emitted_spectral_srgb_abs;
        add_fn(fs, n, "skyfit_spectral4_to_xyz", "v", 3, HI_VEC4, emitted_spectral_xyz, s, 1e-35, ROW_SPECTRAL4,
               PHYS_NONE)->scale_eval = emitted_spectral_xyz_abs;
        add_fn(fs, n, "skyfit_spectral4_wavelengths_nm", "", 4, HI_NONE, emitted_spectral_wavelengths, s, 1e-9,
               ROW_SPECTRAL4, PHYS_NONE);
        add_fn(fs, n, "skyfit_spectral4_sun_irradiance", "", 4, HI_NONE, emitted_spectral_sun, s, 1e-9,
               ROW_SPECTRAL4, PHYS_NONE);
        add_fn(fs, n, "skyfit_spectral4_ground_albedo", "", 4, HI_NONE, emitted_spectral_albedo, s, 1e-9,
               ROW_SPECTRAL4, PHYS_NONE);
        add_fn(fs, n, "skyfit_spectral4_scattering", "i", 4, HI_INDEX, emitted_spectral_scattering, s, 1e-9,
               ROW_SPECTRAL4, PHYS_NONE);
        add_fn(fs, n, "skyfit_spectral4_absorption", "i", 4, HI_INDEX, emitted_spectral_absorption, s, 1e-9,
               ROW_SPECTRAL4, PHYS_NONE);
        break;
      }
    }
    for (int k = first; k < *n; ++k) fs[k].domain = &sa->weights[i].domain;
  }
}

/* ---- the header in a shared object ------------------------------------------------------- */

static void call_text(const swept_function *f, char *out, size_t n) {
  int k = snprintf(out, n, "%s(", f->name);
  int in = 0;
  for (int a = 0; f->args[a]; ++a) {
    const char *sep = a ? ", " : "";
    if (f->args[a] == 'v') {
      k += snprintf(out + k, n - (size_t)k, "%sskyfit_make_vec4(p[0], p[1], p[2], p[3])", sep);
      in += 4;
    } else if (f->args[a] == 'i') {
      k += snprintf(out + k, n - (size_t)k, "%s(int)p[%d]", sep, in++);
    } else {
      k += snprintf(out + k, n - (size_t)k, "%sp[%d]", sep, in++);
    }
  }
  snprintf(out + k, n - (size_t)k, ")");
}

static int write_driver(const char *path, const char *header, const swept_function *fs, int n) {
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f,
          "#include \"%s\"\n\n"
          "void sweep_eval(int fn, int n, const float *in, float *out);\n"
          "void sweep_eval(int fn, int n, const float *in, float *out) {\n"
          "  int i;\n"
          "  for (i = 0; i < n; ++i) {\n"
          "    const float *p = in + 8 * i;\n"
          "    float *o = out + 4 * i;\n"
          "    switch (fn) {\n",
          header);
  char call[512];
  for (int k = 0; k < n; ++k) {
    call_text(&fs[k], call, sizeof call);
    fprintf(f, "      case %d: { skyfit_vec%d v = %s; o[0] = v.x; o[1] = v.y;%s%s } break;\n", k, fs[k].n_out,
            call, fs[k].n_out > 2 ? " o[2] = v.z;" : "", fs[k].n_out > 3 ? " o[3] = v.w;" : "");
  }
  fprintf(f, "      default: o[0] = o[1] = o[2] = o[3] = 0.0f;\n    }\n  }\n}\n");
  return fclose(f);
}

static int is_public(const char *name) {
  static const char *const models[] = {"naive", "chapman", "taylor", "flat", "spline", "sigmoid", "mlp", "hosek",
                                       "preetham", "raymarched", "schuler"};
  static const char *const suffixes[] = {"_transmittance", "_transmittance_segment", "_transmittance_between",
                                         "_transmittance_top", "_sky_radiance", "_sky_radiance_segment"};
  if (strncmp(name, "skyfit_spectral4_", 17) == 0) return 1;
  for (size_t m = 0; m < sizeof models / sizeof models[0]; ++m) {
    size_t lm = strlen(models[m]);
    if (strncmp(name, "skyfit_", 7) != 0 || strncmp(name + 7, models[m], lm) != 0) continue;
    for (size_t s = 0; s < sizeof suffixes / sizeof suffixes[0]; ++s)
      if (strcmp(name + 7 + lm, suffixes[s]) == 0) return 1;
  }
  return 0;
}

/* Every function the header defines whose name is a model's public API
 * (skyfit_<model>_<quantity>[_segment|_between|_top], skyfit_spectral4_*)
 * must be swept, and every swept one defined. Returns the number missing
 * (plus 1 when the counts differ). */
static int check_coverage(const char *header_path, const swept_function *fs, int n) {
  FILE *f = fopen(header_path, "rb");
  if (!f) return -1;
  char line[1024];
  int missing = 0, public_count = 0;
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "static inline ", 14) != 0) continue;
    char *paren = strchr(line, '(');
    if (!paren) continue;
    *paren = '\0';
    char *name = strrchr(line, ' ');
    if (!name) continue;
    ++name;
    if (!is_public(name)) continue;
    ++public_count;
    int found = 0;
    for (int k = 0; k < n; ++k) found |= strcmp(fs[k].name, name) == 0;
    if (!found) {
      printf("  public function %s is not swept\n", name);
      ++missing;
    }
  }
  fclose(f);
  printf("header defines %d public functions, %d swept\n", public_count, n);
  /* every swept function found among the header's (none found: the
   * emitter's line format changed and this check saw nothing) */
  return public_count == n ? missing : missing + 1;
}

/* ---- errors ---------------------------------------------------------------------------- */

static double point_error(const swept_function *f, const float *got, const double *want, double scale) {
  double e = 0.0;
  for (int ch = 0; ch < f->n_out; ++ch)
    e = fmax(e, fabs(got[ch] - want[ch]) / fmax(fmax(fabs(want[ch]), f->norm), scale));
  return e;
}

static double scale_of(const swept_function *f, const float *p) {
  if (!f->scale_eval) return 0.0;
  double full[SF_MAX_CHANNELS], s = 0.0;
  f->scale_eval(f->ctx, p, full);
  for (int ch = 0; ch < f->n_out; ++ch) s = fmax(s, fabs(full[ch]));
  return s;
}

/* The physical transmittance of the ray the function takes at p; 0 where
 * it has none (to-top of a ground-hitting ray). */
static int physical_transmittance(const sf_atmosphere *atm, int kind, const float *p, double *T) {
  double depth[SF_MAX_CONSTITUENTS] = {0};
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  double h = fmax(p[0], 0.0), mu = fmin(fmax(p[1], -1.0), 1.0), r = R + h;
  if (kind == PHYS_FULL) sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
  else if (kind == PHYS_TOP) {
    if (sf_optical_depth_ray(atm, h, mu, SF_RAY_END_TOP, depth) != 0) return 0;
  } else {
    double t0 = kind == PHYS_BETWEEN ? p[2] : 0.0, t1 = kind == PHYS_BETWEEN ? p[3] : p[2];
    double te, tx;
    int ground;
    if (sf_ray_atmosphere_segment(r, mu, R, Rt, &te, &tx, &ground)) {
      /* _between clips [t0, t1] to the ray's LINE outside the planet
       * (models/air_segment.c): a piece starting at or past the ground hit
       * is the far side where the line re-emerges, which no ray reaches:
       * no physical reference there (left out of the comparison). */
      if (kind == PHYS_BETWEEN && ground && t0 >= tx) return 0;
      double a = fmax(t0, te), b = fmin(t1, tx);
      if (b > a) sf_optical_depth_segment(atm, r, mu, a, b, depth);
    }
  }
  sf_transmittance_from_depth(atm, depth, T);
  return 1;
}

static double physical_error(const sf_atmosphere *atm, const swept_function *f, const float *p, const float *got,
                             int *have) {
  double T[SF_MAX_CHANNELS];
  *have = physical_transmittance(atm, f->physical, p, T);
  if (!*have) return 0.0;
  double e = 0.0;
  for (int ch = 0; ch < f->n_out; ++ch) e = fmax(e, fabs(got[ch] - T[ch]));
  return e;
}

/* Where the model is ill-conditioned at float32 input resolution. Float32
 * and double put the horizon (ground hit or not, top entered or not) at mu
 * a few ulp apart, and near tangency the float32 ground-hit distance is
 * uncertain by ~sqrt(eps32) of the distance (its discriminant is a
 * difference of squares ~ (r mu)^2), where the segment functions jump (an
 * end crossing the ground point). The parts of one float computation (hit
 * test, path, lookups) each carry their own rounding, so next to a jump the
 * result may be one branch continued a few ulp past where double ends it.
 * Accepted iff, per channel, got lies within the values of the model (or
 * of the physical reference) over mu moved by -FLIP_ULP..FLIP_ULP float ulp
 * and the ray distances scaled by (1 +- T_SHIFT), widened by the bound and
 * by FLIP_ULP times the model's largest change per ulp of mu there other
 * than the single largest one (the jump, if any). */
#define T_SHIFT 1e-3
static int t_index(hard_case_input in, int *first) {
  if (in == HI_RAY_T) return *first = 2, 1;
  if (in == HI_RAY_T0T1) return *first = 2, 2;
  if (in == HI_SKY_T) return *first = 4, 1;
  return *first = 0, 0;
}

/* How far got lies outside that envelope, per channel in the units of the
 * error (0: inside); INFINITY when there is no reference at all. */
static double envelope_excess(const sf_atmosphere *atm, const swept_function *f, const float *p, const float *got,
                              double scale, int physical) {
  enum { N_MU = 2 * FLIP_ULP + 1 };
  double lo[SF_MAX_CHANNELS], hi[SF_MAX_CHANNELS], norm[SF_MAX_CHANNELS], slope[SF_MAX_CHANNELS];
  for (int ch = 0; ch < f->n_out; ++ch) {
    lo[ch] = INFINITY;
    hi[ch] = -INFINITY;
    norm[ch] = slope[ch] = 0.0;
  }
  int t_first, n_t = t_index(f->input, &t_first), any = 0;
  for (int ts = -1; ts <= 1; ++ts) {
    if (ts != 0 && n_t == 0) continue;
    double v[N_MU][SF_MAX_CHANNELS];
    int have[N_MU];
    for (int k = -FLIP_ULP; k <= FLIP_ULP; ++k) {
      float q[8];
      memcpy(q, p, sizeof q);
      for (int j = 0; j < abs(k); ++j) q[1] = nextafterf(q[1], k < 0 ? -2.0f : 2.0f);
      for (int j = 0; j < n_t; ++j) q[t_first + j] = (float)(q[t_first + j] * (1.0 + ts * T_SHIFT));
      double *want = v[k + FLIP_ULP];
      have[k + FLIP_ULP] = physical ? physical_transmittance(atm, f->physical, q, want) : (f->eval(f->ctx, q, want), 1);
      if (!have[k + FLIP_ULP]) continue;
      any = 1;
      for (int ch = 0; ch < f->n_out; ++ch) {
        lo[ch] = fmin(lo[ch], want[ch]);
        hi[ch] = fmax(hi[ch], want[ch]);
        norm[ch] = fmax(norm[ch], fabs(want[ch]));
      }
    }
    for (int ch = 0; ch < f->n_out; ++ch) {
      double largest = 0.0, second = 0.0;
      for (int k = 1; k < N_MU; ++k) {
        if (!have[k] || !have[k - 1]) continue;
        double step = fabs(v[k][ch] - v[k - 1][ch]);
        if (step > largest) {
          second = largest;
          largest = step;
        } else second = fmax(second, step);
      }
      slope[ch] = fmax(slope[ch], second);
    }
  }
  if (!any) return INFINITY;
  double excess = 0.0;
  for (int ch = 0; ch < f->n_out; ++ch) {
    double out = fmax(0.0, fmax(lo[ch] - FLIP_ULP * slope[ch] - got[ch], got[ch] - hi[ch] - FLIP_ULP * slope[ch]));
    excess = fmax(excess, out / (physical ? 1.0 : fmax(fmax(norm[ch], f->norm), scale)));
  }
  return excess;
}

/* Is p inside the domain the model was fitted on (always, for the baselines)? */
static int in_domain(const swept_function *f, const float *p) {
  const sf_scene_domain *d = f->domain;
  return !d || (p[0] >= d->h_min_km && p[0] <= d->h_max_km && p[1] >= d->mu_min && p[1] <= d->mu_max);
}

/* ---- the sweep --------------------------------------------------------------------------- */

static void sweep_function(const sf_atmosphere *atm, const swept_function *f, int k, sweep_eval_fn eval,
                           long points, uint64_t seed, int calibrate, class_stats *stats) {
  int n_classes = 0;
  for (int c = 0; c < HC_COUNT; ++c) n_classes += hard_case_applies(f->input, (hard_case_class)c);
  long per_class = points / n_classes;
  float *in = malloc(sizeof(float) * 8 * CHUNK), *out = malloc(sizeof(float) * 4 * CHUNK);
  int n_index = f->input == HI_INDEX ? ((const sf_spectral4_emit *)f->ctx)->n_constituents : 0;
  for (int c = 0; c < HC_COUNT; ++c) {
    class_stats *s = &stats[c];
    memset(s, 0, sizeof *s);
    if (!hard_case_applies(f->input, (hard_case_class)c)) {
      s->count = -1;
      continue;
    }
    hard_case_rng g = {seed * 1000003u + (uint64_t)k * 131u + (uint64_t)c};
    double bound = calibrate ? 1e-6 : float_bound[f->row][c];
    double pbound = f->physical ? (calibrate ? 1e-6 : phys_bound[f->row][c]) : 0.0;
    for (long done = 0; done < per_class;) {
      int n = (int)(per_class - done < CHUNK ? per_class - done : CHUNK);
      for (int i = 0; i < n; ++i) hard_case_point(&g, (hard_case_class)c, f->input, atm, n_index, in + 8 * i);
      eval(k, n, in, out);
      for (int i = 0; i < n; ++i) {
        const float *p = in + 8 * i, *got = out + 4 * i;
        double want[SF_MAX_CHANNELS];
        f->eval(f->ctx, p, want);
        int finite = 1;
        for (int ch = 0; ch < f->n_out; ++ch) finite &= isfinite(got[ch]) && isfinite(want[ch]);
        ++s->count;
        if (!finite) {
          if (s->nonfinite++ < 3)
            printf("  NON-FINITE %s [%s] at (%.9g, %.9g, %.9g, %.9g, %.9g): %g %g %g\n", f->name,
                   hard_case_names[c], p[0], p[1], p[2], p[3], p[4], got[0], got[1], got[2]);
          continue;
        }
        double scale = scale_of(f, p);
        double e = point_error(f, got, want, scale);
        int ray = f->input != HI_GROUND && f->input != HI_VEC4 && f->input != HI_INDEX && f->input != HI_NONE;
        s->raw_err = fmax(s->raw_err, e);
        for (int ch = 0; ch < f->n_out; ++ch) {
          if (f->row <= ROW_MLP_T && !(got[ch] >= 0.0f && got[ch] <= 1.0f + 1e-6f)) ++s->out_of_range;
          if ((f->row == ROW_MLP_S || f->row >= ROW_NAIVE_SKY) && !(got[ch] >= 0.0f)) ++s->out_of_range;
        }
        if (e > bound && ray) {   /* the error modulo ill-conditioning */
          double x = envelope_excess(atm, f, p, got, scale, 0);
          if (x <= bound) ++s->flips;
          e = fmin(e, x);
        }
        if (e > bound) ++s->outliers;
        if (e > s->max_err) {
          s->max_err = e;
          memcpy(s->worst, p, sizeof s->worst);
        }
        if (f->physical && done + i < PHYS_POINTS && in_domain(f, p)) {
          int have;
          double ep = physical_error(atm, f, p, got, &have);
          if (!have) continue;
          ++s->phys_count;
          if (ep > pbound) {
            double x = envelope_excess(atm, f, p, got, 0.0, 1);
            if (x <= pbound) ++s->phys_flips;
            ep = fmin(ep, x);
          }
          if (ep > s->phys_err) {
            s->phys_err = ep;
            memcpy(s->phys_worst, p, sizeof s->phys_worst);
          }
        }
      }
      done += n;
    }
  }
  free(in);
  free(out);
}

/* mode: 0 float32 vs double (max over the well-conditioned points), 1 the
 * same over all points, 2 the share of points accepted as ill-conditioned,
 * 3 float32 vs physical reference. */
static void print_table(const char *title, const swept_function *fs, int n_fs, class_stats (*stats)[HC_COUNT],
                        int mode) {
  printf("\n%s\n%-40s", title, "function");
  for (int c = 0; c < HC_COUNT; ++c) printf(" %10s", hard_case_names[c]);
  printf("\n");
  for (int k = 0; k < n_fs; ++k) {
    if (mode == 3 && !fs[k].physical) continue;
    printf("%-40s", fs[k].name);
    for (int c = 0; c < HC_COUNT; ++c) {
      const class_stats *s = &stats[k][c];
      if (s->count < 0 || (mode == 3 && s->phys_count == 0)) printf(" %10s", "-");
      else if (mode == 2) printf(" %10.2e", (double)s->flips / (double)s->count);
      else printf(" %10.2e", mode == 0 ? s->max_err : mode == 1 ? s->raw_err : s->phys_err);
    }
    printf("\n");
  }
}

static void sweep_atmosphere_run(sweep_atmosphere *sa, int index, int with_fitted, long points, int calibrate,
                                 const char *source_dir,
                                 double (*worst)[HC_COUNT], double (*worst_phys)[HC_COUNT]) {
  printf("\n=== atmosphere '%s' ===\n", sa->name);
  double t_start = (double)clock() / CLOCKS_PER_SEC;
  sf_error err;
  sf_error_clear(&err);
  sf_atmosphere *atm = &sa->atm;
  sf_scene_domain domain = {0.0, atm->top_radius_km - atm->bottom_radius_km, -1, 1, -0.2, 1};
  sf_codegen_part parts[20];   /* 15 for Earth */
  int n_parts = 0, n_fs = 0;
  swept_function fs[MAX_FUNCTIONS];
  if (!CHECK(sf_spline_model_make(atm, SF_SPLINE_HEIGHT_POINTS, SF_SPLINE_DISTANCE_POINTS, &sa->spline) == 0)) return;
  for (int k = 0; k < SF_BASELINE_COUNT; ++k) {
    sf_baseline *b = &sa->baselines[k];
    b->kind = (sf_baseline_kind)k;
    b->steps = SF_BASELINE_DEFAULT_STEPS;
    b->atmosphere = atm;
    b->spline = &sa->spline;
    if (!CHECK(sf_baseline_part(b, &domain, &parts[n_parts++], &err) == SF_OK)) return;
    char name[96];
    const char *kind = sf_baseline_kind_name(b->kind);
    snprintf(name, sizeof name, "skyfit_%s_transmittance", kind);
    add_fn(fs, &n_fs, name, "ff", 3, HI_RAY, emitted_baseline_full, b, 1.0, k, PHYS_FULL);
    snprintf(name, sizeof name, "skyfit_%s_transmittance_segment", kind);
    add_fn(fs, &n_fs, name, "fff", 3, HI_RAY_T, emitted_baseline_segment, b, 1.0, k, PHYS_SEGMENT);
    snprintf(name, sizeof name, "skyfit_%s_transmittance_between", kind);
    add_fn(fs, &n_fs, name, "ffff", 3, HI_RAY_T0T1, emitted_baseline_between, b, 1.0, k, PHYS_BETWEEN);
  }
  char path[1024];
  int first = n_parts;
  if (with_fitted) {   /* the shipped weights, and spectral4 in its documented format */
    const char *files[5] = {"sigmoid", "mlp-transmittance", "mlp-scattering", "hosek", "preetham"};
    for (int i = 0; i < 5; ++i) {
      snprintf(path, sizeof path, "%s/weights/default/%s.json", source_dir, files[i]);
      if (!CHECK(load_fitted(sa, path, &parts[n_parts]) == 0)) return;
      ++n_parts;
    }
    snprintf(path, sizeof path, "%s/spectral4_%s.json", tmp_dir, sa->name);
    if (!CHECK(write_spectral4_weights(path, atm) == SF_OK)) return;
  } else {             /* the sigmoid fitted here on this atmosphere */
    snprintf(path, sizeof path, "%s/sigmoid_%s.json", tmp_dir, sa->name);
    if (!CHECK(fit_sigmoid_weights(atm, path) == SF_OK)) return;
  }
  if (!CHECK(load_fitted(sa, path, &parts[n_parts]) == 0)) return;
  ++n_parts;
  sf_fitted_link(sa->fitted, parts + first, sa->n_fitted);
  add_fitted_functions(sa, fs, &n_fs);
  /* the sky-radiance baselines (codegen/emit_sky_naive.h,
   * emit_sky_raymarched.h), last: the functions before them keep their
   * points (each function's stream is seeded by its index) */
  sf_sky_naive naive_sky = {.atm = atm, .view_steps = SF_SKY_NAIVE_VIEW_STEPS,
                            .sun_steps = SF_SKY_NAIVE_SUN_STEPS};
  sf_sky_raymarched raymarched_sky, flat_sky;
  sf_sky_naive schuler_sky;
  sf_sky_schuler_make(atm, &schuler_sky);
  sf_sky_raymarched_make(atm, SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &raymarched_sky);
  sf_sky_raymarched_make(atm, SF_SKY_FLAT_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &flat_sky);
  if (!CHECK(sf_sky_naive_part(&naive_sky, &domain, &parts[n_parts++], &err) == SF_OK) ||
      !CHECK(sf_sky_raymarched_part(&raymarched_sky, 0, &domain, &parts[n_parts++], &err) == SF_OK) ||
      !CHECK(sf_sky_raymarched_part(&flat_sky, 1, &domain, &parts[n_parts++], &err) == SF_OK) ||
      !CHECK(sf_sky_naive_part(&schuler_sky, &domain, &parts[n_parts++], &err) == SF_OK))
    return;
  add_fn(fs, &n_fs, "skyfit_naive_sky_radiance", "ffff", 3, HI_SKY, emitted_naive_sky, &naive_sky, 1e-6,
         ROW_NAIVE_SKY, PHYS_NONE)->scale_eval = emitted_naive_sky;
  add_fn(fs, &n_fs, "skyfit_raymarched_sky_radiance", "ffff", 3, HI_SKY, emitted_raymarched_sky, &raymarched_sky,
         1e-6, ROW_RAYMARCHED_SKY, PHYS_NONE)->scale_eval = emitted_raymarched_sky;
  add_fn(fs, &n_fs, "skyfit_flat_sky_radiance", "ffff", 3, HI_SKY, emitted_raymarched_sky, &flat_sky, 1e-6,
         ROW_FLAT_SKY, PHYS_NONE)->scale_eval = emitted_raymarched_sky;
  add_fn(fs, &n_fs, "skyfit_schuler_sky_radiance", "ffff", 3, HI_SKY, emitted_naive_sky, &schuler_sky, 1e-6,
         ROW_SCHULER_SKY, PHYS_NONE)->scale_eval = emitted_naive_sky;

  char base[64], header[1024], driver[1024], so[1024];
  snprintf(base, sizeof base, "sweep_%s", sa->name);
  if (!CHECK(sf_codegen_write(parts, n_parts, 1, 0, tmp_dir, base, NULL, &err) == SF_OK)) {
    printf("%s\n", err.message);
    return;
  }
  snprintf(header, sizeof header, "%s/%s.h", tmp_dir, base);
  CHECK(check_coverage(header, fs, n_fs) == 0);
  snprintf(driver, sizeof driver, "%s/%s_driver.c", tmp_dir, base);
  snprintf(so, sizeof so, "%s/%s.so", tmp_dir, base);
  char header_name[80];
  snprintf(header_name, sizeof header_name, "%s.h", base);
  CHECK(write_driver(driver, header_name, fs, n_fs) == 0);
  if (!CHECK(emitted_library_compile(driver, so) == 0)) return;
  void *lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
  if (!CHECK(lib != NULL)) {
    printf("%s\n", dlerror());
    return;
  }
  sweep_eval_fn eval;
  *(void **)&eval = dlsym(lib, "sweep_eval");
  if (!CHECK(eval != NULL)) return;

  class_stats (*stats)[HC_COUNT] = calloc((size_t)n_fs, sizeof *stats);
  for (int k = 0; k < n_fs; ++k) {
    const swept_function *f = &fs[k];
    double t0 = (double)clock() / CLOCKS_PER_SEC;
    sweep_function(atm, f, k, eval, points, 1 + (uint64_t)index, calibrate, stats[k]);
    long total = 0, nonfinite = 0;
    for (int c = 0; c < HC_COUNT; ++c) {
      const class_stats *s = &stats[k][c];
      if (s->count < 0) continue;
      total += s->count;
      nonfinite += s->nonfinite;
      worst[f->row][c] = fmax(worst[f->row][c], s->max_err);
      if (f->physical && s->phys_count > 0) worst_phys[f->row][c] = fmax(worst_phys[f->row][c], s->phys_err);
      int t_first, with_t = t_index(f->input, &t_first) > 0;
      long allowed = with_t ? (long)(OUTLIER_SHARE * (double)s->count) : 0;
      if (s->outliers > allowed || (f->physical && s->phys_err > phys_bound[f->row][c]) || s->out_of_range ||
          getenv("SKYFIT_SWEEP_VERBOSE"))   /* debugging: every worst point */
        printf("  WORST %s [%s]: err %.3g (bound %.3g, %ld points over) at (%.9g, %.9g, %.9g, %.9g, %.9g), "
               "phys %.3g (bound %.3g) at (%.9g, %.9g, %.9g, %.9g), %ld out of range\n",
               f->name, hard_case_names[c], s->max_err, float_bound[f->row][c], s->outliers, s->worst[0],
               s->worst[1], s->worst[2], s->worst[3], s->worst[4], s->phys_err, phys_bound[f->row][c],
               s->phys_worst[0], s->phys_worst[1], s->phys_worst[2], s->phys_worst[3], s->out_of_range);
      CHECK(s->outliers <= allowed);
      CHECK(s->out_of_range == 0);
      if (f->physical) CHECK(s->phys_err <= phys_bound[f->row][c]);
    }
    long outliers = 0;
    for (int c = 0; c < HC_COUNT; ++c) outliers += stats[k][c].count > 0 ? stats[k][c].outliers : 0;
    printf("%-40s %8ld points, %ld non-finite, %ld over the bound (segment-class outliers), %.2f s\n", f->name,
           total, nonfinite, outliers, (double)clock() / CLOCKS_PER_SEC - t0);
    CHECK(total >= points - HC_COUNT);
    CHECK(nonfinite == 0);
  }
  print_table("float32 C header vs the same model in double: max error modulo ill-conditioning, per class (reduced "
              "only where over the bound: SKYFIT_SWEEP_CALIBRATE=1 shows it exactly down to 1e-6)", fs,
              n_fs, stats, 0);
  print_table("share of points over the bound accepted as ill-conditioned (within the model's own spread over "
              "mu +-4 ulp, t x (1 +- 1e-3))",
              fs, n_fs, stats, 2);
  print_table("float32 C header vs the same model in double: max error over ALL points", fs, n_fs, stats, 1);
  print_table("float32 C header vs the physical reference (exact optical depth), max |T_f - T_ref|, first 1500 "
              "points per class",
              fs, n_fs, stats, 3);
  printf("\natmosphere '%s': %.1f s CPU\n", sa->name, (double)clock() / CLOCKS_PER_SEC - t_start);
  free(stats);
  dlclose(lib);
}

int main(void) {
  const char *src = getenv("SKYFIT_SOURCE_DIR");
  const char *source_dir = src ? src : ".";
  long points_earth = SWEEP_POINTS_EARTH, points_other = SWEEP_POINTS_OTHER;
  const char *knob = getenv("SKYFIT_SWEEP_POINTS");
  if (knob && atol(knob) > 0) points_earth = points_other = atol(knob);
  snprintf(tmp_dir, sizeof tmp_dir, "/tmp/skyfit_sweep_XXXXXX");
  if (!mkdtemp(tmp_dir)) return 1;
  printf("working in %s; %ld points per function for Earth, %ld for the others\n", tmp_dir, points_earth,
         points_other);

  static sweep_atmosphere cases[N_ATMOSPHERES];
  static const char *const names[N_ATMOSPHERES] = {"earth", "thin", "thick", "faint", "dense"};
  static double worst[ROW_COUNT][HC_COUNT], worst_phys[ROW_COUNT][HC_COUNT];
  const char *only = getenv("SKYFIT_SWEEP_ONLY");   /* debugging: one atmosphere */
  /* recalibrating the bounds: every bound taken as 1e-6, so the tables show
   * the error modulo ill-conditioning exactly wherever it exceeds 1e-6 */
  int calibrate = getenv("SKYFIT_SWEEP_CALIBRATE") != NULL;
  for (int i = 0; i < N_ATMOSPHERES; ++i) {
    cases[i].name = names[i];
    make_atmosphere(i, &cases[i].atm);
    if (!only || strcmp(only, names[i]) == 0) sweep_atmosphere_run(&cases[i], i, i == 0, i == 0 ? points_earth : points_other, calibrate, source_dir, worst, worst_phys);
  }
  printf("\nmax over the atmospheres, float32 vs double, modulo ill-conditioning (bound):\n%-20s", "model");
  for (int c = 0; c < HC_COUNT; ++c) printf(" %19s", hard_case_names[c]);
  for (int r = 0; r < ROW_COUNT; ++r) {
    printf("\n%-20s", row_names[r]);
    for (int c = 0; c < HC_COUNT; ++c) printf("  %8.2e (%7.1e)", worst[r][c], float_bound[r][c]);
  }
  printf("\n\nmax over the atmospheres, float32 vs physical reference (bound):\n%-20s", "model");
  for (int c = 0; c < HC_COUNT; ++c) printf(" %19s", hard_case_names[c]);
  for (int r = 0; r <= ROW_MLP_T; ++r) {
    printf("\n%-20s", row_names[r]);
    for (int c = 0; c < HC_COUNT; ++c) printf("  %8.2e (%7.1e)", worst_phys[r][c], phys_bound[r][c]);
  }
  printf("\n");
  for (int i = 0; i < N_ATMOSPHERES; ++i) {
    for (int k = 0; k < cases[i].n_fitted; ++k) {
      sf_fitted_free(cases[i].fitted[k]);
      sf_weights_free(&cases[i].weights[k]);
    }
    if (!only || strcmp(only, names[i]) == 0) sf_spline_model_free(&cases[i].spline);
  }
  if (check_failed_count == 0) {
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmp_dir);
    run(cmd);
  }
  return check_summary();
}
