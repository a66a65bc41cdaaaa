/* Ground-level sky radiance samples for the Perez and Hosek fits (SPEC
 * §7.2): a viewer at h = 0, the sun at a given elevation, view directions
 * on a grid over the sky above the horizon, the reference radiance from the
 * tables (data/sky_lookup.h: single scattering of every constituent times
 * its phase function plus multiple scattering; no sun disc).
 *
 * Grid: theta_i = (i + 1/2)/n_theta * pi/2 (never exactly the horizon,
 * where Perez's exp(B / cos theta) is undefined), azimuth from the sun
 * phi_j = j/(n_phi - 1) * pi (the sky is symmetric about the sun's
 * vertical, so half of it is enough; phi = 0 passes through the sun). */
#ifndef SKYFIT_FIT_SKY_RADIANCE_SAMPLES_H
#define SKYFIT_FIT_SKY_RADIANCE_SAMPLES_H

#include "data/sky_lookup.h"
#include "util/error.h"

typedef struct sf_sky_samples {
  int n, n_channels;
  double elevation_rad;
  double *theta, *cos_theta, *gamma, *cos_gamma;
  double *radiance;          /* [i * n_channels + k] */
  double zenith_radiance[SF_MAX_CHANNELS];   /* the view straight up */
} sf_sky_samples;

/* Allocates n samples (zeroed). */
int sf_sky_samples_alloc(sf_sky_samples *s, int n, int n_channels, sf_error *err);
void sf_sky_samples_free(sf_sky_samples *s);

/* The angles of a sample from (theta, phi) and the sun elevation:
 * cos gamma = cos theta sin e + sin theta cos e cos phi. */
void sf_sky_sample_set_angles(sf_sky_samples *s, int i, double theta, double cos_gamma);

/* Reference samples at the view zenith angles theta[0..n_theta-1] (each
 * with the n_phi azimuths above; n = n_theta * n_phi). */
int sf_sky_samples_at(const sf_sky_tables *sky, double elevation_rad, int n_theta, const double *theta,
                      int n_phi, sf_sky_samples *out, sf_error *err);

/* Reference samples on the grid above (n = n_theta * n_phi). */
int sf_sky_samples_from_tables(const sf_sky_tables *sky, double elevation_rad, int n_theta,
                               int n_phi, sf_sky_samples *out, sf_error *err);

#endif
