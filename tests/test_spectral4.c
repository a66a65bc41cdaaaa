/* The 4-wavelength spectral fit (SPEC §7.3) on a cheaper configuration than
 * the command's default (reference at 10 nm instead of 5, small tables,
 * 3 scattering orders, fewer samples), with the targets asserted:
 * mean ΔE2000 <= 0.5 and 99th percentile <= 1.5 against the full spectrum,
 * with and without aerosols; plain RGB must be clearly worse. Plus
 * independent checks: the closed-form loss against a direct sum over the
 * samples (eq. 5.13), the least-squares weights' optimality, the CIE
 * integration of a flat spectrum, and thread-count independence. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/spectral4_run.h"
#include "models/ciede2000.h"
#include "models/color_space.h"
#include "models/spectral_atmosphere.h"
#include "models/spectral_reference.h"
#include "tests/check.h"

static void cheap_options(sf_spectral4_run_options *o) {
  sf_spectral4_run_options_default(o);
  o->step_nm = 10.0;
  sf_table_resolution_parse("64x16,8x32x8x4", &o->res, NULL);
  o->orders = 3;
  o->train = (sf_spectral4_grid){10, 12, 6, 1};
  o->eval = (sf_spectral4_grid){24, 16, 8, 0};
  o->n_threads = 2;
}

/* eq. 5.13 summed directly over stored spectra. */
static double direct_loss(int n_ch, const double *nm, const sf_cmf *cmf, size_t n, const double *L, const double *y,
                          const sf_spectral4_params *p) {
  double sum = 0.0;
  for (size_t s = 0; s < n; ++s) {
    double xyz[3] = {0, 0, 0}, rgb[3];
    for (int i = 0; i < 4; ++i) {
      double bar[3], l = sf_spectrum_at(n_ch, nm, L + s * n_ch, p->lambda_nm[i]);
      sf_cmf_at(cmf, p->lambda_nm[i], bar);
      for (int c = 0; c < 3; ++c) xyz[c] += p->weight_nm[i] * bar[c] * l;
    }
    sf_xyz_to_linear_srgb(xyz, rgb);
    for (int c = 0; c < 3; ++c) sum += (rgb[c] - y[s * 3 + c]) * (rgb[c] - y[s * 3 + c]);
  }
  return sum / (3.0 * (double)n);
}

/* The loss at wavelengths l (nm), with its least-squares weights. */
static double lattice_loss(const sf_spectral4_kernel *k, const int l[4]) {
  sf_spectral4_params p = {{l[0], l[1], l[2], l[3]}, {0, 0, 0, 0}};
  return sf_spectral4_optimal_weights(k, &p);
}

/* The fit against a search of its own kind: every quadruple of a 5 nm
 * lattice over 380-780 nm, then from the best of them coordinate descent
 * on a 1 nm lattice (one wavelength moved by 1 nm while that lowers the
 * loss). Nelder-Mead from the best 10 nm quadruple alone had stopped at
 * twice such a search's loss on the example spectral4 scene. */
static void fit_vs_lattice_search(const sf_spectral4_kernel *k) {
  int best[4] = {0, 0, 0, 0};
  double best_loss = INFINITY;
  for (int a = 380; a <= 780; a += 5)
    for (int b = a + 5; b <= 780; b += 5)
      for (int c = b + 5; c <= 780; c += 5)
        for (int d = c + 5; d <= 780; d += 5) {
          int l[4] = {a, b, c, d};
          double f = lattice_loss(k, l);
          if (f < best_loss) {
            best_loss = f;
            memcpy(best, l, sizeof best);
          }
        }
  for (int moved = 1; moved;) {
    moved = 0;
    for (int i = 0; i < 4; ++i)
      for (int step = -1; step <= 1; step += 2) {
        int l[4];
        memcpy(l, best, sizeof l);
        l[i] += step;
        if (l[i] < 380 || l[i] > 780 || (i > 0 && l[i] <= l[i - 1]) || (i < 3 && l[i] >= l[i + 1])) continue;
        double f = lattice_loss(k, l);
        if (f < best_loss) {
          best_loss = f;
          memcpy(best, l, sizeof best);
          moved = 1;
        }
      }
  }
  sf_spectral4_fit_options o;
  sf_spectral4_fit_options_default(&o);
  sf_spectral4_fit_result r;
  sf_error err = {0};
  CHECK(sf_spectral4_fit(k, &o, &r, &err) == 0);
  printf("fit: loss %.6g (%d Nelder-Mead starts) vs lattice search %.6g at %d %d %d %d nm\n", r.loss, r.starts,
         best_loss, best[0], best[1], best[2], best[3]);
  CHECK(r.loss <= best_loss * 1.001);
}

static void kernel_checks(const sf_spectral4_run_options *o, const sf_cmf *cmf) {
  sf_scene *scene = malloc(sizeof *scene);
  sf_atmosphere *spec = malloc(sizeof *spec), *clean = malloc(sizeof *clean);
  sf_scene_default(scene);
  double nm[SF_MAX_CHANNELS];
  int n_ch = sf_spectral_grid(o->min_nm, o->max_nm, o->step_nm, nm);
  sf_error err = {0};
  CHECK(sf_spectral_atmosphere(&scene->atmosphere, n_ch, nm, spec, &err) == 0);
  CHECK(sf_atmosphere_without_aerosols(spec, clean) == 1);   /* the default's Mie */
  sf_table_set set;
  sf_table_set_options so;
  sf_table_set_options_default(&so);
  so.res = o->res;
  so.orders = 2;
  so.run.n_threads = 2;
  CHECK(sf_table_set_make(&set, clean, &so, &err) == 0);
  sf_sky_tables sky;
  sf_sky_tables_of_set(&sky, clean, &set);
  sf_view_sample *s = NULL;
  size_t n = 0;
  sf_spectral4_grid g = {5, 8, 4, 1};
  CHECK(sf_spectral4_make_samples(scene, &g, 6.0, &s, &n, &err) == 0);
  double *L1 = malloc(n * n_ch * sizeof *L1), *L2 = malloc(n * n_ch * sizeof *L2), *y = malloc(n * 3 * sizeof *y);
  unsigned char *in1 = malloc(n), *in2 = malloc(n);
  sf_spectral_radiance(&sky, n, s, 1, L1, in1);
  sf_spectral_radiance(&sky, n, s, 2, L2, in2);
  CHECK(memcmp(L1, L2, n * n_ch * sizeof *L1) == 0);   /* any thread count, same bits */
  sf_spectral4_kernel k;
  CHECK(sf_spectral4_kernel_init(&k, n_ch, nm, cmf, &err) == 0);
  for (size_t i = 0; i < n; ++i) {
    double xyz[3];
    sf_spectrum_to_xyz(cmf, n_ch, nm, L1 + i * n_ch, xyz);
    sf_xyz_to_linear_srgb(xyz, y + i * 3);
    sf_spectral4_kernel_add(&k, L1 + i * n_ch, y + i * 3, 1.0);
  }
  sf_spectral4_params p = {{452.5, 531.0, 587.3, 641.9}, {40.0, 55.0, 61.0, 70.0}};
  double direct = direct_loss(n_ch, nm, cmf, n, L1, y, &p);
  CHECK_REL(sf_spectral4_loss(&k, &p), direct, 1e-9);
  /* least-squares weights: no nearby weights do better, and the loss is
   * the direct sum's */
  double best = sf_spectral4_optimal_weights(&k, &p);
  CHECK_REL(best, direct_loss(n_ch, nm, cmf, n, L1, y, &p), 1e-8);
  int optimal = 1;
  for (int i = 0; i < 4; ++i)
    for (int sign = -1; sign <= 1; sign += 2) {
      sf_spectral4_params q = p;
      q.weight_nm[i] += sign * 0.01 * q.weight_nm[i];
      optimal &= sf_spectral4_loss(&k, &q) > best;
    }
  CHECK(optimal);
  fit_vs_lattice_search(&k);
  sf_spectral4_kernel_free(&k);
  free(L1);
  free(L2);
  free(y);
  free(in1);
  free(in2);
  free(s);
  sf_table_set_free(&set);
  free(scene);
  free(spec);
  free(clean);
}

/* The fit reads L at its wavelengths by interpolating the reference in
 * wavelength. A renderer computes L at those wavelengths directly: tables of
 * the 4-wavelength atmosphere (coefficients interpolated like the weights
 * file's). Both colours through to_linear_srgb must agree. */
static void direct_wavelength_check(const sf_spectral4_run_options *o, const sf_cmf *cmf,
                                    const sf_spectral4_params *p) {
  sf_scene *scene = malloc(sizeof *scene);
  sf_atmosphere *spec = malloc(sizeof *spec), *clean = malloc(sizeof *clean), *four = malloc(sizeof *four);
  sf_scene_default(scene);
  double nm[SF_MAX_CHANNELS];
  int n_ch = sf_spectral_grid(o->min_nm, o->max_nm, o->step_nm, nm);
  sf_error err = {0};
  CHECK(sf_spectral_atmosphere(&scene->atmosphere, n_ch, nm, spec, &err) == 0);
  sf_atmosphere_without_aerosols(spec, clean);
  CHECK(sf_spectral_atmosphere(clean, 4, p->lambda_nm, four, &err) == 0);
  sf_table_set set_full, set_four;
  sf_table_set_options so;
  sf_table_set_options_default(&so);
  so.res = o->res;
  so.orders = o->orders;
  so.run.n_threads = 2;
  CHECK(sf_table_set_make(&set_full, clean, &so, &err) == 0);
  CHECK(sf_table_set_make(&set_four, four, &so, &err) == 0);
  sf_sky_tables sky_full, sky_four;
  sf_sky_tables_of_set(&sky_full, clean, &set_full);
  sf_sky_tables_of_set(&sky_four, four, &set_four);
  sf_view_sample *s = NULL;
  size_t n = 0;
  sf_spectral4_grid g = {12, 12, 6, 0};
  double display = SF_SPECTRAL4_SUN_LUMINANCE / sf_spectral_sun_luminance(spec, cmf);
  CHECK(sf_spectral4_make_samples(scene, &g, display, &s, &n, &err) == 0);
  double *Lf = malloc(n * n_ch * sizeof *Lf), *L4 = malloc(n * 4 * sizeof *L4);
  unsigned char *in_f = malloc(n), *in_4 = malloc(n);
  sf_spectral_radiance(&sky_full, n, s, 2, Lf, in_f);
  sf_spectral_radiance(&sky_four, n, s, 2, L4, in_4);
  sf_color_method m = {"spectral4", SF_COLOR_FOUR_WAVELENGTHS, *p, {0, 0, 0}, 0.0};
  double sum = 0.0, worst = 0.0;
  size_t used = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!in_f[i] || Lf[i * n_ch + n_ch / 2] == 0.0) continue;
    double rgb_interp[3], xyz[3] = {0, 0, 0}, rgb_direct[3], lab1[3], lab2[3];
    sf_color_method_apply(&m, cmf, n_ch, nm, Lf + i * n_ch, rgb_interp);
    for (int k = 0; k < 4; ++k) {
      double bar[3];
      sf_cmf_at(cmf, p->lambda_nm[k], bar);
      for (int c = 0; c < 3; ++c) xyz[c] += p->weight_nm[k] * bar[c] * L4[i * 4 + k];
    }
    sf_xyz_to_linear_srgb(xyz, rgb_direct);
    sf_display_lab(rgb_interp, 1.0, lab1);
    sf_display_lab(rgb_direct, 1.0, lab2);
    double de = sf_ciede2000(lab1, lab2);
    sum += de;
    worst = de > worst ? de : worst;
    ++used;
  }
  printf("4 wavelengths computed directly vs read from the interpolated reference: mean ΔE00 %.4f, max %.4f over "
         "%zu samples\n", sum / used, worst, used);
  CHECK_ABS(sum / used, 0.0, 0.1);
  CHECK_ABS(worst, 0.0, 1.0);
  free(Lf);
  free(L4);
  free(in_f);
  free(in_4);
  free(s);
  sf_table_set_free(&set_full);
  sf_table_set_free(&set_four);
  free(scene);
  free(spec);
  free(clean);
  free(four);
}

int main(void) {
  sf_error err = {0};
  sf_cmf *cmf = malloc(sizeof *cmf);
  CHECK(sf_cmf_load(cmf, &err) == 0);
  /* a flat unit spectrum on the 5 nm grid integrates to 5 x sum of the
   * CMFs: (106.866, 106.857, 106.893) (data README) */
  double nm5[SF_MAX_CHANNELS], ones[SF_MAX_CHANNELS], xyz[3];
  int n5 = sf_spectral_grid(360.0, 830.0, 5.0, nm5);
  CHECK(n5 == 95);
  for (int i = 0; i < n5; ++i) ones[i] = 1.0;
  sf_spectrum_to_xyz(cmf, n5, nm5, ones, xyz);
  CHECK_REL(xyz[0], 106.866, 1e-5);
  CHECK_REL(xyz[1], 106.857, 1e-5);
  CHECK_REL(xyz[2], 106.893, 1e-5);

  sf_spectral4_run_options o;
  cheap_options(&o);
  kernel_checks(&o, cmf);

  sf_scene *scene = malloc(sizeof *scene);
  sf_spectral4_report *rep = malloc(sizeof *rep);
  sf_scene_default(scene);
  cJSON *doc = NULL;
  CHECK(sf_spectral4_run(scene, &o, rep, &doc, &err) == 0);
  printf("%s\n", err.message);
  const sf_spectral4_params *p = &rep->fit.best;
  printf("fit: %.2f %.2f %.2f %.2f nm, weights %.3f %.3f %.3f %.3f; loss grid %.4g -> %.4g (%d evaluations), "
         "rgb %.4g, uniform4 %.4g; fit %.2f s, reference %.2f s\n",
         p->lambda_nm[0], p->lambda_nm[1], p->lambda_nm[2], p->lambda_nm[3], p->weight_nm[0], p->weight_nm[1],
         p->weight_nm[2], p->weight_nm[3], rep->fit.grid_loss, rep->fit.loss, rep->fit.evaluations, rep->rgb_loss,
         rep->uniform_loss, rep->fit_seconds, rep->reference_seconds);
  CHECK(rep->has_aerosols);
  CHECK(rep->fit.loss <= rep->fit.grid_loss);
  direct_wavelength_check(&o, cmf, p);
  for (int a = 0; a < 2; ++a) {
    printf("%s aerosols:\n", a ? "with" : "without");
    for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m)
      printf("  %-16s mean %.4f p99 %.4f max %.4f (%zu samples)\n", rep->methods[m].name, rep->stats[a][m].mean,
             rep->stats[a][m].p99, rep->stats[a][m].max, rep->stats[a][m].n);
    CHECK(rep->stats[a][0].n > 5000);
    CHECK_ABS(rep->stats[a][0].mean, 0.0, 0.5);   /* issue 5 targets */
    CHECK_ABS(rep->stats[a][0].p99, 0.0, 1.5);
    CHECK(rep->stats[a][1].mean > 4.0 * rep->stats[a][0].mean);   /* plain RGB is far worse */
  }
  /* the weights document: to_linear_srgb = xyz_to_srgb . to_xyz */
  const cJSON *params = cJSON_GetObjectItemCaseSensitive(doc, "params");
  const cJSON *to_xyz = cJSON_GetObjectItemCaseSensitive(params, "to_xyz");
  const cJSON *to_rgb = cJSON_GetObjectItemCaseSensitive(params, "to_linear_srgb");
  CHECK(cJSON_GetArraySize(to_xyz) == 3 && cJSON_GetArraySize(to_rgb) == 3);
  double bar[3];
  sf_cmf_at(cmf, p->lambda_nm[2], bar);
  CHECK_REL(cJSON_GetArrayItem(cJSON_GetArrayItem(to_xyz, 1), 2)->valuedouble, bar[1] * p->weight_nm[2], 1e-12);
  double r0 = 0.0;
  for (int c = 0; c < 3; ++c)
    r0 += sf_xyz_to_linear_srgb_matrix[0][c] * cJSON_GetArrayItem(cJSON_GetArrayItem(to_xyz, c), 0)->valuedouble;
  CHECK_REL(cJSON_GetArrayItem(cJSON_GetArrayItem(to_rgb, 0), 0)->valuedouble, r0, 1e-12);
  cJSON_Delete(doc);
  free(scene);
  free(rep);
  free(cmf);
  return check_summary();
}
