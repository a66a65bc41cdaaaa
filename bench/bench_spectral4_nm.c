/* Benchmark (issue 5): NLopt's Nelder-Mead on the 4-wavelength objective
 * (seed 003 eq. 5.13, fit/spectral4_fit.h) from the grid search's best
 * point, timed; the same objective's data and start are written for
 * bench/spectral4_nm.py, which runs SciPy's Nelder-Mead from the same start.
 *
 *   bench_spectral4_nm --out DIR [--cache DIR] [--quick] [--repeat N]
 *
 * Writes DIR/objective.json: the reference grid, K (n x n), P (n x 3), yy,
 * weight sum, the start point, NLopt's initial steps and tolerances, and
 * NLopt's result (evaluations, loss, seconds). --quick uses the test's cheap
 * reference (10 nm, small tables); the default is the command's reference
 * (5 nm), computed once and cached in --cache. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/spectral4_fit.h"
#include "fit/spectral4_run.h"
#include "fit/spectral4_samples.h"
#include "models/color_space.h"
#include "models/spectral_atmosphere.h"
#include "models/spectral_reference.h"
#include "util/atomic_file.h"
#include "util/make_folders.h"
#include "util/clock.h"

int main(int argc, char **argv) {
  const char *out = NULL, *cache = NULL;
  int quick = 0, repeat = 20;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out = argv[++i];
    else if (strcmp(argv[i], "--cache") == 0 && i + 1 < argc) cache = argv[++i];
    else if (strcmp(argv[i], "--quick") == 0) quick = 1;
    else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = atoi(argv[++i]);
    else {
      fprintf(stderr, "usage: bench_spectral4_nm --out DIR [--cache DIR] [--quick] [--repeat N]\n");
      return 2;
    }
  }
  if (!out || repeat < 1) {
    fprintf(stderr, "bench_spectral4_nm: --out DIR is required\n");
    return 2;
  }
  sf_error err = {0};
  if (sf_make_folders(out, "--out", &err) || (cache && sf_make_folders(cache, "--cache", &err))) {
    fprintf(stderr, "bench_spectral4_nm: %s\n", err.message);
    return 2;
  }
  sf_spectral4_run_options o;
  sf_spectral4_run_options_default(&o);
  if (quick) {
    o.step_nm = 10.0;
    sf_table_resolution_parse("64x16,8x32x8x4", &o.res, NULL);
    o.orders = 3;
    o.train = (sf_spectral4_grid){10, 12, 6, 1};
  }
  sf_scene *scene = malloc(sizeof *scene);
  sf_atmosphere *full = malloc(sizeof *full), *clean = malloc(sizeof *clean);
  sf_cmf *cmf = malloc(sizeof *cmf);
  sf_scene_default(scene);
  double nm[SF_MAX_CHANNELS];
  int n = sf_spectral_grid(o.min_nm, o.max_nm, o.step_nm, nm);
  sf_table_set set;
  sf_table_set_options so;
  sf_table_set_options_default(&so);
  so.res = o.res;
  so.orders = o.orders;
  so.stop_fraction = o.stop_fraction;
  so.cache_dir = cache;
  if (sf_cmf_load(cmf, &err) || sf_spectral_atmosphere(&scene->atmosphere, n, nm, full, &err)) {
    fprintf(stderr, "bench_spectral4_nm: %s\n", err.message);
    return 1;
  }
  sf_atmosphere_without_aerosols(full, clean);
  double t0 = sf_wall_seconds();
  if (sf_table_set_make(&set, clean, &so, &err)) {
    fprintf(stderr, "bench_spectral4_nm: %s\n", err.message);
    return 1;
  }
  double t_ref = sf_wall_seconds() - t0;
  sf_sky_tables sky;
  sf_sky_tables_of_set(&sky, clean, &set);
  sf_view_sample *s = NULL;
  size_t ns = 0;
  double display = SF_SPECTRAL4_SUN_LUMINANCE / sf_spectral_sun_luminance(full, cmf);
  sf_spectral4_make_samples(scene, &o.train, display, &s, &ns, &err);
  double *L = malloc(ns * n * sizeof *L);
  unsigned char *in = malloc(ns);
  sf_spectral_radiance(&sky, ns, s, 0, L, in);
  sf_spectral4_kernel k;
  sf_spectral4_kernel_init(&k, n, nm, cmf, &err);
  for (size_t i = 0; i < ns; ++i) {
    int seen = 0;
    for (int ch = 0; ch < n; ++ch) seen |= L[i * n + ch] != 0.0;
    if (!in[i] || !seen) continue;
    double xyz[3], y[3];
    sf_spectrum_to_xyz(cmf, n, nm, L + i * n, xyz);
    sf_xyz_to_linear_srgb(xyz, y);
    sf_spectral4_kernel_add(&k, L + i * n, y, 1.0);
  }
  /* the start: the grid search's best quadruple with its least-squares weights */
  sf_spectral4_fit_result grid;
  sf_spectral4_fit_options fo = o.fit;
  fo.max_evaluations = 1;   /* grid only; Nelder-Mead timed below */
  sf_spectral4_fit(&k, &fo, &grid, &err);
  sf_spectral4_params start = grid.grid_best, best;
  double loss = 0.0, t_nm = 0.0;
  int evals = 0, status = 0;
  /* one run (no restart), as SciPy's; then as the fit runs it (restarts) */
  sf_spectral4_fit_options single = o.fit;
  single.restarts = 0;
  for (int r = 0; r < repeat; ++r) {
    double t = sf_wall_seconds();
    sf_spectral4_nelder_mead(&k, &start, &single, &best, &loss, &evals, &status, &err);
    t_nm += sf_wall_seconds() - t;
  }
  t_nm /= repeat;
  sf_spectral4_params best_r;
  double loss_r = 0.0, t_r = sf_wall_seconds();
  int evals_r = 0, status_r = 0;
  for (int r = 0; r < repeat; ++r) sf_spectral4_nelder_mead(&k, &start, &o.fit, &best_r, &loss_r, &evals_r, &status_r, &err);
  t_r = (sf_wall_seconds() - t_r) / repeat;
  printf("reference tables: %.2f s (%s), %d channels, %zu training samples\n", t_ref,
         set.from_cache[0] ? "cached" : "computed", n, k.n_samples);
  printf("start (grid search, %ld quadruples): loss %.10g\n", grid.grid_candidates, grid.grid_loss);
  printf("NLopt Nelder-Mead, one run: %d evaluations, loss %.10g, %.6f s (mean of %d), status %d\n", evals, loss,
         t_nm, repeat, status);
  printf("NLopt Nelder-Mead with the fit's %d restarts: %d evaluations, loss %.10g, %.6f s\n", o.fit.restarts, evals_r,
         loss_r, t_r);
  cJSON *doc = cJSON_CreateObject();
  cJSON_AddItemToObject(doc, "lambda_nm", cJSON_CreateDoubleArray(nm, n));
  cJSON *K = cJSON_AddArrayToObject(doc, "K");
  for (int a = 0; a < n; ++a) cJSON_AddItemToArray(K, cJSON_CreateDoubleArray(k.K + (size_t)a * n, n));
  cJSON *P = cJSON_AddArrayToObject(doc, "P");
  for (int a = 0; a < n; ++a) cJSON_AddItemToArray(P, cJSON_CreateDoubleArray(k.P[a], 3));
  cJSON_AddNumberToObject(doc, "yy", k.yy);
  cJSON_AddNumberToObject(doc, "weight_sum", k.weight_sum);
  double x0[8], step[8];
  for (int i = 0; i < 4; ++i) {
    x0[i] = start.lambda_nm[i];
    x0[4 + i] = start.weight_nm[i];
    step[i] = o.fit.initial_step_nm;
    step[4 + i] = o.fit.initial_step_fraction * fabs(start.weight_nm[i]) + 1e-3;
  }
  cJSON_AddItemToObject(doc, "start", cJSON_CreateDoubleArray(x0, 8));
  cJSON_AddItemToObject(doc, "initial_step", cJSON_CreateDoubleArray(step, 8));
  cJSON_AddNumberToObject(doc, "start_loss", grid.grid_loss);
  cJSON_AddNumberToObject(doc, "ftol_rel", o.fit.ftol_rel);
  cJSON_AddNumberToObject(doc, "xtol_rel", o.fit.xtol_rel);
  cJSON_AddNumberToObject(doc, "max_evaluations", o.fit.max_evaluations);
  cJSON *res = cJSON_AddObjectToObject(doc, "nlopt");
  cJSON_AddNumberToObject(res, "evaluations", evals);
  cJSON_AddNumberToObject(res, "loss", loss);
  cJSON_AddNumberToObject(res, "seconds", t_nm);
  double xb[8];
  for (int i = 0; i < 4; ++i) xb[i] = best.lambda_nm[i], xb[4 + i] = best.weight_nm[i];
  cJSON_AddItemToObject(res, "x", cJSON_CreateDoubleArray(xb, 8));
  cJSON *rr = cJSON_AddObjectToObject(doc, "nlopt_restarts");
  cJSON_AddNumberToObject(rr, "evaluations", evals_r);
  cJSON_AddNumberToObject(rr, "loss", loss_r);
  cJSON_AddNumberToObject(rr, "seconds", t_r);
  char *text = cJSON_Print(doc);
  char path[4096];
  snprintf(path, sizeof path, "%s/objective.json", out);
  sf_atomic_file f;
  int rc = sf_atomic_open(&f, path, &err);
  if (!rc) {
    fputs(text, f.stream);
    rc = sf_atomic_commit(&f, &err);
  }
  if (rc) fprintf(stderr, "bench_spectral4_nm: %s\n", err.message);
  free(text);
  cJSON_Delete(doc);
  sf_spectral4_kernel_free(&k);
  sf_table_set_free(&set);
  free(L);
  free(in);
  free(s);
  free(scene);
  free(full);
  free(clean);
  free(cmf);
  return rc ? 1 : 0;
}
