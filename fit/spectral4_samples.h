/* The (viewer, view direction, sun elevation) samples of the 4-wavelength
 * fit (SPEC §7.3, seed 003 eq. 5.13) and of its evaluation.
 *
 * Viewers: 4 altitudes of the scene, h_min + (h_max - h_min) x {0, 1/64,
 * 1/4, 1} (for the default scene 0, 6.25, 100 and 400 km: ground, plane,
 * orbit and space as in SPEC §12). Directions over the sphere: mu at the
 * centres of n_mu equal cells of [-1, 1] (equal solid angle), azimuth from
 * the sun at the centres of n_phi cells of [0, pi] (the sky is symmetric
 * about the sun's vertical plane); a scene with view "above_horizon" keeps
 * only directions above each viewer's horizon. Rays that see nothing (a
 * viewer on the ground looking down, a space viewer whose ray misses the
 * atmosphere) are left out by the caller once the radiance is known.
 * Sun elevations: the scene's range intersected with [-2, 90] degrees.
 *  - training: n_sun elevations e = lo + (hi - lo) u², u evenly spaced in
 *    [0, 1]: crowded toward sunrise/sunset, where seed 003 §5.4.3 puts its
 *    emphasis ("we have deliberately skipped higher Sun elevation angles");
 *  - evaluation: n_sun elevations evenly spaced over [lo, hi].
 * Each sample's scale is the exposure of SPEC §12 (sf_standard_exposure)
 * times display_scale (the caller's radiance normalisation). */
#ifndef SKYFIT_FIT_SPECTRAL4_SAMPLES_H
#define SKYFIT_FIT_SPECTRAL4_SAMPLES_H

#include <stddef.h>

#include "models/scene_file.h"
#include "models/spectral_reference.h"
#include "util/error.h"

#define SF_SPECTRAL4_SUN_MIN_DEG -2.0
#define SF_SPECTRAL4_SUN_MAX_DEG 90.0
#define SF_SPECTRAL4_VIEWERS 4

typedef struct sf_spectral4_grid {
  int n_sun, n_mu, n_phi;
  int crowd_low_sun;      /* 1: training spacing, 0: even (evaluation) */
} sf_spectral4_grid;

/* The viewer altitudes (km) of the scene. */
void sf_spectral4_viewers(const sf_scene *scene, double h_km[SF_SPECTRAL4_VIEWERS]);

/* The scene's sun elevations within the fit's [SF_SPECTRAL4_SUN_MIN_DEG,
 * SF_SPECTRAL4_SUN_MAX_DEG] (degrees); SF_ERR_INPUT if they miss it. */
int sf_spectral4_sun_range(const sf_scene *scene, double *lo, double *hi, sf_error *err);

/* Allocates *out (caller frees) with the samples; SF_ERR_INPUT when the
 * scene's sun range misses [-2, 90] degrees. */
int sf_spectral4_make_samples(const sf_scene *scene, const sf_spectral4_grid *grid, double display_scale,
                              sf_view_sample **out, size_t *n_out, sf_error *err);

#endif
