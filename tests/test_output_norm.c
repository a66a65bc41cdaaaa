/* The brightness normalisation of scattering networks (fit/output_norm.h,
 * models/mlp_sky.h):
 *  - the fit recovers a known log-brightness polynomial from a set whose
 *    slices have exactly that RMS (unlit slices present and ignored), and
 *    apply/restore give each slice RMS 1 and the original targets back;
 *  - with a cap e below the brightest slice, the cap is that slice's log
 *    RMS less e, and after apply the slices brighter than it keep their
 *    RMS over the cap's brightness, the others RMS 1;
 *  - a normalised model's radiance is the raw network's times exp(b), b
 *    from its definition (models/mlp_sky.h: the polynomial summed here
 *    monomial by monomial at the clamped inputs, capped, its slope term by
 *    term below the lowest sun, where the raw network is evaluated at the
 *    lowest sun), not by the model's Horner, in double and float32, for
 *    the sky network and with the horizon split, without and with a cap;
 *  - the weights file round-trips it bit for bit, and a file with a degree
 *    above SF_MLP_NORM_MAX_DEGREE, or a cap that is not finite, is refused
 *    naming the key. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/output_norm.h"
#include "fit/train.h"
#include "models/atmosphere_file.h"
#include "models/mlp_sky.h"
#include "models/rng.h"
#include "models/single_scattering.h"
#include "models/weights_file.h"
#include "tests/check.h"
#include "tests/mlp_scattering_test_weights.h"

#define NU 9    /* slices in u */
#define NV 11   /* slices in v */
#define PER 6   /* samples per slice (even: the pattern's RMS is exactly 1) */

/* b(u, v) with degrees 2, 3, coef[a * 4 + c] of u^a v^c */
static const double true_coef[3 * 4] = {-3.0, 2.5, -1.2, 0.4, 0.7, -0.3, 0.25, 0.1, -0.6, 0.2, 0.05, -0.15};

static double true_b(double u, double v) {
  double sum = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 4; ++c) sum += true_coef[a * 4 + c] * pow(u, a) * pow(v, c);
  return sum;
}

/* The model's b (models/mlp_sky.h) from the definition: the polynomial at
 * the clamped inputs, at most cap, and below v = -1 its slope there (d/dv
 * summed term by term), never rising. */
static double model_b(double u, double v, double cap) {
  double uc = fmin(fmax(u, -1.0), 1.0), vc = fmin(fmax(v, -1.0), 1.0), slope = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int c = 1; c < 4; ++c) slope += true_coef[a * 4 + c] * pow(uc, a) * c * pow(-1.0, c - 1);
  return fmin(true_b(uc, vc), cap) + fmax(slope, 0.0) * fmin(v + 1.0, 0.0);
}

static void test_fit(void) {
  sf_error err = {0};
  sf_dataset d;
  CHECK(sf_dataset_init(&d, (long)(NU * NV + 3) * PER, 4, 3, &err) == SF_OK);
  sf_rng rng;
  sf_rng_seed(&rng, 5, 0, 0);
  long i = 0;
  /* samples of a slice interleaved with others': the fit must group them */
  for (int k = 0; k < PER; ++k)
    for (int s = 0; s < NU * NV + 3; ++s, ++i) {
      int unlit = s >= NU * NV;   /* three slices of zeros at u = -1 */
      double u = unlit ? -1.0 : -1.0 + 2.0 * (s / NV) / (NU - 1.0);
      double v = unlit ? -0.95 + 0.1 * (s - NU * NV) : -1.0 + 2.0 * (s % NV) / (NV - 1.0);
      double *x = d.x + i * 4, *y = d.y + i * 3;
      x[0] = u;
      x[1] = 2.0 * sf_rng_uniform(&rng) - 1.0;
      x[2] = v;
      x[3] = 2.0 * sf_rng_uniform(&rng) - 1.0;
      /* per-sample pattern 0.5 or sqrt(1.75) in every output: mean square 1 */
      double pattern = k % 2 ? 0.5 : sqrt(1.75);
      for (int o = 0; o < 3; ++o) y[o] = unlit ? 0.0 : exp(true_b(u, v)) * pattern;
    }
  sf_mlp_output_norm n;
  CHECK(sf_output_norm_fit(&d, 2, 3, INFINITY, &n, &err) == SF_OK);
  CHECK(n.active && n.degree_h == 2 && n.degree_mu_s == 3);
  double worst = 0.0;
  for (int k = 0; k < 12; ++k) worst = worst_of(worst, fabs(n.coef[k] - true_coef[k]));
  printf("largest coefficient error %.3g\n", worst);
  CHECK(worst < 1e-12);
  double *y0 = malloc(sizeof *y0 * (size_t)d.n * 3);
  memcpy(y0, d.y, sizeof *y0 * (size_t)d.n * 3);
  sf_output_norm_apply(&n, &d);
  /* every lit slice now has RMS 1: sample k of slice s is k * (NU NV + 3) + s */
  double worst_rms = 0.0;
  for (int s = 0; s < NU * NV; ++s) {
    double sq = 0.0;
    for (int k = 0; k < PER; ++k)
      for (int o = 0; o < 3; ++o) sq += pow(d.y[((long)k * (NU * NV + 3) + s) * 3 + o], 2);
    worst_rms = worst_of(worst_rms, fabs(sqrt(sq / (PER * 3)) - 1.0));
  }
  printf("largest |slice RMS - 1| after apply %.3g\n", worst_rms);
  CHECK(worst_rms < 1e-12);
  sf_output_norm_restore(&n, &d);
  double worst_back = 0.0;
  for (long j = 0; j < d.n * 3; ++j)
    worst_back = worst_of(worst_back, fabs(d.y[j] - y0[j]) / (fabs(y0[j]) > 0.0 ? fabs(y0[j]) : 1.0));
  printf("restore: largest relative change %.3g\n", worst_back);
  CHECK(worst_back < 1e-14);
  /* capped 1.5 below the brightest slice */
  double brightest = -INFINITY;
  for (int s = 0; s < NU * NV; ++s) brightest = fmax(brightest, true_b(-1.0 + 2.0 * (s / NV) / (NU - 1.0), -1.0 + 2.0 * (s % NV) / (NV - 1.0)));
  CHECK(sf_output_norm_fit(&d, 2, 3, 1.5, &n, &err) == SF_OK);
  printf("cap %.17g, brightest slice's log RMS %.17g\n", n.cap, brightest);
  CHECK(n.has_cap && fabs(n.cap - (brightest - 1.5)) < 1e-12);
  sf_output_norm_apply(&n, &d);
  int above = 0;
  worst_rms = 0.0;
  for (int s = 0; s < NU * NV; ++s) {
    double b = true_b(-1.0 + 2.0 * (s / NV) / (NU - 1.0), -1.0 + 2.0 * (s % NV) / (NV - 1.0));
    double sq = 0.0;
    for (int k = 0; k < PER; ++k)
      for (int o = 0; o < 3; ++o) sq += pow(d.y[((long)k * (NU * NV + 3) + s) * 3 + o], 2);
    above += b > n.cap;
    worst_rms = worst_of(worst_rms, fabs(sqrt(sq / (PER * 3)) / exp(fmax(b - n.cap, 0.0)) - 1.0));
  }
  printf("capped: %d slices above the cap; largest |slice RMS / exp(max(b - cap, 0)) - 1| %.3g\n", above, worst_rms);
  CHECK(above >= 3 && above < NU * NV / 2);
  CHECK(worst_rms < 1e-12);
  sf_output_norm_restore(&n, &d);
  sf_error_clear(&err);
  CHECK(sf_output_norm_fit(&d, 2, 3, -0.5, &n, &err) == SF_ERR_INPUT);
  printf("refused: %s\n", err.message);
  /* a degree out of range; more coefficients than slices (the first 40
   * samples are 40 slices); a set of zeros */
  CHECK(sf_output_norm_fit(&d, 8, 1, INFINITY, &n, &err) == SF_ERR_INPUT);
  printf("refused: %s\n", err.message);
  long all = d.n;
  d.n = 40;
  sf_error_clear(&err);
  CHECK(sf_output_norm_fit(&d, 7, 7, INFINITY, &n, &err) == SF_ERR_INPUT);
  printf("refused: %s\n", err.message);
  d.n = all;
  for (long j = 0; j < d.n * 3; ++j) d.y[j] = 0.0;
  sf_error_clear(&err);
  CHECK(sf_output_norm_fit(&d, 1, 1, INFINITY, &n, &err) == SF_ERR_INPUT);
  printf("refused: %s\n", err.message);
  free(y0);
  sf_dataset_free(&d);
}

static sf_mlp random_network(uint64_t seed) {
  sf_mlp_shape ss = {3, {4, 8, 8, 9}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG};
  sf_mlp net;
  sf_mlp_init(&net, &ss);
  sf_mlp_init_xavier(&ss, seed, 1, net.params);
  return net;
}

static void make_model(const sf_atmosphere *atm, int split, sf_mlp_sky *s) {
  sf_error err = {0};
  double top = atm->top_radius_km - atm->bottom_radius_km;
  double off[4] = {0.5 * sqrt(top), 0.0, 0.4, 0.0}, sc[4] = {2.0 / sqrt(top), 1.0, 1.0 / 0.6, 1.0};
  int constituents[2] = {0, 1};
  sf_mlp net = random_network(3);
  CHECK(sf_mlp_sky_make(s, &net, SF_MLP_TARGET_SEPARATE, atm, off, sc, 2, constituents, &err) == SF_OK);
  if (split) {
    sf_mlp ground = random_network(4);
    CHECK(sf_mlp_sky_set_ground_net(s, &ground, &err) == SF_OK);
  }
}

static void replace_param(cJSON *doc, const char *name, int n_dims, const int *shape, const double *values) {
  cJSON_DeleteItemFromObject(cJSON_GetObjectItem(doc, "params"), name);
  sf_weights_add_param(doc, name, n_dims, shape, values);
}

/* doc, printed as bad.json, is refused naming the file and key: by the
 * weights file's own checks (a number beyond float32) or, loaded, by the
 * network's */
static void expect_refused(const cJSON *doc, const char *key) {
  sf_error err = {0};
  sf_weights w;
  sf_mlp_sky back;
  char *text = sf_weights_print(doc);
  if (!CHECK(text != NULL)) return;
  if (sf_weights_load_string(text, "bad.json", NULL, &w, &err) == SF_OK) {
    CHECK(sf_mlp_sky_from_weights(&w, &back, &err) == SF_ERR_INPUT);
    sf_weights_free(&w);
  }
  printf("refused: %s\n", err.message);
  CHECK(err.status == SF_ERR_INPUT && strstr(err.message, "bad.json") && strstr(err.message, key));
  free(text);
}

static void test_model(const sf_atmosphere *atm, int split, double cap) {
  sf_error err = {0};
  sf_mlp_sky raw, normed;
  make_model(atm, split, &raw);
  make_model(atm, split, &normed);
  sf_mlp_output_norm n;
  memset(&n, 0, sizeof n);
  n.degree_h = 2;
  n.degree_mu_s = 3;
  memcpy(n.coef, true_coef, sizeof true_coef);
  n.has_cap = isfinite(cap);
  n.cap = n.has_cap ? cap : 0.0;
  CHECK(sf_mlp_sky_set_output_norm(&normed, 0, &n, &err) == SF_OK);
  sf_rng rng;
  sf_rng_seed(&rng, 9, split, 0);
  double worst_d = 0.0, worst_f = 0.0;
  int ground_rays = 0, below = 0, capped = 0;
  for (int i = 0; i < 4000; ++i) {
    double h = 100.0 * pow(sf_rng_uniform(&rng), 2.0), mu = 2.0 * sf_rng_uniform(&rng) - 1.0;
    double mu_s = 2.0 * sf_rng_uniform(&rng) - 1.0, nu = 2.0 * sf_rng_uniform(&rng) - 1.0;
    nu = sf_clamp_nu(mu, mu_s, nu);
    int ground = split && sf_mlp_ray_ends_on_ground(atm->bottom_radius_km, h, mu);
    ground_rays += ground;
    /* the ground network has no normalisation: factor 1 there (x2 reaches
     * -2.3 here: b extrapolated below the fitted square, where the sky
     * network itself sees the sun at the square's edge v = -1: the raw
     * model is evaluated there, for a nu both suns allow) */
    double u = (sqrt(h) - raw.offset[0]) * raw.scale[0], v = (mu_s - raw.offset[2]) * raw.scale[2];
    double f = ground ? 1.0 : exp(model_b(u, v, cap));
    capped += !ground && isfinite(cap) && true_b(fmin(fmax(u, -1.0), 1.0), fmin(fmax(v, -1.0), 1.0)) > cap;
    double mu_s_net = !ground && v < -1.0 ? raw.offset[2] - 1.0 / raw.scale[2] : mu_s;
    if (sf_clamp_nu(mu, mu_s_net, nu) != nu) continue;
    below += !ground && v < -1.0;
    double L0[3], L1[3];
    float F0[3], F1[3];
    sf_mlp_scattering(&raw, h, mu, mu_s_net, nu, L0);
    sf_mlp_scattering(&normed, h, mu, mu_s, nu, L1);
    sf_mlp_scattering_f(&raw, (float)h, (float)mu, (float)mu_s_net, (float)nu, F0);
    sf_mlp_scattering_f(&normed, (float)h, (float)mu, (float)mu_s, (float)nu, F1);
    for (int c = 0; c < 3; ++c) {
      if (L0[c] > 0.0) worst_d = worst_of(worst_d, fabs(L1[c] - f * L0[c]) / (f * L0[c]));
      if (F0[c] > 0.0f) worst_f = worst_of(worst_f, fabs((double)F1[c] - f * (double)F0[c]) / (f * (double)F0[c]));
    }
  }
  printf("split %d, cap %g (%d ground rays, %d sky rays with the sun below the square, %d capped): normalised / raw "
         "vs exp(b): double %.3g, float32 %.3g\n", split, cap, ground_rays, below, capped, worst_d, worst_f);
  CHECK(worst_d < 1e-13);
  CHECK(worst_f < 1e-5);
  CHECK(!split || ground_rays > 100);
  CHECK(below > 500);
  CHECK(!isfinite(cap) || capped > 200);
  /* the slope at v = -1 of this polynomial is positive over u in [0, 1]:
   * b keeps falling below the square */
  CHECK(model_b(0.5, -2.0, cap) < model_b(0.5, -1.0, cap) - 1.0);
  /* weights round trip */
  sf_scene_domain domain = {0.0, 100.0, -1.0, 1.0, -1.0, 1.0};
  cJSON *doc = mlp_scattering_weights_doc(atm, &domain, normed.offset, normed.scale);
  CHECK(sf_mlp_add_to_weights(doc, &normed.net) == SF_OK);
  if (split) CHECK(sf_mlp_add_params_to_weights(doc, &normed.net_ground, "ground_") == SF_OK);
  CHECK(sf_mlp_sky_add_norms_to_weights(doc, &normed) == SF_OK);
  char *text = sf_weights_print(doc);
  sf_weights w;
  sf_mlp_sky back;
  CHECK(text && sf_weights_load_string(text, "normed.json", NULL, &w, &err) == SF_OK);
  CHECK(sf_mlp_sky_from_weights(&w, &back, &err) == SF_OK);
  CHECK(back.norm.active && !back.norm_ground.active && back.norm.degree_h == 2 && back.norm.degree_mu_s == 3);
  CHECK(memcmp(back.norm.coef, normed.norm.coef, sizeof true_coef) == 0);
  CHECK(back.norm.has_cap == normed.norm.has_cap && (!back.norm.has_cap || back.norm.cap == normed.norm.cap));
  double a[3], b[3];
  sf_mlp_scattering(&normed, 1.5, 0.2, 0.1, 0.3, a);
  sf_mlp_scattering(&back, 1.5, 0.2, 0.1, 0.3, b);
  CHECK(memcmp(a, b, sizeof a) == 0);
  sf_mlp_sky_free(&back);
  sf_weights_free(&w);
  free(text);
  /* degree 8 in u: refused, naming the file and key */
  double big[9 * 2] = {0};
  replace_param(doc, "norm_coef", 2, (const int[]){9, 2}, big);
  expect_refused(doc, "params.norm_coef");
  /* a cap of 1e300 (the float32 cap would be infinite): refused */
  replace_param(doc, "norm_coef", 2, (const int[]){3, 4}, true_coef);
  replace_param(doc, "norm_cap", 1, (const int[]){1}, (const double[]){1e300});
  expect_refused(doc, "params.norm_cap");
  cJSON_Delete(doc);
  sf_mlp_sky_free(&raw);
  sf_mlp_sky_free(&normed);
}

/* sf_output_norm_prepare on a set whose dark slices (sun far below the
 * horizon) are faint but not black: log brightness 13 v - 13 on the lit
 * half v >= 0 (down to e^-13, above the 1e-6 floor), targets 1e-7 on the
 * dark half. The polynomial, exact on the lit half, reaches -26 at v = -1
 * and would scale those targets to 1e-7 e^26 = 2e4 (a thin shell's set had
 * reached 2.4e6 and diverged, a huge planet's inf): the set stays raw and
 * the reason names the dark slice. The same set with black dark slices is
 * normalised. */
static void test_dark_slices(double dark_target, int want_active) {
  sf_error err = {0};
  sf_dataset d;
  enum { SU = 5, SV = 21 };
  CHECK(sf_dataset_init(&d, SU * SV, 4, 1, &err) == SF_OK);
  for (int s = 0; s < SU * SV; ++s) {
    double u = -1.0 + 2.0 * (s / SV) / (SU - 1.0), v = -1.0 + 2.0 * (s % SV) / (SV - 1.0);
    double *x = d.x + (long)s * 4;
    x[0] = u;
    x[1] = 0.5;
    x[2] = v;
    x[3] = 0.0;
    d.y[s] = v >= 0.0 ? exp(13.0 * v - 13.0) : dark_target;
  }
  double *y0 = malloc(sizeof *y0 * SU * SV);
  memcpy(y0, d.y, sizeof *y0 * SU * SV);
  sf_mlp_output_norm n;
  char why[512];
  CHECK(sf_output_norm_prepare(&d, INFINITY, &n, why, sizeof why, &err) == SF_OK);
  printf("dark slices at %g: %s%s\n", dark_target, n.active ? "normalised" : "raw: ", why);
  CHECK(n.active == want_active);
  if (!want_active) {
    CHECK(strstr(why, "dark slice") != NULL && strstr(why, "mu_s -1") != NULL);
    CHECK(memcmp(y0, d.y, sizeof *y0 * SU * SV) == 0);   /* left raw */
  } else {
    double worst = 0.0;
    for (int s = 0; s < SU * SV; ++s) worst = worst_of(worst, fabs(d.y[s]));
    printf("largest normalised target %.3g\n", worst);
    CHECK(worst <= SF_OUTPUT_NORM_MAX_SCALED);
    CHECK(n.degree_mu_s == SF_OUTPUT_NORM_DEGREE_MU_S);   /* fitted exactly: no lower degree */
  }
  free(y0);
  sf_dataset_free(&d);
}

/* sf_output_norm_prepare on the slices of a real coarse set: the log RMS of
 * the sky network's targets per (altitude, sun elevation) of a hazy Earth
 * (`"base": "default"`, Mie 0.012/km with a 2 km scale height) on
 * 16x64x16x8 tables over a 0-10 km scene (`skyfit fit mlp-scattering
 * --dump-dataset`): Bruneton's mu_s axis leaves only two slices above 40
 * degrees (v 0.39 and 1). At every altitude the brightness rises with the
 * sun, so between two slices it lies between them; the piecewise-linear
 * interpolation of their logs stands for it. The degree-6 fit dipped 2.3
 * below it between those two slices (a factor 10: the build's network was
 * 0.15x the reference at sun 64 degrees); the fit prepared must stay within
 * a factor 2 of it everywhere between the lowest and the highest sun,
 * capped as the fit is, and still normalise. */
static void test_sparse_sun_slices(void) {
  enum { SU = 5, SV = 15 };
  static const double u_of[SU] = {-1.0, -0.576716, -0.153477, 0.269672, 0.692688};
  static const double v_of[SV] = {-0.957547, -0.878546, -0.812290, -0.753321, -0.697928, -0.643208, -0.586505,
                                  -0.524961, -0.455018, -0.371664, -0.267066, -0.127697, 0.072626, 0.392806, 1.0};
  static const double log_rms[SU][SV] = {
      {-9.8179, -7.7882, -6.1907, -4.9136, -3.9186, -3.2568, -2.8571, -2.5822, -2.3744, -2.2083, -2.0700, -1.9515,
       -1.8474, -1.7541, -1.6693},
      {-9.6806, -7.6859, -6.1156, -4.8463, -3.8236, -3.1003, -2.6675, -2.3753, -2.1554, -1.9790, -1.8316, -1.7046,
       -1.5927, -1.4922, -1.4007},
      {-9.2807, -7.3691, -5.8643, -4.6075, -3.5503, -2.8632, -2.4562, -2.1782, -1.9690, -1.8026, -1.6650, -1.5478,
       -1.4455, -1.3545, -1.2722},
      {-8.7702, -6.9598, -5.5294, -4.2585, -3.2291, -2.6284, -2.2565, -1.9969, -1.8032, -1.6518, -1.5290, -1.4260,
       -1.3373, -1.2592, -1.1893},
      {-8.2589, -6.5462, -5.1762, -3.8671, -2.9503, -2.4164, -2.0708, -1.8323, -1.6589, -1.5267, -1.4212, -1.3341,
       -1.2598, -1.1950, -1.1374}};
  sf_error err = {0};
  sf_dataset d;
  CHECK(sf_dataset_init(&d, SU * SV, 4, 1, &err) == SF_OK);
  double brightest = -INFINITY;
  for (int s = 0; s < SU * SV; ++s) {
    double *x = d.x + (long)s * 4;
    x[0] = u_of[s / SV];
    x[1] = 0.5;
    x[2] = v_of[s % SV];
    x[3] = 0.0;
    d.y[s] = exp(log_rms[s / SV][s % SV]);   /* one sample: its RMS */
    brightest = fmax(brightest, log_rms[s / SV][s % SV]);
    if (s % SV) CHECK(log_rms[s / SV][s % SV] > log_rms[s / SV][s % SV - 1]);   /* rising with the sun */
  }
  sf_mlp_output_norm n;
  char why[512];
  CHECK(sf_output_norm_prepare(&d, SF_OUTPUT_NORM_CAP_BELOW, &n, why, sizeof why, &err) == SF_OK);
  printf("sparse sun slices: %s%s, degree in mu_s %d\n", n.active ? "normalised" : "raw: ", why, n.degree_mu_s);
  CHECK(n.active);
  double cap = brightest - SF_OUTPUT_NORM_CAP_BELOW, worst = 0.0, at_u = 0.0, at_v = 0.0;
  for (int a = 0; a < SU; ++a)
    for (int j = 0; j + 1 < SV; ++j)
      for (int k = 0; k <= 32; ++k) {
        double t = k / 32.0, v = v_of[j] + (v_of[j + 1] - v_of[j]) * t;
        double truth = fmin(log_rms[a][j] + (log_rms[a][j + 1] - log_rms[a][j]) * t, cap);
        double e = fabs(fmin(sf_mlp_output_norm_log_brightness(&n, u_of[a], v), cap) - truth);
        if (e > worst) {
          worst = e;
          at_u = u_of[a];
          at_v = v;
        }
      }
  printf("sparse sun slices: largest |b - interpolated log RMS| %.3g at u %.3g, v %.3g (bound ln 2)\n", worst, at_u,
         at_v);
  CHECK(worst < log(2.0));
  sf_dataset_free(&d);
}

int main(void) {
  test_fit();
  test_dark_slices(1e-7, 0);
  test_dark_slices(0.0, 1);
  test_sparse_sun_slices();
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  test_model(&atm, 0, INFINITY);
  test_model(&atm, 1, INFINITY);
  /* a cap crossing the polynomial's range over the square (-5.1..-1.4) */
  test_model(&atm, 0, -2.5);
  test_model(&atm, 1, -2.5);
  return check_summary();
}
