#include "fit/mlp_sky_metrics.h"

#include <math.h>
#include <string.h>

#include "models/optical_depth.h"
#include "models/views_standard.h"
#include "models/phase.h"
#include "models/rng.h"
#include "util/constants.h"

static void error_begin(sf_mlp_error *e, int nch) {
  memset(e, 0, sizeof *e);
  e->n_channels = nch;
}

static void error_add(sf_mlp_error *e, const double *model, const double *reference) {
  for (int c = 0; c < e->n_channels; ++c) {
    double d = model[c] - reference[c];
    e->rmse[c] += d * d;
    e->max_abs[c] = fmax(e->max_abs[c], fabs(d));
    e->mean_abs_reference += fabs(reference[c]);
  }
  e->n += 1;
}

static void error_end(sf_mlp_error *e) {
  double all = 0.0;
  for (int c = 0; c < e->n_channels; ++c) {
    all += e->rmse[c];
    e->rmse[c] = e->n ? sqrt(e->rmse[c] / e->n) : NAN;
    e->max_abs_all = fmax(e->max_abs_all, e->max_abs[c]);
  }
  e->rmse_all = e->n ? sqrt(all / ((double)e->n * e->n_channels)) : NAN;
  e->mean_abs_reference = e->n ? e->mean_abs_reference / ((double)e->n * e->n_channels) : NAN;
}

static double denorm(const sf_dataset *d, int k, double x) { return x / d->input_scale[k] + d->input_offset[k]; }

void sf_mlp_error_validation(const sf_mlp_sky *m, const sf_dataset *val, sf_mlp_error *out) {
  int nch = m->n_channels;
  error_begin(out, nch);
  double model[SF_MAX_CHANNELS], ref[SF_MAX_CHANNELS];
  for (long i = 0; i < val->n; ++i) {
    const double *x = val->x + i * val->n_in, *y = val->y + i * val->n_out;
    double h = denorm(val, 0, x[0]);
    h = h * h;
    double mu = denorm(val, 1, x[1]);
    if (m->input_map == SF_MLP_INPUTS_BRUNETON)   /* inputs x_r, x_mu (models/mlp_sky.h) */
      sf_mlp_bruneton_inverse(m->bottom_radius_km, m->top_radius_km, denorm(val, 0, x[0]), denorm(val, 1, x[1]), &h,
                              &mu);
    if (m->target == SF_MLP_TARGET_TRANSMITTANCE_TOP) {
      sf_mlp_transmittance_top(m, h, mu, model);
      for (int c = 0; c < nch; ++c) ref[c] = y[c];
    } else {
      double mu_s = denorm(val, 2, x[2]), nu = denorm(val, 3, x[3]);
      sf_mlp_scattering(m, h, mu, mu_s, nu, model);
      if (m->target == SF_MLP_TARGET_SEPARATE) {
        for (int c = 0; c < nch; ++c) ref[c] = y[m->n_single * nch + c];
        for (int k = 0; k < m->n_single; ++k) {
          double phase = sf_phase_value(&m->phases[k], nu);
          for (int c = 0; c < nch; ++c) ref[c] += phase * y[k * nch + c];
        }
      } else {
        for (int c = 0; c < nch; ++c) ref[c] = y[c];
      }
    }
    error_add(out, model, ref);
  }
  error_end(out);
}

void sf_mlp_error_transmittance(const sf_mlp_sky *t, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                long n, uint64_t seed, int float32, sf_mlp_error *out) {
  int nch = atm->n_channels;
  error_begin(out, nch);
  sf_rng rng;
  sf_rng_seed(&rng, seed, 0x74657374ull, 1);
  double top = atm->top_radius_km - atm->bottom_radius_km;
  double h_lo = fmin(dom->h_min_km, top), h_hi = fmin(dom->h_max_km, top);
  double model[SF_MAX_CHANNELS], ref[SF_MAX_CHANNELS], depth[SF_MAX_CONSTITUENTS];
  for (long i = 0; i < n; ++i) {
    /* sqrt-uniform in h like the training grid: more viewers near the ground */
    double s = sqrt(h_lo) + (sqrt(h_hi) - sqrt(h_lo)) * sf_rng_uniform(&rng);
    double h = s * s;
    double mu = dom->mu_min + (dom->mu_max - dom->mu_min) * sf_rng_uniform(&rng);
    sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
    sf_transmittance_from_depth(atm, depth, ref);
    if (float32) {
      float tf[SF_MAX_CHANNELS];
      sf_mlp_transmittance_f(t, (float)h, (float)mu, tf);
      for (int c = 0; c < nch; ++c) model[c] = tf[c];
    } else {
      sf_mlp_transmittance(t, h, mu, model);
    }
    error_add(out, model, ref);
  }
  error_end(out);
}

void sf_mlp_error_radiance(const sf_mlp_sky *s, const sf_sky_tables *sky, const sf_scene_domain *dom,
                           double elevation_deg, long n, uint64_t seed, sf_mlp_error *out) {
  int nch = s->n_channels;
  error_begin(out, nch);
  sf_rng rng;
  sf_rng_seed(&rng, seed, 0x72616469ull, (uint64_t)(elevation_deg * 1000.0 + 1e6));
  double top = s->top_radius_km - s->bottom_radius_km;
  double h_lo = fmin(dom->h_min_km, top), h_hi = fmin(dom->h_max_km, top);
  double mu_s = sin(elevation_deg * SF_PI / 180.0);
  double model[SF_MAX_CHANNELS];
  for (long i = 0; i < n; ++i) {
    double q = sqrt(h_lo) + (sqrt(h_hi) - sqrt(h_lo)) * sf_rng_uniform(&rng);
    double h = q * q;
    double mu = dom->mu_min + (dom->mu_max - dom->mu_min) * sf_rng_uniform(&rng);
    double nu = 2.0 * sf_rng_uniform(&rng) - 1.0;
    sf_sky_sample ref;
    sf_sky_lookup(sky, h, mu, mu_s, nu, &ref);
    sf_mlp_scattering(s, h, mu, mu_s, nu, model);
    error_add(out, model, ref.radiance);
  }
  error_end(out);
}

int sf_mlp_error_transmittance_views(const sf_mlp_sky *t, const sf_atmosphere *atm, int width, int height,
                                     sf_mlp_error *out, int max_views) {
  const sf_view_def *views;
  int nv = sf_standard_transmittance_views(&views);
  if (nv > max_views) nv = max_views;
  int nch = atm->n_channels;
  double model[SF_MAX_CHANNELS], ref[SF_MAX_CHANNELS], depth[SF_MAX_CONSTITUENTS];
  for (int v = 0; v < nv; ++v) {
    sf_view_camera cam;
    sf_view_camera_make(&views[v], atm, width, height, &cam);
    error_begin(&out[v], nch);
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i) {
        double in[4];
        sf_view_pixel_inputs(&cam, atm, i, j, in);
        sf_optical_depth_ray(atm, in[0], in[1], SF_RAY_END_NEAREST, depth);
        sf_transmittance_from_depth(atm, depth, ref);
        sf_mlp_transmittance(t, in[0], in[1], model);
        error_add(&out[v], model, ref);
      }
    error_end(&out[v]);
  }
  return nv;
}

int sf_mlp_error_radiance_views(const sf_mlp_sky *s, const sf_sky_tables *sky, const sf_atmosphere *atm,
                                int width, int height, sf_mlp_error *out, int max_views) {
  const sf_view_def *views;
  int nv = sf_standard_radiance_views(&views);
  if (nv > max_views) nv = max_views;
  int nch = atm->n_channels;
  double model[SF_MAX_CHANNELS], ref[SF_MAX_CHANNELS];
  for (int v = 0; v < nv; ++v) {
    sf_view_camera cam;
    sf_view_camera_make(&views[v], atm, width, height, &cam);
    double scale = views[v].exposure * SF_VIEW_SUN_IRRADIANCE;
    error_begin(&out[v], nch);
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i) {
        double in[4];
        sf_view_pixel_inputs(&cam, atm, i, j, in);
        sf_sky_sample r;
        sf_sky_lookup(sky, in[0], in[1], in[2], in[3], &r);
        sf_mlp_scattering(s, in[0], in[1], in[2], in[3], model);
        for (int c = 0; c < nch; ++c) {
          model[c] *= scale;
          ref[c] = r.radiance[c] * scale;
        }
        error_add(&out[v], model, ref);
      }
    error_end(&out[v]);
  }
  return nv;
}
