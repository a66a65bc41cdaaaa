/* The published skies as baselines (SPEC §7.2): Preetham 1999 (in linear
 * sRGB, models/preetham.h) and Hosek 2012 RGB (models/hosek_dataset.h), at
 * the turbidity and per-channel factor that fit reference samples best:
 * a scan of T in steps of 0.25 (Preetham 2..10, Hosek 1..10; Hosek with
 * the atmosphere's ground albedo), each T with its closed-form
 * least-squares factor per channel, which maps the models' units
 * (Preetham's kcd/m^2, Hosek's radiance) onto ours. The most favourable
 * reading of them. A channel of an atmosphere without 3 channels takes the
 * model's green (Hosek; Preetham applies to 3 channels only). */
#ifndef SKYFIT_FIT_PUBLISHED_SKY_H
#define SKYFIT_FIT_PUBLISHED_SKY_H

#include "fit/sky_radiance_samples.h"
#include "models/atmosphere.h"
#include "models/hosek_dataset.h"
#include "util/error.h"

typedef struct sf_published_sky {
  int preetham;                         /* 1: Preetham 1999; 0: Hosek 2012 */
  const sf_hosek_dataset *dataset;      /* Hosek: borrowed */
  int n_channels;
  double turbidity;
  double albedo[SF_HOSEK_DATASET_CHANNELS];
  double scale[SF_MAX_CHANNELS];
} sf_published_sky;

/* Fits turbidity and factors to the samples of n_e sun elevations; *rmse
 * over every sample and channel after the factors. SF_ERR_INPUT when the
 * model does not apply (Preetham without 3 channels, Hosek without its
 * dataset); *out and *rmse are then NAN-filled. */
int sf_published_sky_fit(const sf_sky_samples *samples, int n_e, const sf_atmosphere *atm,
                         const sf_hosek_dataset *dataset, int preetham, sf_published_sky *out, double *rmse,
                         sf_error *err);

/* The fitted model's radiance per channel for a ground viewer: view zenith
 * angle theta, view-sun angle gamma, sun elevation (taken into [0, pi/2]). */
void sf_published_sky_radiance(const sf_published_sky *p, double theta, double gamma, double elevation_rad,
                               double *out);

#endif
