#include "fit/sky_radiance_samples.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/constants.h"

int sf_sky_samples_alloc(sf_sky_samples *s, int n, int n_channels, sf_error *err) {
  memset(s, 0, sizeof *s);
  s->n = n;
  s->n_channels = n_channels;
  s->theta = calloc((size_t)n, sizeof(double));
  s->cos_theta = calloc((size_t)n, sizeof(double));
  s->gamma = calloc((size_t)n, sizeof(double));
  s->cos_gamma = calloc((size_t)n, sizeof(double));
  s->radiance = calloc((size_t)n * (size_t)n_channels, sizeof(double));
  if (!s->theta || !s->cos_theta || !s->gamma || !s->cos_gamma || !s->radiance) {
    sf_sky_samples_free(s);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for %d sky samples", n);
  }
  return SF_OK;
}

void sf_sky_samples_free(sf_sky_samples *s) {
  free(s->theta);
  free(s->cos_theta);
  free(s->gamma);
  free(s->cos_gamma);
  free(s->radiance);
  memset(s, 0, sizeof *s);
}

void sf_sky_sample_set_angles(sf_sky_samples *s, int i, double theta, double cos_gamma) {
  cos_gamma = cos_gamma > 1.0 ? 1.0 : cos_gamma < -1.0 ? -1.0 : cos_gamma;
  s->theta[i] = theta;
  s->cos_theta[i] = cos(theta);
  s->cos_gamma[i] = cos_gamma;
  s->gamma[i] = acos(cos_gamma);
}

int sf_sky_samples_at(const sf_sky_tables *sky, double elevation_rad, int n_theta, const double *theta,
                      int n_phi, sf_sky_samples *out, sf_error *err) {
  if (n_theta < 1 || n_phi < 2)
    return sf_fail(err, SF_ERR_INPUT, "sky samples: need at least 1 x 2 directions, got %d x %d", n_theta, n_phi);
  int nk = sky->atm->n_channels;
  if (sf_sky_samples_alloc(out, n_theta * n_phi, nk, err) != SF_OK) return err->status;
  out->elevation_rad = elevation_rad;
  double mu_s = sin(elevation_rad), cos_e = cos(elevation_rad);
  sf_sky_sample sample;
  for (int i = 0; i < n_theta; ++i) {
    for (int j = 0; j < n_phi; ++j) {
      double phi = (double)j / (n_phi - 1) * SF_PI;
      int idx = i * n_phi + j;
      sf_sky_sample_set_angles(out, idx, theta[i],
                               cos(theta[i]) * mu_s + sin(theta[i]) * cos_e * cos(phi));
      sf_sky_lookup(sky, 0.0, out->cos_theta[idx], mu_s, out->cos_gamma[idx], &sample);
      for (int k = 0; k < nk; ++k) out->radiance[idx * nk + k] = sample.radiance[k];
    }
  }
  sf_sky_lookup(sky, 0.0, 1.0, mu_s, mu_s, &sample);
  for (int k = 0; k < nk; ++k) out->zenith_radiance[k] = sample.radiance[k];
  return SF_OK;
}

int sf_sky_samples_from_tables(const sf_sky_tables *sky, double elevation_rad, int n_theta,
                               int n_phi, sf_sky_samples *out, sf_error *err) {
  if (n_theta < 2 || n_phi < 2)
    return sf_fail(err, SF_ERR_INPUT, "sky samples: need at least 2 x 2 directions, got %d x %d",
                   n_theta, n_phi);
  double *theta = malloc(sizeof *theta * (size_t)n_theta);
  if (!theta) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < n_theta; ++i) theta[i] = (i + 0.5) / n_theta * 0.5 * SF_PI;
  int status = sf_sky_samples_at(sky, elevation_rad, n_theta, theta, n_phi, out, err);
  free(theta);
  return status;
}
