/* The emitted transmittance MLP in float32 on SPEC §10's very thick
 * atmosphere (every coefficient x1e3), where eq. 43's T_viewer/T_intersect
 * is a ratio of two transmittances near 0: the network gives the optical
 * depth to the top, tau ~ 1e2..1e4, and a segment is exp(-(tau_a - tau_b)).
 * tests/test_float32_sweep.c sweeps the MLPs on Earth's shipped weights
 * only (tau <= ~40); this test fits one here on the thick atmosphere
 * (`skyfit fit mlp-transmittance`, ~6 s), emits its C header
 * (sf_codegen_write, as `skyfit codegen` writes it), compiles it as the
 * sweep does (C99, -Wall -Wextra -Werror -pedantic, ISO mode) and compares
 * it with the same model in double (models/mlp_sky.h) at the hard-case
 * points of tests/hard_case_points.h: h = 0 looking down, T -> 0 (long
 * grazing rays), segments, anywhere.
 *
 * The error of a point is measured modulo the inputs' own float32
 * resolution: the distance of the float32 result from the range of the
 * double model over h and mu moved by -4..4 float ulp (and the segment's
 * distance by 1 +- 1e-3), so a jump at the horizon is not counted. A
 * ray from h = 1e-5 km looking down at mu = -0.2 is well conditioned
 * (T moves by ~1e-9 over those ulps); the bound is the one the sweep
 * states for the same functions on Earth (mlp-transmittance: h0-down and
 * T->0 1e-4, domain 5e-5, segment 5e-4), and no NaN or Inf. */
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "codegen/codegen_file.h"
#include "codegen/fitted_part.h"
#include "emitted_library.h"
#include "hard_case_points.h"
#include "models/atmosphere_file.h"
#include "models/mlp_sky.h"
#include "models/weights_file.h"

#define POINTS_PER_CLASS 20000
#define ENVELOPE_ULP 4

/* The default atmosphere with every coefficient x1e3 ("base": "default"
 * keeps the rest: radii, densities, phases). */
static int write_dense_atmosphere(const char *path) {
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f,
          "{\"base\": \"default\", \"name\": \"dense-x1e3\", \"constituents\": [\n"
          " {\"name\": \"rayleigh\", \"scattering\": [5.802, 13.558, 33.1], \"absorption\": [0, 0, 0],\n"
          "  \"phase\": {\"kind\": \"rayleigh\"},\n"
          "  \"density\": [{\"width_km\": 0, \"exp_term\": 1, \"exp_scale_per_km\": -0.125}]},\n"
          " {\"name\": \"mie\", \"scattering\": [3.996, 3.996, 3.996], \"absorption\": [0.444, 0.444, 0.444],\n"
          "  \"phase\": {\"kind\": \"cornette_shanks\", \"g\": 0.8},\n"
          "  \"density\": [{\"width_km\": 0, \"exp_term\": 1, \"exp_scale_per_km\": -0.8333333}]},\n"
          " {\"name\": \"ozone\", \"scattering\": [0, 0, 0], \"absorption\": [0.650, 1.881, 0.085],\n"
          "  \"density\": [{\"width_km\": 25, \"linear_per_km\": 0.0666667, \"constant\": -0.6666667},\n"
          "              {\"width_km\": 0, \"linear_per_km\": -0.0666667, \"constant\": 2.6666667}]}]}\n");
  return fclose(f);
}

typedef void (*eval_fn)(int fn, int n, const float *in, float *out);

/* The double model at p; fn 0: full ray (h, mu), 1: segment (h, mu, d). */
static void model_d(const sf_mlp_sky *m, int fn, const float *p, double *T) {
  if (fn == 0) sf_mlp_transmittance(m, p[0], p[1], T);
  else sf_mlp_transmittance_segment(m, p[0], p[1], p[2], T);
}

/* How far got lies outside the double model's values over h and mu moved
 * by -ENVELOPE_ULP..ENVELOPE_ULP float ulp (and d by 1 +- 1e-3). */
static double excess(const sf_mlp_sky *m, int fn, const float *p, const float *got) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int dh = -ENVELOPE_ULP; dh <= ENVELOPE_ULP; ++dh)
    for (int dm = -ENVELOPE_ULP; dm <= ENVELOPE_ULP; ++dm)
      for (int dd = -1; dd <= 1; ++dd) {
        if (fn == 0 && dd != 0) continue;
        float q[8];
        memcpy(q, p, sizeof q);
        for (int k = 0; k < abs(dh); ++k) q[0] = nextafterf(q[0], dh < 0 ? -1e30f : 1e30f);
        for (int k = 0; k < abs(dm); ++k) q[1] = nextafterf(q[1], dm < 0 ? -2.0f : 2.0f);
        q[0] = fmaxf(q[0], 0.0f);
        q[1] = fminf(fmaxf(q[1], -1.0f), 1.0f);
        if (fn == 1) q[2] = (float)(q[2] * (1.0 + 1e-3 * dd));
        double T[3];
        model_d(m, fn, q, T);
        for (int c = 0; c < 3; ++c) {
          lo[c] = fmin(lo[c], T[c]);
          hi[c] = fmax(hi[c], T[c]);
        }
      }
  double e = 0.0;
  for (int c = 0; c < 3; ++c) e = fmax(e, fmax(0.0, fmax(lo[c] - got[c], got[c] - hi[c])));
  return e;
}

static void sweep(const sf_mlp_sky *m, const sf_atmosphere *atm, eval_fn eval, int fn, hard_case_class c,
                  double bound) {
  static float in[8 * POINTS_PER_CLASS], out[4 * POINTS_PER_CLASS];
  hard_case_rng g = {0x5eed0000u + 17u * (uint64_t)fn + (uint64_t)c};
  hard_case_input kind = fn == 0 ? HI_RAY : HI_RAY_T;
  for (int i = 0; i < POINTS_PER_CLASS; ++i) hard_case_point(&g, c, kind, atm, 0, in + 8 * i);
  eval(fn, POINTS_PER_CLASS, in, out);
  long nonfinite = 0, over = 0;
  double worst = 0.0, worst_raw = 0.0;
  float worst_at[3] = {0, 0, 0};
  double worst_got = 0, worst_want = 0;
  for (int i = 0; i < POINTS_PER_CLASS; ++i) {
    const float *p = in + 8 * i, *got = out + 4 * i;
    double want[3];
    model_d(m, fn, p, want);
    double e = 0.0;
    for (int ch = 0; ch < 3; ++ch) {
      if (!isfinite(got[ch])) ++nonfinite;
      e = fmax(e, fabs(got[ch] - want[ch]));
    }
    worst_raw = fmax(worst_raw, e);
    if (e > bound) e = fmin(e, excess(m, fn, p, got));
    if (e > bound) ++over;
    if (e > worst) {
      worst = e;
      memcpy(worst_at, p, sizeof worst_at);
      worst_got = got[2];
      worst_want = want[2];
    }
  }
  printf("%-38s %-8s: max |T_f - T_d| modulo input ulps %.3g (bound %.3g, raw %.3g), %ld of %d over, %ld "
         "non-finite; worst at h %.9g mu %.9g d %.9g: blue %.9g, double %.9g\n",
         fn == 0 ? "skyfit_mlp_transmittance" : "skyfit_mlp_transmittance_segment", hard_case_names[c], worst,
         bound, worst_raw, over, POINTS_PER_CLASS, nonfinite, worst_at[0], worst_at[1], fn ? worst_at[2] : 0.0f,
         worst_got, worst_want);
  CHECK(nonfinite == 0);
  CHECK(worst <= bound);
}

int main(void) {
  const char *bin = getenv("SKYFIT_BIN");
  if (!bin) bin = "./skyfit";
  char dir[] = "/tmp/skyfit_mlp_dense_XXXXXX";
  if (!mkdtemp(dir)) return 1;
  char atm_path[512], w_path[512], cmd[2048], driver[512], so[512];
  snprintf(atm_path, sizeof atm_path, "%s/dense.json", dir);
  snprintf(w_path, sizeof w_path, "%s/mlp-transmittance.json", dir);
  if (!CHECK(write_dense_atmosphere(atm_path) == 0)) return check_summary();
  /* a small transmittance table, the default network and training */
  snprintf(cmd, sizeof cmd,
           "%s fit mlp-transmittance --atmosphere %s --resolution 64x16,8x32x8x4 --epochs 30 --threads 1 "
           "--quiet --out %s",
           bin, atm_path, w_path);
  fflush(stdout);
  if (!CHECK(system(cmd) == 0)) return check_summary();

  sf_error err;
  sf_error_clear(&err);
  sf_weights w;
  sf_fitted_model *fm = NULL;
  sf_codegen_part part;
  if (!CHECK(sf_weights_load_file(w_path, "mlp-transmittance", &w, &err) == SF_OK) ||
      !CHECK(sf_fitted_part(&w, &fm, &part, &err) == SF_OK) ||
      !CHECK(sf_codegen_write(&part, 1, 1, 0, dir, "dense", NULL, &err) == SF_OK)) {
    printf("%s\n", err.message);
    return check_summary();
  }
  snprintf(driver, sizeof driver, "%s/driver.c", dir);
  snprintf(so, sizeof so, "%s/dense.so", dir);
  const char *text =
      "#include \"dense.h\"\n"
      "void ev(int fn, int n, const float *in, float *out);\n"
      "void ev(int fn, int n, const float *in, float *out) {\n"
      "  int i;\n"
      "  for (i = 0; i < n; ++i) {\n"
      "    const float *p = in + 8 * i;\n"
      "    skyfit_vec3 v = fn == 0 ? skyfit_mlp_transmittance(p[0], p[1])\n"
      "                            : skyfit_mlp_transmittance_segment(p[0], p[1], p[2]);\n"
      "    out[4 * i] = v.x; out[4 * i + 1] = v.y; out[4 * i + 2] = v.z;\n"
      "  }\n"
      "}\n";
  if (!CHECK(emitted_library_build(driver, text, so) == 0)) return check_summary();
  void *lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
  if (!CHECK(lib != NULL)) return check_summary();
  eval_fn eval;
  *(void **)&eval = dlsym(lib, "ev");
  if (!CHECK(eval != NULL)) return check_summary();

  sf_atmosphere atm;
  sf_atmosphere_default(&atm);   /* the radii: what the hard-case points need */
  /* bounds: tests/test_float32_sweep.c's mlp-transmittance row */
  sweep(&fm->mlp, &atm, eval, 0, HC_DOMAIN, 5e-5);
  sweep(&fm->mlp, &atm, eval, 0, HC_GROUND_DOWN, 1e-4);
  sweep(&fm->mlp, &atm, eval, 0, HC_DEEP, 1e-4);
  sweep(&fm->mlp, &atm, eval, 1, HC_GROUND_DOWN, 1e-4);
  sweep(&fm->mlp, &atm, eval, 1, HC_DEEP, 1e-4);
  dlclose(lib);
  sf_fitted_free(fm);
  sf_weights_free(&w);
  if (check_failed_count == 0) {
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    fflush(stdout);
    if (system(cmd) != 0) printf("could not remove %s\n", dir);
  }
  return check_summary();
}
