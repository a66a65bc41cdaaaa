/* The transmittance network's horizon-aware inputs (models/mlp_sky.h,
 * Bruneton 2017's x_r, x_mu):
 *  1. sf_mlp_bruneton_coords against an independent long-double evaluation
 *     of the textbook formulas (rho = sqrt(r^2 - R^2), d = -r mu +
 *     sqrt(r^2 (mu^2 - 1) + Rt^2)) and against the closed-form corners
 *     (ground zenith (0, 0), ground horizon (0, 1), top zenith (1, 0), a
 *     ray tangent to the ground x_mu = 1 at any altitude), and the inverse
 *     map (used by the metrics on normalised data sets) recovering (h, mu);
 *  2. float32 against double through a random network with these inputs
 *     (T_top, full rays, segments) on random points and on the SPEC §10 hard
 *     cases: no NaN/Inf, within a stated bound;
 *  3. the weights file: inputs named "x_r", "x_mu" load as this mapping and
 *     evaluate bit for bit as the network built in memory; "sqrt_h_km", "mu"
 *     still load as the original mapping; a mixed pair is refused naming
 *     the file and inputs[1].name;
 *  4. the emitted C header (codegen/emit_mlp.c), compiled with cc -std=c99
 *     and run, agrees with the model's float32 path (models/mlp_sky_impl.inc,
 *     the same operations) on random points and the hard cases: full rays,
 *     segments, T_top. (The GLSL is compiled by tests/cli_fit_mlp.sh.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/codegen_file.h"
#include "codegen/emit_mlp.h"
#include "fit/train.h"
#include "models/atmosphere_file.h"
#include "models/mlp_sky.h"
#include "models/ray_geometry.h"
#include "models/rng.h"
#include "tests/check.h"

static void textbook_coords(double R, double Rt, double h, double mu, double *x_r, double *x_mu) {
  long double r = (long double)R + h, Rl = R, Rtl = Rt;
  long double H = sqrtl(Rtl * Rtl - Rl * Rl), rho = sqrtl(r * r - Rl * Rl);
  long double d = -r * mu + sqrtl(r * r * ((long double)mu * mu - 1.0L) + Rtl * Rtl);
  long double d_min = Rtl - r, d_max = rho + H;
  *x_r = (double)(rho / H);
  *x_mu = (double)((d - d_min) / (d_max - d_min));
}

/* A 2-8-8-3 network on (x_r, x_mu) with the normalisation the data sets use. */
static int make_model(const sf_atmosphere *atm, sf_mlp_input_map map, sf_mlp_sky *t) {
  sf_error err = {0};
  sf_mlp_shape s = {3, {2, 8, 8, 3}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG};
  sf_mlp net;
  if (sf_mlp_init(&net, &s)) return -1;
  sf_mlp_init_xavier(&s, 21, 0, net.params);
  for (int k = 0; k < 3; ++k) net.params[sf_mlp_bias_offset(&s, 2) + k] += 0.3 + 0.2 * k;
  double off[2] = {0.5, 0.5}, sc[2] = {2.0, 2.0};
  if (map == SF_MLP_INPUTS_SQRT_H_MU) {
    double top = atm->top_radius_km - atm->bottom_radius_km;
    off[0] = 0.5 * sqrt(top), sc[0] = 2.0 / sqrt(top), off[1] = 0.0, sc[1] = 1.0;
  }
  if (sf_mlp_sky_make(t, &net, SF_MLP_TARGET_TRANSMITTANCE_TOP, atm, off, sc, 0, NULL, &err)) {
    printf("make: %s\n", err.message);
    return -1;
  }
  t->input_map = map;
  return 0;
}

static cJSON *weights_doc(const sf_atmosphere *atm, const sf_mlp_sky *t, const char *name0, const char *name1) {
  sf_scene_domain dom = {0.0, 100.0, -1.0, 1.0, -0.2, 1.0};
  cJSON *doc = sf_weights_new("mlp-transmittance", "transmittance", atm, &dom);
  sf_weights_add_input(doc, name0, t->offset[0], t->scale[0]);
  sf_weights_add_input(doc, name1, t->offset[1], t->scale[1]);
  cJSON_AddStringToObject(sf_weights_training(doc), "target", "transmittance_top");
  sf_mlp_add_to_weights(doc, &t->net);
  return doc;
}

static int load_doc(const cJSON *doc, sf_mlp_sky *out, sf_error *err) {
  char *text = sf_weights_print(doc);
  sf_weights w;
  int status = sf_weights_load_string(text, "mapped.json", NULL, &w, err);
  free(text);
  if (status) return status;
  status = sf_mlp_sky_from_weights(&w, out, err);
  sf_weights_free(&w);
  return status;
}


static void emit_t(sf_code_writer *w, const void *model) { sf_emit_mlp_transmittance(w, model); }

/* Writes the emitted header and a driver, compiles and runs it on points
 * (h, mu, d) and compares with the model's float path. Returns the largest
 * difference, or -1 when cc is missing or the build fails. */
static double emitted_c_difference(const sf_mlp_sky *t, const float *pts, int n) {
  char dir[] = "/tmp/skyfit_mlp_map_XXXXXX";
  if (!mkdtemp(dir)) return -1.0;
  sf_codegen_part part;
  memset(&part, 0, sizeof part);
  snprintf(part.name, sizeof part.name, "mlp");
  snprintf(part.quantity, sizeof part.quantity, "transmittance");
  snprintf(part.summary, sizeof part.summary, "test network on x_r, x_mu");
  snprintf(part.atmosphere_name, sizeof part.atmosphere_name, "default");
  snprintf(part.atmosphere_hash, sizeof part.atmosphere_hash, "0000000000000000");
  snprintf(part.error, sizeof part.error, "none");
  part.emit = emit_t;
  part.model = t;
  sf_error err = {0};
  char path[512], cmd[1600];
  if (sf_codegen_write(&part, 1, 1, 0, dir, "mapped", NULL, &err)) {
    printf("codegen: %s\n", err.message);
    return -1.0;
  }
  snprintf(path, sizeof path, "%s/drive.c", dir);
  FILE *f = fopen(path, "w");
  if (!f) return -1.0;
  fprintf(f,
          "#include <stdio.h>\n#include \"mapped.h\"\n"
          "int main(void) {\n  float h, mu, d;\n"
          "  while (scanf(\"%%a %%a %%a\", &h, &mu, &d) == 3) {\n"
          "    skyfit_vec3 a = skyfit_mlp_transmittance(h, mu), b = skyfit_mlp_transmittance_segment(h, mu, d),\n"
          "                c = skyfit_mlp_transmittance_top(h, mu);\n"
          "    printf(\"%%a %%a %%a %%a %%a %%a %%a %%a %%a\\n\", a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z);\n"
          "  }\n  return 0;\n}\n");
  fclose(f);
  snprintf(path, sizeof path, "%s/points.txt", dir);
  f = fopen(path, "w");
  if (!f) return -1.0;
  for (int i = 0; i < n; ++i) fprintf(f, "%a %a %a\n", pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
  fclose(f);
  snprintf(cmd, sizeof cmd,
           "cc -std=c99 -O2 -ffp-contract=off -Wall -Wextra -Werror -pedantic -I%s -o %s/drive %s/drive.c -lm && "
           "%s/drive < %s/points.txt > %s/out.txt",
           dir, dir, dir, dir, dir, dir);
  double worst = -1.0;
  if (system(cmd) == 0) {
    snprintf(path, sizeof path, "%s/out.txt", dir);
    f = fopen(path, "r");
    worst = f ? 0.0 : -1.0;
    for (int i = 0; f && i < n; ++i) {
      float got[9], want[9];
      for (int k = 0; k < 9; ++k)
        if (fscanf(f, "%a", &got[k]) != 1) got[k] = NAN;
      sf_mlp_transmittance_f(t, pts[3 * i], pts[3 * i + 1], want);
      sf_mlp_transmittance_segment_f(t, pts[3 * i], pts[3 * i + 1], pts[3 * i + 2], want + 3);
      sf_mlp_transmittance_top_f(t, pts[3 * i], pts[3 * i + 1], want + 6);
      /* a viewer below float's resolution of R + h (5e-4 km) looking down
       * is on the ground for one geometry and just above it for the other
       * (both finite, checked); the mapping is what is compared here */
      int unresolved = pts[3 * i] < 1e-3f && pts[3 * i + 1] < 0.0f;
      for (int k = 0; k < 9; ++k) {
        if (!isfinite(got[k])) worst = INFINITY;
        else if (!unresolved) worst = worst_of(worst, fabsf(got[k] - want[k]));
      }
    }
    if (f) fclose(f);
  }
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) printf("could not remove %s\n", dir);
  return worst;
}

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  double R = atm.bottom_radius_km, Rt = atm.top_radius_km, top = Rt - R;
  sf_rng rng;
  sf_rng_seed(&rng, 17, 0x6d6170ull, 0);

  /* 1. coordinates */
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    double q = sqrt(top) * sf_rng_uniform(&rng), h = q * q;
    double mu_h = sf_horizon_mu(R + h, R);
    double mu = mu_h + (1.0 - mu_h) * sf_rng_uniform(&rng);
    double xr, xm, xr_ref, xm_ref;
    sf_mlp_bruneton_coords(R, Rt, h, mu, &xr, &xm);
    textbook_coords(R, Rt, h, mu, &xr_ref, &xm_ref);
    worst = worst_of(worst_of(worst, fabs(xr - xr_ref)), fabs(xm - xm_ref));
  }
  printf("x_r, x_mu against long-double textbook formulas, 20000 points: max |diff| %.3g\n", worst);
  double worst_inverse = 0.0;
  for (int i = 0; i < 20000; ++i) {
    double q = sqrt(top) * sf_rng_uniform(&rng), h = q * q;
    double mu_h = sf_horizon_mu(R + h, R);
    double mu = mu_h + (1.0 - mu_h) * sf_rng_uniform(&rng), h2, mu2, xr, xm;
    sf_mlp_bruneton_coords(R, Rt, h, mu, &xr, &xm);
    sf_mlp_bruneton_inverse(R, Rt, xr, xm, &h2, &mu2);
    worst_inverse = worst_of(worst_of(worst_inverse, fabs(h2 - h) / top), fabs(mu2 - mu));
  }
  printf("inverse (h, mu) of (x_r, x_mu), 20000 points: max |diff| %.3g (h / top, mu)\n", worst_inverse);
  CHECK(worst_inverse < 1e-8);
  CHECK(worst < 1e-10);
  double xr, xm;
  sf_mlp_bruneton_coords(R, Rt, 0.0, 1.0, &xr, &xm);
  CHECK_ABS(xr, 0.0, 1e-15);
  CHECK_ABS(xm, 0.0, 1e-15);
  sf_mlp_bruneton_coords(R, Rt, 0.0, 0.0, &xr, &xm);
  CHECK_ABS(xm, 1.0, 1e-12);
  sf_mlp_bruneton_coords(R, Rt, top, 1.0, &xr, &xm);
  CHECK_ABS(xr, 1.0, 1e-15);
  CHECK_ABS(xm, 0.0, 1e-15);
  sf_mlp_bruneton_coords(R, Rt, 37.0, sf_horizon_mu(R + 37.0, R), &xr, &xm);
  CHECK_ABS(xm, 1.0, 1e-9);

  /* 2. float32 against double */
  sf_mlp_sky t;
  if (make_model(&atm, SF_MLP_INPUTS_BRUNETON, &t)) return 1;
  double worst_top = 0.0, worst_full = 0.0, worst_seg = 0.0;
  int finite = 1;
  for (int i = 0; i < 20000; ++i) {
    double q = sqrt(top) * sf_rng_uniform(&rng), h = q * q;
    double mu = 2.0 * sf_rng_uniform(&rng) - 1.0, dist = 300.0 * sf_rng_uniform(&rng);
    double Td[3];
    float Tf[3];
    sf_mlp_transmittance_top(&t, h, fmax(mu, sf_horizon_mu(R + h, R)), Td);
    sf_mlp_transmittance_top_f(&t, (float)h, (float)fmax(mu, sf_horizon_mu(R + h, R)), Tf);
    for (int c = 0; c < 3; ++c) worst_top = worst_of(worst_top, fabs(Tf[c] - Td[c]));
    sf_mlp_transmittance(&t, h, mu, Td);
    sf_mlp_transmittance_f(&t, (float)h, (float)mu, Tf);
    for (int c = 0; c < 3; ++c) worst_full = worst_of(worst_full, fabs(Tf[c] - Td[c]));
    finite &= isfinite(Tf[0]) && isfinite(Tf[1]) && isfinite(Tf[2]);
    sf_mlp_transmittance_segment(&t, h, mu, dist, Td);
    sf_mlp_transmittance_segment_f(&t, (float)h, (float)mu, (float)dist, Tf);
    for (int c = 0; c < 3; ++c) worst_seg = worst_of(worst_seg, fabs(Tf[c] - Td[c]));
    finite &= isfinite(Tf[0]) && isfinite(Tf[1]) && isfinite(Tf[2]);
  }
  printf("float32 vs double, 20000 random points: T_top %.3g, full ray %.3g, segment %.3g\n", worst_top, worst_full,
         worst_seg);
  CHECK(finite);
  CHECK(worst_top < 2e-5);
  CHECK(worst_full < 2e-4);
  CHECK(worst_seg < 2e-3);
  /* SPEC §10 hard cases */
  static const double hs[] = {0.0, 1e-6, 0.5, 25.0, 99.999, 100.0, 100.001, 150.0, 5000.0};
  double worst_hard = 0.0;
  int hard_finite = 1, n_hard = 0;
  for (size_t i = 0; i < sizeof hs / sizeof hs[0]; ++i) {
    double h = hs[i], mh = sf_horizon_mu(R + fmin(h, top), R);
    double mus[] = {-1.0, 1.0, 0.0, mh, mh - 1e-6, mh + 1e-6, -1e-6, 1e-6, -0.3};
    for (size_t j = 0; j < sizeof mus / sizeof mus[0]; ++j) {
      double Td[3];
      float Tf[3];
      sf_mlp_transmittance(&t, h, mus[j], Td);
      sf_mlp_transmittance_f(&t, (float)h, (float)mus[j], Tf);
      hard_finite &= isfinite(Tf[0]) && isfinite(Tf[1]) && isfinite(Tf[2]);
      /* float's r = R + h resolves 5e-4 km: within 1e-3 of the horizon
       * cosine float and double may take different sides of eq. 43 */
      if (fabs(mus[j] - mh) > 1e-3)
        for (int c = 0; c < 3; ++c) worst_hard = worst_of(worst_hard, fabs(Tf[c] - Td[c]));
      sf_mlp_transmittance_top_f(&t, (float)h, (float)mus[j], Tf);
      hard_finite &= isfinite(Tf[0]) && isfinite(Tf[1]) && isfinite(Tf[2]);
      ++n_hard;
    }
  }
  printf("hard cases (%d): all finite %d, float32 vs double max %.3g (away from the horizon cosine)\n", n_hard, hard_finite, worst_hard);
  CHECK(hard_finite);
  CHECK(worst_hard < 1e-4);

  /* 3. weights file */
  sf_error err = {0};
  cJSON *doc = weights_doc(&atm, &t, "x_r", "x_mu");
  sf_mlp_sky back;
  CHECK(load_doc(doc, &back, &err) == SF_OK);
  cJSON_Delete(doc);
  CHECK(back.input_map == SF_MLP_INPUTS_BRUNETON);
  int same = 1;
  double worst_double = 0.0;
  for (int i = 0; i < 2000 && back.input_map == SF_MLP_INPUTS_BRUNETON; ++i) {
    double h = 120.0 * sf_rng_uniform(&rng), mu = 2.0 * sf_rng_uniform(&rng) - 1.0;
    double a[3], b[3];
    float af[3], bf[3];
    sf_mlp_transmittance(&t, h, mu, a);
    sf_mlp_transmittance(&back, h, mu, b);
    sf_mlp_transmittance_f(&t, (float)h, (float)mu, af);
    sf_mlp_transmittance_f(&back, (float)h, (float)mu, bf);
    /* float32 (what shaders do) bit for bit; double within rounding of the
     * printed parameters */
    same &= memcmp(af, bf, sizeof af) == 0;
    for (int c = 0; c < 3; ++c) worst_double = worst_of(worst_double, fabs(a[c] - b[c]));
  }
  printf("weights file round trip (x_r, x_mu): mapping %s, float32 bit-identical %d, double max diff %.3g\n",
         sf_mlp_input_map_name(back.input_map), same, worst_double);
  CHECK(same);
  CHECK(worst_double < 1e-13);
  sf_mlp_sky_free(&back);

  sf_mlp_sky old;
  if (make_model(&atm, SF_MLP_INPUTS_SQRT_H_MU, &old)) return 1;
  doc = weights_doc(&atm, &old, "sqrt_h_km", "mu");
  CHECK(load_doc(doc, &back, &err) == SF_OK);
  cJSON_Delete(doc);
  CHECK(back.input_map == SF_MLP_INPUTS_SQRT_H_MU);
  double a[3], b[3];
  sf_mlp_transmittance(&old, 3.0, 0.2, a);
  sf_mlp_transmittance(&back, 3.0, 0.2, b);
  CHECK_ABS(a[1], b[1], 1e-13);
  sf_mlp_sky_free(&back);

  doc = weights_doc(&atm, &t, "x_r", "mu");
  sf_error_clear(&err);
  CHECK(load_doc(doc, &back, &err) == SF_ERR_INPUT);
  cJSON_Delete(doc);
  printf("mixed input names: %s\n", err.message);
  CHECK(strstr(err.message, "mapped.json") && strstr(err.message, "inputs[1].name") && strstr(err.message, "x_mu"));

  /* 4. emitted C against the float path */
  enum { N_EMIT = 3000 };
  static float pts[3 * N_EMIT];
  int k = 0;
  for (size_t i = 0; i < sizeof hs / sizeof hs[0]; ++i) {
    double mh = sf_horizon_mu(R + fmin(hs[i], top), R);
    double mus[] = {-1.0, 1.0, 0.0, mh, mh - 1e-6, mh + 1e-6, -1e-6, 1e-6, -0.3};
    for (size_t j = 0; j < sizeof mus / sizeof mus[0]; ++j, ++k) {
      pts[3 * k] = (float)hs[i];
      pts[3 * k + 1] = (float)mus[j];
      pts[3 * k + 2] = (float)(50.0 * j);
    }
  }
  for (; k < N_EMIT; ++k) {
    double q = sqrt(1.3 * top) * sf_rng_uniform(&rng);
    pts[3 * k] = (float)(q * q);
    pts[3 * k + 1] = (float)(2.0 * sf_rng_uniform(&rng) - 1.0);
    pts[3 * k + 2] = (float)(400.0 * sf_rng_uniform(&rng));
  }
  double emitted = emitted_c_difference(&t, pts, N_EMIT);
  printf("emitted C header (x_r, x_mu) vs the model's float32 path, %d points x 9 values (all finite; viewers "
         "below 1 m looking down excluded): max |diff| %.3g\n", N_EMIT, emitted);
  CHECK(emitted >= 0.0 && emitted <= 5e-6);

  sf_mlp_sky_free(&t);
  sf_mlp_sky_free(&old);
  return check_summary();
}
