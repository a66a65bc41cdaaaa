#include "fit/spectral4_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/ciede2000.h"
#include "models/color_space.h"
#include "models/spectral_atmosphere.h"
#include "models/spectral_reference.h"
#include "models/weights_file.h"
#include "util/clock.h"
#include "util/constants.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#define BLOCK 4096

void sf_spectral4_run_options_default(sf_spectral4_run_options *o) {
  memset(o, 0, sizeof *o);
  o->min_nm = SF_SPECTRAL_MIN_NM;
  o->max_nm = SF_SPECTRAL_MAX_NM;
  o->step_nm = SF_SPECTRAL_STEP_NM;
  sf_table_resolution_default(&o->res);
  o->res.transmittance_mu = 128;
  o->res.transmittance_h = 32;
  o->res.scattering_h = 16;
  o->res.scattering_mu = 64;
  o->res.scattering_mu_s = 16;
  o->res.scattering_nu = 8;
  o->orders = SF_TABLE_SET_DEFAULT_ORDERS;
  o->stop_fraction = SF_TABLE_SET_DEFAULT_STOP_FRACTION;
  o->train = (sf_spectral4_grid){16, 24, 12, 1};
  o->eval = (sf_spectral4_grid){47, 32, 16, 0};
  sf_spectral4_fit_options_default(&o->fit);
}

static int make_tables(const sf_atmosphere *atm, const sf_spectral4_run_options *o, sf_table_set *set,
                       int *all_cached, int *highest_order, sf_error *err) {
  sf_table_set_options so;
  sf_table_set_options_default(&so);
  so.kind = SF_PARAM_BRUNETON;
  so.res = o->res;
  so.orders = o->orders;
  so.stop_fraction = o->stop_fraction;
  so.cache_dir = o->cache_dir;
  so.run.n_threads = o->n_threads;
  so.run.progress = o->progress;
  so.run.progress_ctx = o->progress_ctx;
  so.note = o->note;
  so.note_ctx = o->note_ctx;
  int rc = sf_table_set_make(set, atm, &so, err);
  if (rc) return rc;
  *all_cached = 1;
  for (int i = 0; i < set->n_tables; ++i) *all_cached &= set->from_cache[i];
  *highest_order = set->multiple_computed ? set->report.highest_order : -1;
  return 0;
}

static int sees_something(const double *L, int n, unsigned char in_atmosphere) {
  if (!in_atmosphere) return 0;
  for (int ch = 0; ch < n; ++ch)
    if (L[ch] != 0.0) return 1;
  return 0;
}

static void reference_rgb(const sf_cmf *cmf, int n, const double *nm, const double *L, double rgb[3]) {
  double xyz[3];
  sf_spectrum_to_xyz(cmf, n, nm, L, xyz);
  sf_xyz_to_linear_srgb(xyz, rgb);
}

/* Accumulates eq. 5.13's sums over the training samples, in sample order. */
static int accumulate(const sf_sky_tables *sky, const sf_view_sample *s, size_t n, const sf_cmf *cmf,
                      int n_threads, sf_spectral4_kernel *k, sf_error *err) {
  int nch = sky->atm->n_channels;
  double *L = malloc((size_t)BLOCK * nch * sizeof *L);
  unsigned char *in = malloc(BLOCK);
  if (!L || !in) {
    free(L);
    free(in);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  for (size_t start = 0; start < n; start += BLOCK) {
    size_t m = n - start < BLOCK ? n - start : BLOCK;
    sf_spectral_radiance(sky, m, s + start, n_threads, L, in);
    for (size_t i = 0; i < m; ++i) {
      const double *Li = L + i * nch;
      if (!sees_something(Li, nch, in[i])) continue;
      double y[3];
      reference_rgb(cmf, nch, sky->atm->wavelengths_nm, Li, y);
      sf_spectral4_kernel_add(k, Li, y, s[start + i].weight);
    }
  }
  free(L);
  free(in);
  return 0;
}

/* ΔE2000 after exposure of every method against the full spectrum. */
static int evaluate(const sf_sky_tables *sky, const sf_view_sample *s, size_t n, const sf_cmf *cmf,
                    const sf_color_method *methods, int n_threads, sf_delta_e_stats *stats, sf_error *err) {
  int nch = sky->atm->n_channels;
  const double *nm = sky->atm->wavelengths_nm;
  double *L = malloc((size_t)BLOCK * nch * sizeof *L);
  unsigned char *in = malloc(BLOCK);
  double *de[SF_SPECTRAL4_METHODS], *block_de = malloc((size_t)BLOCK * SF_SPECTRAL4_METHODS * sizeof *block_de);
  int ok = L && in && block_de;
  for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m) ok &= (de[m] = malloc((n ? n : 1) * sizeof *de[m])) != NULL;
  size_t kept = 0;
#ifdef _OPENMP
  int threads = n_threads > 0 ? n_threads : omp_get_max_threads();
#else
  (void)n_threads;
#endif
  if (ok) {
    for (size_t start = 0; start < n; start += BLOCK) {
      long m_count = (long)(n - start < BLOCK ? n - start : BLOCK);
      sf_spectral_radiance(sky, (size_t)m_count, s + start, n_threads, L, in);
#pragma omp parallel for schedule(static) num_threads(threads)
      for (long i = 0; i < m_count; ++i) {
        const double *Li = L + (size_t)i * nch;
        double rgb[3], lab_ref[3], lab[3];
        reference_rgb(cmf, nch, nm, Li, rgb);
        sf_display_lab(rgb, 1.0, lab_ref);   /* the exposure is in the sample's scale */
        for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m) {
          sf_color_method_apply(&methods[m], cmf, nch, nm, Li, rgb);
          sf_display_lab(rgb, 1.0, lab);
          block_de[(size_t)i * SF_SPECTRAL4_METHODS + m] = sf_ciede2000(lab_ref, lab);
        }
      }
      for (long i = 0; i < m_count; ++i) {
        if (!sees_something(L + (size_t)i * nch, nch, in[i])) continue;
        for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m) de[m][kept] = block_de[(size_t)i * SF_SPECTRAL4_METHODS + m];
        ++kept;
      }
    }
    for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m) sf_delta_e_summarise(de[m], kept, &stats[m]);
  }
  free(L);
  free(in);
  free(block_de);
  for (int m = 0; m < SF_SPECTRAL4_METHODS; ++m) free(de[m]);
  return ok ? 0 : sf_fail(err, SF_ERR_INTERNAL, "out of memory");
}

static void add_stats(cJSON *obj, const char *name, const sf_delta_e_stats *st) {
  cJSON *o = cJSON_AddObjectToObject(obj, name);
  cJSON_AddNumberToObject(o, "mean_delta_e2000", st->mean);
  cJSON_AddNumberToObject(o, "p99_delta_e2000", st->p99);
  cJSON_AddNumberToObject(o, "max_delta_e2000", st->max);
  cJSON_AddNumberToObject(o, "samples", (double)st->n);
}

void sf_spectral4_weights_domain(const sf_scene *scene, sf_scene_domain *domain) {
  sf_error derr = {0};
  if (sf_scene_get_domain(scene, domain, &derr)) memset(domain, 0, sizeof *domain);
  /* The samples' suns: the scene's range within the fit's
   * (fit/spectral4_samples.h), not all of the scene's. */
  domain->mu_s_min = fmax(domain->mu_s_min, sin(SF_SPECTRAL4_SUN_MIN_DEG * SF_PI / 180.0));
  domain->mu_s_max = fmin(domain->mu_s_max, sin(SF_SPECTRAL4_SUN_MAX_DEG * SF_PI / 180.0));
}

static cJSON *weights_document(const sf_scene *scene, const sf_atmosphere *spectral, const sf_cmf *cmf,
                               const sf_spectral4_report *rep, const sf_spectral4_run_options *o) {
  sf_scene_domain domain;
  sf_spectral4_weights_domain(scene, &domain);
  cJSON *doc = sf_weights_new("spectral4", "sky_radiance", &scene->atmosphere, &domain);
  /* SPEC §8's "inputs": the model's functions take radiances, no
   * normalised input */
  if (!doc || !cJSON_AddArrayToObject(doc, "inputs")) {
    cJSON_Delete(doc);
    return NULL;
  }
  const sf_spectral4_params *p = &rep->fit.best;
  double to_xyz[12], to_rgb[12], sun[4], albedo[4];
  int n = spectral->n_channels, nc = spectral->n_constituents;
  double scattering[SF_MAX_CONSTITUENTS * 4], absorption[SF_MAX_CONSTITUENTS * 4];
  sf_spectral4_to_xyz(cmf, p->lambda_nm, p->weight_nm, to_xyz);
  sf_spectral4_srgb_of_xyz(to_xyz, to_rgb);
  for (int i = 0; i < 4; ++i) {
    double l = p->lambda_nm[i];
    sun[i] = sf_spectrum_at(n, spectral->wavelengths_nm, spectral->sun_irradiance, l);
    albedo[i] = sf_spectrum_at(n, spectral->wavelengths_nm, spectral->ground_albedo, l);
    for (int k = 0; k < nc; ++k) {
      scattering[k * 4 + i] = sf_spectrum_at(n, spectral->wavelengths_nm, spectral->constituents[k].scattering, l);
      absorption[k * 4 + i] = sf_spectrum_at(n, spectral->wavelengths_nm, spectral->constituents[k].absorption, l);
    }
  }
  int s4[1] = {4}, s34[2] = {3, 4}, sc4[2] = {nc, 4};
  sf_weights_add_param(doc, "wavelengths_nm", 1, s4, p->lambda_nm);
  sf_weights_add_param(doc, "weights_nm", 1, s4, p->weight_nm);
  sf_weights_add_param(doc, "to_xyz", 2, s34, to_xyz);
  sf_weights_add_param(doc, "to_linear_srgb", 2, s34, to_rgb);
  sf_weights_add_param(doc, "sun_irradiance", 1, s4, sun);
  sf_weights_add_param(doc, "ground_albedo", 1, s4, albedo);
  sf_weights_add_param(doc, "scattering", 2, sc4, scattering);
  sf_weights_add_param(doc, "absorption", 2, sc4, absorption);
  cJSON *m = sf_weights_metrics(doc);
  cJSON_AddNumberToObject(m, "loss", rep->fit.loss);
  cJSON_AddNumberToObject(m, "grid_loss", rep->fit.grid_loss);
  cJSON_AddNumberToObject(m, "rgb_680_550_440_loss", rep->rgb_loss);
  cJSON_AddNumberToObject(m, "uniform4_loss", rep->uniform_loss);
  cJSON_AddNumberToObject(m, "evaluations", rep->fit.evaluations);
  cJSON_AddNumberToObject(m, "nelder_mead_starts", rep->fit.starts);
  cJSON_AddNumberToObject(m, "rgb_scale", rep->rgb_scale);
  cJSON_AddItemToObject(m, "uniform4_wavelengths_nm", cJSON_CreateDoubleArray(rep->methods[2].four.lambda_nm, 4));
  cJSON_AddItemToObject(m, "uniform4_weights_nm", cJSON_CreateDoubleArray(rep->methods[2].four.weight_nm, 4));
  static const char *const atm_names[2] = {"without_aerosols", "with_aerosols"};
  for (int a = 0; a < 2; ++a) {
    cJSON *o_atm = cJSON_AddObjectToObject(m, atm_names[a]);
    for (int k = 0; k < SF_SPECTRAL4_METHODS; ++k) add_stats(o_atm, rep->methods[k].name, &rep->stats[a][k]);
  }
  cJSON_AddBoolToObject(m, "atmosphere_has_aerosols", rep->has_aerosols);
  cJSON *t = sf_weights_training(doc);
  cJSON_AddNumberToObject(t, "seed", 0);
  cJSON_AddNumberToObject(t, "epochs", rep->fit.evaluations);   /* each a pass over every sample */
  cJSON_AddStringToObject(t, "loss", "mse_linear_srgb (seed 003 eq. 5.13)");
  cJSON_AddStringToObject(t, "optimizer", "grid search + NLopt NLOPT_LN_NELDERMEAD");
  cJSON_AddNumberToObject(t, "training_samples", (double)rep->n_train);
  double ref[3] = {o->min_nm, o->max_nm, o->step_nm};
  cJSON_AddItemToObject(t, "reference_wavelengths_nm", cJSON_CreateDoubleArray(ref, 3));
  return doc;
}

static int check_sun_luminance(double luminance, sf_error *err) {
  if (luminance > 0.0) return SF_OK;
  return sf_fail(err, SF_ERR_INPUT, "sun_irradiance: the sun has no luminance (its spectrum is 0 where the eye sees)");
}

/* The fit is to the sky without aerosols (seed 003 §5: every scatterer
 * whose phase is not Rayleigh's is left out); with nothing left that
 * scatters, that sky is black and every loss infinite ("no finite loss",
 * exit 1, after the tables: an isotropic-only or an ozone-only atmosphere). */
static int check_clean_sky_scatters(const sf_atmosphere *full, sf_error *err) {
  sf_atmosphere *clean = malloc(sizeof *clean);
  if (!clean) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_atmosphere_without_aerosols(full, clean);
  int scatters = 0;
  for (int i = 0; i < clean->n_constituents; ++i)
    scatters |= sf_constituent_scatters(&clean->constituents[i], clean->n_channels);
  free(clean);
  if (scatters) return SF_OK;
  return sf_fail(err, SF_ERR_INPUT,
                 "constituents: none scatters with the \"rayleigh\" phase: the 4 wavelengths are fitted to the sky "
                 "without aerosols (seed 003; a constituent of another phase counts as an aerosol), which would be "
                 "black");
}

int sf_spectral4_check_scene(const sf_scene *scene, const sf_spectral4_run_options *o, sf_error *err) {
  double nm[SF_MAX_CHANNELS];
  int n = sf_spectral_grid(o->min_nm, o->max_nm, o->step_nm, nm);
  sf_atmosphere *full = malloc(sizeof *full);
  sf_cmf *cmf = malloc(sizeof *cmf);
  int rc = (!full || !cmf) ? sf_fail(err, SF_ERR_INTERNAL, "out of memory") : 0;
  if (!rc) rc = sf_cmf_load(cmf, err);
  if (!rc) rc = sf_spectral_atmosphere(&scene->atmosphere, n, nm, full, err);
  if (!rc) rc = check_sun_luminance(sf_spectral_sun_luminance(full, cmf), err);
  if (!rc) rc = check_clean_sky_scatters(full, err);
  double lo, hi;
  if (!rc) rc = sf_spectral4_sun_range(scene, &lo, &hi, err);
  free(full);
  free(cmf);
  return rc;
}

int sf_spectral4_run(const sf_scene *scene, const sf_spectral4_run_options *o, sf_spectral4_report *rep,
                     cJSON **doc_out, sf_error *err) {
  memset(rep, 0, sizeof *rep);
  *doc_out = NULL;
  double nm[SF_MAX_CHANNELS];
  int n = sf_spectral_grid(o->min_nm, o->max_nm, o->step_nm, nm);
  sf_atmosphere *full = malloc(sizeof *full), *clean = malloc(sizeof *clean);
  sf_cmf *cmf = malloc(sizeof *cmf);
  sf_table_set *sets = calloc(2, sizeof *sets);
  sf_view_sample *train = NULL, *eval = NULL;
  size_t n_train = 0, n_eval = 0;
  sf_spectral4_kernel kernel = {0};
  int rc = (!full || !clean || !cmf || !sets) ? sf_fail(err, SF_ERR_INTERNAL, "out of memory") : 0;
  if (!rc) rc = sf_cmf_load(cmf, err);
  if (!rc) rc = sf_spectral_atmosphere(&scene->atmosphere, n, nm, full, err);
  if (!rc) {
    rep->has_aerosols = sf_atmosphere_without_aerosols(full, clean) > 0;
    rep->sun_luminance = sf_spectral_sun_luminance(full, cmf);
    rc = check_sun_luminance(rep->sun_luminance, err);
  }
  double display_scale = SF_SPECTRAL4_SUN_LUMINANCE / rep->sun_luminance;
  if (!rc) rc = sf_spectral4_make_samples(scene, &o->train, display_scale, &train, &n_train, err);
  if (!rc) rc = sf_spectral4_make_samples(scene, &o->eval, display_scale, &eval, &n_eval, err);
  /* the reference: without aerosols (fit and evaluation), with (evaluation) */
  double t0 = sf_wall_seconds();
  if (!rc) rc = make_tables(clean, o, &sets[0], &rep->tables_cached[0], &rep->highest_order[0], err);
  if (!rc && rep->has_aerosols)
    rc = make_tables(full, o, &sets[1], &rep->tables_cached[1], &rep->highest_order[1], err);
  rep->reference_seconds = sf_wall_seconds() - t0;
  sf_sky_tables sky[2];
  if (!rc) {
    sf_sky_tables_of_set(&sky[0], clean, &sets[0]);
    if (rep->has_aerosols) sf_sky_tables_of_set(&sky[1], full, &sets[1]);
  }
  /* fit */
  double t1 = sf_wall_seconds();
  if (!rc) rc = sf_spectral4_kernel_init(&kernel, n, nm, cmf, err);
  if (!rc) rc = accumulate(&sky[0], train, n_train, cmf, o->n_threads, &kernel, err);
  rep->n_train = kernel.n_samples;
  if (!rc) rc = sf_spectral4_fit(&kernel, &o->fit, &rep->fit, err);
  rep->fit_seconds = sf_wall_seconds() - t1;
  /* baselines (seed 003 §6 RGB; uniform sampling of eq. 5.10) */
  if (!rc) {
    const double rgb_nm[3] = {SF_RGB_LAMBDA_R_NM, SF_RGB_LAMBDA_G_NM, SF_RGB_LAMBDA_B_NM};
    rep->rgb_loss = sf_spectral4_rgb_baseline(&kernel, rgb_nm, &rep->rgb_scale);
    sf_color_method *m = rep->methods;
    m[0] = (sf_color_method){"spectral4", SF_COLOR_FOUR_WAVELENGTHS, rep->fit.best, {0, 0, 0}, 0.0};
    m[1] = (sf_color_method){"rgb_680_550_440", SF_COLOR_PLAIN_RGB, {{0}, {0}}, {rgb_nm[0], rgb_nm[1], rgb_nm[2]},
                             rep->rgb_scale};
    m[2] = (sf_color_method){"uniform4", SF_COLOR_FOUR_WAVELENGTHS, {{0}, {0}}, {0, 0, 0}, 0.0};
    double width = (SF_UNIFORM4_MAX_NM - SF_UNIFORM4_MIN_NM) / 4.0;
    for (int i = 0; i < 4; ++i) {
      m[2].four.lambda_nm[i] = SF_UNIFORM4_MIN_NM + (i + 0.5) * width;
      m[2].four.weight_nm[i] = width;
    }
    rep->uniform_loss = sf_spectral4_loss(&kernel, &m[2].four);
  }
  /* evaluation */
  double t2 = sf_wall_seconds();
  if (!rc) rc = evaluate(&sky[0], eval, n_eval, cmf, rep->methods, o->n_threads, rep->stats[0], err);
  if (!rc && rep->has_aerosols)
    rc = evaluate(&sky[1], eval, n_eval, cmf, rep->methods, o->n_threads, rep->stats[1], err);
  if (!rc && !rep->has_aerosols) memcpy(rep->stats[1], rep->stats[0], sizeof rep->stats[0]);
  rep->eval_seconds = sf_wall_seconds() - t2;
  if (!rc) {
    *doc_out = weights_document(scene, full, cmf, rep, o);
    if (!*doc_out) rc = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  sf_spectral4_kernel_free(&kernel);
  if (sets) {
    sf_table_set_free(&sets[0]);
    sf_table_set_free(&sets[1]);
  }
  free(sets);
  free(train);
  free(eval);
  free(full);
  free(clean);
  free(cmf);
  return rc;
}
