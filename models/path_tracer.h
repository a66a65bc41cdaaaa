/* Monte Carlo volumetric path tracer: the ground truth for sky radiance
 * (SPEC §6, seed 000 §4). Backward paths from the viewer: delta tracking
 * (Woodcock) for free flights, each straight segment against a guaranteed
 * bound of the extinction above the segment's lowest altitude (exact maxima
 * of the density profiles, models/density_bound.h), next-event estimation
 * towards the sun at every scattering vertex with ratio tracking (Novák et al. 2014, seed 000 eq. 13)
 * for the shadow ray and the planet's shadow, absorption as the local
 * scattering albedo weight, phase functions importance-sampled (weight
 * phase / sampling density), a Lambertian ground that reflects the sun and
 * the sky into later orders (cosine-sampled bounce), and Russian roulette on
 * the path weight after a few orders.
 *
 * The quantity is Bruneton's sky radiance: light scattered into the view ray
 * along its path inside the atmosphere, all orders (or up to max_order), for a
 * point sun of irradiance atm->sun_irradiance[ch] (its angular radius is
 * ignored). Neither the direct sun nor the ground seen at the end of the view
 * ray is included; the ground does light the air in higher orders.
 *
 * Deterministic: sample i of channel ch draws from the random stream
 * (seed, i, ch), samples are summed in fixed blocks and the blocks merged in
 * order, so the result is bit-identical for any thread count. */
#ifndef SKYFIT_MODELS_PATH_TRACER_H
#define SKYFIT_MODELS_PATH_TRACER_H

#include "models/atmosphere.h"
#include "util/error.h"

typedef struct sf_path_tracer_options {
  long long samples;          /* paths per channel, >= 1 */
  unsigned long long seed;
  int max_order;              /* 0: all orders; k: paths of at most k scattering
                                 events, a ground reflection counting as one
                                 (sun -> ground -> air -> eye is order 2, as in
                                 Bruneton's scattering orders) */
  int threads;                /* 0: OpenMP's default; 1: serial */
} sf_path_tracer_options;

typedef struct sf_path_tracer_result {
  double radiance[SF_MAX_CHANNELS];
  double std_error[SF_MAX_CHANNELS];   /* standard error of the mean */
  long long samples;
} sf_path_tracer_result;

/* Sky radiance per channel seen from altitude h_km (km above the bottom
 * radius; above the top radius the ray starts where it enters) along view
 * cosine mu, sun at zenith cosine mu_s, view-sun cosine nu (clamped into the
 * range mu and mu_s allow). Returns 0, or SF_ERR_INPUT with err set for bad
 * arguments, SF_ERR_INTERNAL when out of memory. */
int sf_path_trace_sky_radiance(const sf_atmosphere *atm, double h_km, double mu, double mu_s,
                               double nu, const sf_path_tracer_options *opt,
                               sf_path_tracer_result *out, sf_error *err);

#endif
