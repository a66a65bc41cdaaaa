/* The published Preetham 1999 and Hosek 2012 skies as sky-radiance
 * baselines of the report (SPEC §7.2: "evaluable too, as baselines"; §12:
 * every model fitted or baseline), at the turbidity and per-channel factor
 * that fit the reference best over the scene's sun range
 * (fit/published_sky.h), on the same grid of ground-level samples as our
 * fits. Ground viewer, sun up, RGB atmospheres (the published models are
 * RGB).
 * - Hosek: the dataset's state at that turbidity and the ground albedo is
 *   a quintic Bezier in the sun elevation (its control points baked,
 *   models/hosek_dataset.h), the form of our fitted Hosek: evaluated,
 *   timed in float32 and emitted as it is (fit/candidate_sky_form.c).
 * - Preetham: its zenith values and xyY-to-sRGB conversion are not that
 *   form; evaluated in double, the sun's state per evaluation, not
 *   emitted. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/emit_sky.h"
#include "fit/candidate_fitted.h"
#include "fit/fit_sky_elevation.h"
#include "fit/published_sky.h"
#include "fit/sky_radiance_samples.h"
#include "models/hosek_bezier.h"

/* Preetham, with the clamps of our Perez form's emitted function
 * (codegen/emit_sky.h); never negative. */
static void preetham_eval(const void *ctx, const double *in, double *out) {
  const sf_published_sky *p = ctx;
  double theta, gamma, elevation;
  sf_sky_clamped_angles(SF_SKY_FORM_PEREZ, in[1], in[2], in[3], &theta, &gamma, &elevation);
  sf_published_sky_radiance(p, theta, gamma, elevation, out);
  for (int k = 0; k < p->n_channels; ++k) out[k] = fmax(out[k], 0.0);
}

/* Hosek's state at the fitted turbidity and albedo as our Hosek form, the
 * factors in its radiance. */
static int bake_hosek(const sf_published_sky *p, double e_min, double e_max, sf_elevation_sky_model *m,
                      sf_error *err) {
  memset(m, 0, sizeof *m);
  m->form = SF_SKY_FORM_HOSEK;
  m->n_coeffs = SF_HOSEK_N_COEFFS;
  m->n_channels = 3;
  m->elevation_min_rad = e_min;
  m->elevation_max_rad = e_max;
  for (int k = 0; k < 3; ++k) {
    double radiance[SF_BEZIER_POINTS];
    int status = sf_hosek_dataset_control_points(p->dataset, k, p->turbidity, p->albedo[k], m->coefficients[k],
                                                 radiance, err);
    if (status != SF_OK) return status;
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) m->scale[k][j] = p->scale[k] * radiance[j];
  }
  return SF_OK;
}

static int applies(const sf_candidate_inputs *in, int hosek, char *why, size_t why_len) {
  const char *name = hosek ? "hosek-published" : "preetham-published";
  if (in->atm->spectral || in->atm->n_channels != 3) {
    snprintf(why, why_len, "%s gives RGB; the atmosphere's channels are %s", name,
             in->atm->spectral ? "wavelengths" : "not 3");
    return 0;
  }
  /* where our fits apply: a ground viewer, the sun up, the tables made */
  return hosek ? sf_candidate_applies_hosek(in, why, why_len) : sf_candidate_applies_preetham(in, why, why_len);
}

int sf_candidate_applies_hosek_published(const sf_candidate_inputs *in, char *why, size_t why_len) {
  return applies(in, 1, why, why_len);
}
int sf_candidate_applies_preetham_published(const sf_candidate_inputs *in, char *why, size_t why_len) {
  return applies(in, 0, why, why_len);
}

static int make(const sf_candidate_inputs *in, int hosek, sf_candidate *out, sf_error *err) {
  const char *name = hosek ? "hosek-published" : "preetham-published";
  /* the suns, view grid and valid box of our fits of the same form */
  sf_sky_elevation_options o;
  sf_scene_domain valid;
  sf_candidate_sky_options(in, hosek ? SF_SKY_FORM_HOSEK : SF_SKY_FORM_PEREZ, &o, &valid);
  sf_published_sky *p = calloc(1, sizeof *p);
  sf_hosek_dataset *dataset = hosek ? malloc(sizeof *dataset) : NULL;
  sf_sky_samples *samples = calloc((size_t)o.n_elevations, sizeof *samples);
  sf_elevation_sky_model *m = hosek ? malloc(sizeof *m) : NULL;
  int status = p && samples && (!hosek || (dataset && m)) ? SF_OK : sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK && hosek) status = sf_hosek_dataset_load_default(dataset, err);
  int n_made = 0;
  for (int e = 0; e < o.n_elevations && status == SF_OK; ++e, ++n_made) {
    double x;
    status = sf_sky_samples_from_tables(in->sky, sf_sky_fit_elevation(&o, e, &x), o.n_theta, o.n_phi, &samples[e],
                                        err);
  }
  double rmse = NAN;
  if (status == SF_OK) status = sf_published_sky_fit(samples, o.n_elevations, in->atm, dataset, !hosek, p, &rmse, err);
  for (int e = 0; e < n_made; ++e) sf_sky_samples_free(&samples[e]);
  free(samples);
  char description[400] = "";
  if (status == SF_OK)
    snprintf(description, sizeof description,
             "The published %s at turbidity %.2f with a factor per channel (%.4g, %.4g, %.4g) that maps its "
             "units onto ours: the turbidity and factors that fit the reference best over the scene's sun range "
             "(%d suns, %d x %d directions). Ground viewer, sun up.%s",
             hosek ? "Hosek-Wilkie 2012 RGB dataset" : "Preetham 1999 daylight model (linear sRGB)", p->turbidity,
             p->scale[0], p->scale[1], p->scale[2], o.n_elevations, o.n_theta, o.n_phi,
             hosek ? " Its state baked into our Hosek form (a Bezier in the sun elevation)." : " Not emitted.");
  const char *label = hosek ? "Hosek-Wilkie 2012, published" : "Preetham 1999, published";
  if (status == SF_OK && hosek) {
    status = bake_hosek(p, o.elevation_min_rad, o.elevation_max_rad, m, err);
    if (status == SF_OK) status = sf_candidate_of_sky_model(m, &valid, SF_ROLE_BASELINE, name, label, description,
                                                            out, err);
  } else if (status == SF_OK) {
    sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, name, label);
    snprintf(out->description, sizeof out->description, "%s", description);
    out->n_channels = 3;
    /* what a renderer holds at a fixed turbidity: 3 x 5 Perez
     * coefficients, the zenith luminance's 3 and chromaticities' 2 x 4
     * polynomial coefficients, the 3 x 3 XYZ-to-sRGB matrix, the 3 factors */
    out->n_params = 15 + 3 + 8 + 9 + 3;
    out->constant_bytes = 4 * out->n_params;
    out->valid = valid;
    out->eval = preetham_eval;
    out->ctx = p;
    out->free_ctx = free;
    p = NULL;   /* the candidate's */
  }
  free(p);
  free(dataset);
  free(m);
  return status;
}

int sf_candidate_make_hosek_published(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err) {
  return make(in, 1, out, err);
}
int sf_candidate_make_preetham_published(const sf_candidate_inputs *in, sf_candidate *out, sf_error *err) {
  return make(in, 0, out, err);
}
