/* Accuracy of the neural sky (issue targets, SPEC §12 metrics): RMSE as
 * seed 000 eq. 61 and the largest absolute error, per channel.
 *  - held-out validation samples (table grid points never trained on);
 *  - transmittance of full rays (eq. 43, reversed rays) at random points
 *    of the domain against the exact reference (models/optical_depth.h);
 *  - sky radiance at one sun elevation (noon, sunrise, dawn) at random
 *    viewers and directions of the domain against the tables
 *    (data/sky_lookup.h). */
#ifndef SKYFIT_FIT_MLP_SKY_METRICS_H
#define SKYFIT_FIT_MLP_SKY_METRICS_H

#include <stdint.h>

#include "data/sky_lookup.h"
#include "fit/dataset.h"
#include "models/mlp_sky.h"
#include "models/scene_file.h"

typedef struct sf_mlp_error {
  long n;
  int n_channels;
  double rmse[SF_MAX_CHANNELS], max_abs[SF_MAX_CHANNELS];
  double rmse_all, max_abs_all;   /* over every channel */
  double mean_abs_reference;      /* scale of the values compared */
} sf_mlp_error;

/* The model's quantity (T_top, or radiance) at validation samples. */
void sf_mlp_error_validation(const sf_mlp_sky *m, const sf_dataset *val, sf_mlp_error *out);
/* Full-ray transmittance at n random points of the domain; float32 = 1
 * evaluates in float32. */
void sf_mlp_error_transmittance(const sf_mlp_sky *t, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                long n, uint64_t seed, int float32, sf_mlp_error *out);
/* Sky radiance at sun elevation elevation_deg, n random (h, mu, nu). */
void sf_mlp_error_radiance(const sf_mlp_sky *s, const sf_sky_tables *sky, const sf_scene_domain *dom,
                           double elevation_deg, long n, uint64_t seed, sf_mlp_error *out);

/* Full-ray transmittance on the 5 standard transmittance views of seed 000
 * App. C/D (models/views_standard.h; width x height pixels, every pixel,
 * exposure 1) against the exact reference (models/optical_depth.h): one
 * error per view, out[0..n-1] in sf_standard_transmittance_views' order.
 * Returns the number of views (<= max_views). */
int sf_mlp_error_transmittance_views(const sf_mlp_sky *t, const sf_atmosphere *atm, int width, int height,
                                     sf_mlp_error *out, int max_views);

/* Sky radiance on the 12 standard views of seed 000 App. A/B, every pixel
 * (no sun disc, no ground), both sides scaled by the view's exposure times
 * SF_VIEW_SUN_IRRADIANCE as the report renders them, against the tables
 * (data/sky_lookup.h). out[0..n-1] in sf_standard_radiance_views' order. */
int sf_mlp_error_radiance_views(const sf_mlp_sky *s, const sf_sky_tables *sky, const sf_atmosphere *atm,
                                int width, int height, sf_mlp_error *out, int max_views);

#endif
