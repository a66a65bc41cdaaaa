/* Ceres side of bench/ceres_vs_scipy.sh: the sky fits of SPEC §7.2 on
 * fixed samples from a fixed start, timed (median of repeats), and the
 * same problems written to DIR for SciPy's least_squares
 * (bench/ceres_vs_scipy.py): DIR/<name>.csv holds cos_theta, gamma,
 * cos_gamma, radiance per sample; DIR/<name>.json the form, start, weight,
 * whether the scale is fixed, and Ceres' time and costs.
 *   bench_ceres_fit DIR [repeats] [tolerance, default 1e-14] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/fit_sky_config.h"
#include "models/hosek.h"
#include "fit/sky_radiance_samples.h"
#include "models/atmosphere_file.h"
#include "models/hosek_dataset.h"
#include "models/preetham.h"
#include "util/constants.h"
#include "util/clock.h"

/* The product's sky-fit settings (fit/fit_sky_config.h) with the
 * benchmark's tolerance (the same for SciPy's ftol, xtol, gtol);
 * BENCH_QR, BENCH_RADIUS, BENCH_DOGLEG, BENCH_NONMONOTONIC, BENCH_JACOBI
 * override them to compare Ceres' options. */
static double bench_tolerance = 1e-14;
static void bench_options(sf_lsq_options *o) {
  sf_sky_fit_options_default(o);
  o->max_iterations = 1000;
  o->function_tolerance = o->parameter_tolerance = o->gradient_tolerance = bench_tolerance;
  if (getenv("BENCH_QR")) o->normal_equations = 0;
  if (getenv("BENCH_RADIUS")) o->initial_trust_region_radius = atof(getenv("BENCH_RADIUS"));
  if (getenv("BENCH_DOGLEG")) o->dogleg = 1;
  if (getenv("BENCH_NONMONOTONIC")) o->nonmonotonic_steps = 1;
  if (getenv("BENCH_JACOBI")) o->jacobi_scaling = 1;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* truth (may be NULL): the coefficients and scale that generated the
 * samples; the cost there through the fit's own evaluator is the rounding
 * floor a recovery can reach. */
static void run(const char *dir, const char *name, sf_sky_form form, const sf_sky_samples *s, int ch,
                const double *start, const double *truth, int fix_scale, int repeats) {
  int nc = sf_sky_form_n_coeffs(form);
  double ss = 0;
  for (int i = 0; i < s->n; ++i) ss += pow(s->radiance[(size_t)i * s->n_channels + ch], 2);
  sf_sky_fit_data d = {form, s->n, s->cos_theta, s->gamma, s->cos_gamma, s->radiance + ch,
                       s->n_channels, 1 / sqrt(ss / s->n)};
  sf_lsq_options o;
  bench_options(&o);
  double times[256], cpu[256], c[SF_HOSEK_N_COEFFS + 1];
  sf_lsq_summary sum;
  for (int r = 0; r < repeats; ++r) {
    memcpy(c, start, sizeof(double) * (size_t)(nc + 1));
    sf_error err = {0};
    double t0 = sf_wall_seconds(), c0 = sf_cpu_seconds();
    if (sf_fit_sky_config(&d, SF_SKY_BOUNDS_SCALE_ONLY, fix_scale, &o, c, &c[nc], &sum, &err))
      fprintf(stderr, "%s: %s\n", name, err.message);
    times[r] = sf_wall_seconds() - t0;
    cpu[r] = sf_cpu_seconds() - c0;
  }
  qsort(times, (size_t)repeats, sizeof(double), cmp);
  qsort(cpu, (size_t)repeats, sizeof(double), cmp);
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.csv", dir, name);
  FILE *f = fopen(path, "w");
  for (int i = 0; i < s->n; ++i)
    fprintf(f, "%.17g,%.17g,%.17g,%.17g\n", s->cos_theta[i], s->gamma[i], s->cos_gamma[i],
            s->radiance[(size_t)i * s->n_channels + ch]);
  fclose(f);
  snprintf(path, sizeof path, "%s/%s.json", dir, name);
  f = fopen(path, "w");
  fprintf(f, "{\"name\": \"%s\", \"form\": \"%s\", \"fix_scale\": %d, \"weight\": %.17g, \"samples\": %d, \"tolerance\": %.17g, \"start\": [",
          name, sf_sky_form_model_name(form), fix_scale, d.weight, s->n, bench_tolerance);
  for (int i = 0; i <= nc; ++i) fprintf(f, "%s%.17g", i ? ", " : "", start[i]);
  fprintf(f, "]");
  if (truth) {
    double floor_ss = 0;
    sf_sky_fit_gram(&d, truth, truth[nc], &floor_ss, NULL);
    fprintf(f, ", \"truth\": [");
    for (int i = 0; i <= nc; ++i) fprintf(f, "%s%.17g", i ? ", " : "", truth[i]);
    fprintf(f, "], \"ceres_truth_cost\": %.17g", 0.5 * floor_ss);
  }
  fprintf(f, ", \"ceres_seconds\": %.6g, \"ceres_cpu_seconds\": %.6g, \"ceres_initial_cost\": %.17g, \"ceres_final_cost\": %.17g, "
             "\"ceres_iterations\": %d, \"ceres_result\": [",
          times[repeats / 2], cpu[repeats / 2], sum.initial_cost, sum.final_cost, sum.iterations);
  for (int i = 0; i <= nc; ++i) fprintf(f, "%s%.17g", i ? ", " : "", c[i]);
  fprintf(f, "]}\n");
  fclose(f);
  printf("%-28s ceres %9.3f ms (cpu %.3f ms)  cost %.6g -> %.6g  (%d iterations, %s)\n", name,
         1e3 * times[repeats / 2], 1e3 * cpu[repeats / 2], sum.initial_cost, sum.final_cost, sum.iterations,
         sf_lsq_termination_name(sum.termination));
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: bench_ceres_fit DIR [repeats] [tolerance]\n");
    return 2;
  }
  int repeats = argc > 2 ? atoi(argv[2]) : 7;
  if (repeats < 1 || repeats > 256) repeats = 7;
  if (argc > 3) bench_tolerance = atof(argv[3]);
  if (!(bench_tolerance > 0 && bench_tolerance < 1)) {
    fprintf(stderr, "bench_ceres_fit: tolerance must lie in (0, 1), got %s\n", argv[3]);
    return 2;
  }
  sf_error err = {0};
  sf_hosek_dataset *ds = malloc(sizeof *ds);
  if (sf_hosek_dataset_load_default(ds, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  /* 1-2: published skies on a 40 x 60 view grid, perturbed starts */
  double elev = 0.5, c[SF_HOSEK_N_COEFFS + 1], R;
  sf_hosek_dataset_state(ds, 1, 4.0, 0.3, elev, c, &R, &err);
  sf_sky_samples s;
  sf_sky_samples_alloc(&s, 40 * 60, 1, &err);
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 60; ++j) {
      double th = (i + 0.5) / 40 * 0.5 * SF_PI, ph = (double)j / 59 * SF_PI;
      sf_sky_sample_set_angles(&s, i * 60 + j, th, cos(th) * sin(elev) + sin(th) * cos(elev) * cos(ph));
      s.radiance[i * 60 + j] = R * sf_hosek_f(c, s.cos_theta[i * 60 + j], s.gamma[i * 60 + j]);
    }
  double start[SF_HOSEK_N_COEFFS + 1];
  for (int i = 0; i < 9; ++i) start[i] = c[i] * (1.0 + 0.04 * ((i % 3) - 1) + 0.02);
  start[9] = R;
  double truth[SF_HOSEK_N_COEFFS + 1];
  memcpy(truth, c, sizeof(double) * 9);
  truth[9] = R;
  run(argv[1], "hosek_published_recovery", SF_SKY_FORM_HOSEK, &s, 0, start, truth, 1, repeats);
  sf_preetham_sky sky;
  sf_preetham_sky_init(&sky, 3.0, 0.5 * SF_PI - elev);
  for (int i = 0; i < s.n; ++i) s.radiance[i] = sf_perez_f(sky.coeffs[0], s.cos_theta[i], s.gamma[i]) * 2.5;
  for (int i = 0; i < 5; ++i) start[i] = sky.coeffs[0][i] * (1.0 + 0.04 * ((i % 3) - 1) + 0.02);
  start[5] = 2.0;
  memcpy(truth, sky.coeffs[0], sizeof(double) * 5);
  truth[5] = 2.5;
  run(argv[1], "perez_preetham_recovery", SF_SKY_FORM_PEREZ, &s, 0, start, truth, 0, repeats);
  sf_sky_samples_free(&s);

  /* 3-4: the reference sky of the built-in atmosphere (small tables, 30 deg
   * sun, green), from the published sets' starts */
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_atmosphere_default(atm);
  sf_table_set_options to;
  sf_table_set_options_default(&to);
  to.orders = 2;
  to.res = (sf_table_resolution){64, 16, 12, 48, 16, 8, 16, 4};
  sf_table_set set;
  if (sf_table_set_make(&set, atm, &to, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  sf_sky_tables tables;
  sf_sky_tables_of_set(&tables, atm, &set);
  double e30 = 30 * SF_PI / 180;
  sf_sky_samples_from_tables(&tables, e30, 40, 60, &s, &err);
  sf_hosek_dataset_state(ds, 1, 3.0, 0.0, e30, start, &R, &err);
  start[9] = s.zenith_radiance[1];
  double md = 0, mm = 0;
  for (int i = 0; i < s.n; ++i) {
    double f = start[9] * sf_hosek_f(start, s.cos_theta[i], s.gamma[i]);
    md += f * s.radiance[i * 3 + 1];
    mm += f * f;
  }
  const int lin[5] = {2, 3, 5, 6, 8};
  for (int q = 0; q < 5; ++q) start[lin[q]] *= md / mm;
  run(argv[1], "hosek_reference_sky", SF_SKY_FORM_HOSEK, &s, 1, start, NULL, 1, repeats);
  {
    /* the product's multi-start (fit/fit_sky_elevation.c): the published
     * set at T = 2, 4, 7 (albedo 0), linear part rescaled; written for
     * SciPy as DIR/multistart.txt (one start per line) */
    const double turb[3] = {2.0, 4.0, 7.0};
    double starts[3][SF_HOSEK_N_COEFFS + 1], sol[SF_HOSEK_N_COEFFS + 1], costs[3], times[256],
        cpu[256];
    for (int t = 0; t < 3; ++t) {
      sf_hosek_dataset_state(ds, 1, turb[t], 0.0, e30, starts[t], &R, &err);
      starts[t][9] = s.zenith_radiance[1];
      double a = 0, b = 0;
      for (int i = 0; i < s.n; ++i) {
        double f = starts[t][9] * sf_hosek_f(starts[t], s.cos_theta[i], s.gamma[i]);
        a += f * s.radiance[i * 3 + 1];
        b += f * f;
      }
      for (int q = 0; q < 5; ++q) starts[t][lin[q]] *= a / b;
    }
    double ss = 0;
    for (int i = 0; i < s.n; ++i) ss += pow(s.radiance[(size_t)i * 3 + 1], 2);
    sf_sky_fit_data d = {SF_SKY_FORM_HOSEK, s.n, s.cos_theta, s.gamma, s.cos_gamma, s.radiance + 1, 3,
                         1 / sqrt(ss / s.n)};
    sf_lsq_options o;
    bench_options(&o);
    int winner = -1;
    sf_lsq_summary sum;
    for (int r = 0; r < repeats; ++r) {
      double t0 = sf_wall_seconds(), c0 = sf_cpu_seconds();
      sf_fit_sky_multistart(&d, SF_SKY_BOUNDS_SCALE_ONLY, 1, &o, 3, (const double(*)[SF_HOSEK_N_COEFFS + 1])starts, sol, &sol[9], &winner,
                            &sum, costs, &err);
      times[r] = sf_wall_seconds() - t0;
      cpu[r] = sf_cpu_seconds() - c0;
    }
    qsort(times, (size_t)repeats, sizeof(double), cmp);
    qsort(cpu, (size_t)repeats, sizeof(double), cmp);
    char path[4096];
    snprintf(path, sizeof path, "%s/multistart.txt", argv[1]);
    FILE *f = fopen(path, "w");
    fprintf(f, "%.6g %.17g %d %.6g\n", times[repeats / 2], costs[winner], winner, cpu[repeats / 2]);
    for (int t = 0; t < 3; ++t)
      for (int i = 0; i <= 9; ++i) fprintf(f, "%.17g%s", starts[t][i], i == 9 ? "\n" : " ");
    fclose(f);
    printf("%-28s ceres %9.3f ms (cpu %.3f ms)  final costs T=2 %.6g, T=4 %.6g, T=7 %.6g; winner T=%g\n",
           "hosek_reference_multistart", 1e3 * times[repeats / 2], 1e3 * cpu[repeats / 2], costs[0], costs[1], costs[2], turb[winner]);
  }
  sf_preetham_coefficients(SF_PREETHAM_Y, 3.0, start);
  md = mm = 0;
  for (int i = 0; i < s.n; ++i) {
    double f = sf_perez_f(start, s.cos_theta[i], s.gamma[i]);
    md += f * s.radiance[i * 3 + 1];
    mm += f * f;
  }
  start[5] = md / mm;
  run(argv[1], "perez_reference_sky", SF_SKY_FORM_PEREZ, &s, 1, start, NULL, 0, repeats);
  sf_sky_samples_free(&s);
  sf_table_set_free(&set);
  free(atm);
  free(ds);
  return 0;
}
