/* The standard views of SPEC §12 / seed 000 §11.4: where the camera is, where
 * it looks, where the sun is, and the exposure, so that every model is
 * rendered and compared on the same pictures as seed 000's App. A-D.
 *
 * seed 000 §11.4 fixes the viewers (ground; plane, 5 km; orbit, 100 km then
 * moved 1000 km backwards; space, the whole planet with the sun to the top
 * right; planet shadow from the ground and from 200 km with the sun 3° below
 * the horizon to the right), the suns (dawn -6° and sunrise +6° towards the
 * viewer, noon overhead), the exposures (1; 16 at dawn; 2 in space; 32 for
 * the planet shadow) and the sun irradiance 6. It does not state the field
 * of view or the camera pitch; ours (below, one place) are:
 *   - pinhole camera, 60° vertical field of view (40° in space), the
 *     horizontal one following the image's aspect ratio;
 *   - the pitch of each place, the one whose reference images reproduce
 *     App. B's "Empty" column best (the mean of (1 - L)^2, a white image's
 *     error, depends on the reference alone) among those where App. B's
 *     "Naive" (single scattering only) errs by at least our multiple
 *     scattering, on a 1° grid (bench/bench_views_calibration.c): ground
 *     (and its planet-shadow view) pitched up 3°, plane up 9°, orbit down
 *     2°, moved 1000 km back along its view direction: within 1.0, 1.7 and
 *     0.5 % of the Empty column in every view of the place. Down to the
 *     geometric horizon (the limb centred), orbit-dawn's white image would
 *     err 9 % more than the seed's, more than any exposure of our picture
 *     allows, and its multiple scattering would be 8.5x the seed's naive
 *     model's whole error: not the seed's picture. The 200 km shadow view
 *     matches no pitch (28 % off at best) and keeps the horizon;
 *   - space: at the distance where the top of the atmosphere fills 80 % of
 *     the vertical field of view, looking at the
 *     planet's centre, the sun along (right + up)/sqrt 2, perpendicular to
 *     the view, so half the disc is lit.
 * World frame: planet centre at the origin; the viewer starts above the
 * north pole (0, 0, R + h); forward is +x tilted by the pitch; right is -y.
 *
 * Pixel (i, j), j = 0 the top row: direction ∝ forward + x right + y up with
 * x = (2 (i + 1/2) / W - 1) tan(hfov/2), y = (1 - 2 (j + 1/2) / H) tan(vfov/2).
 * Its model inputs (SPEC §3): h = |p| - R, mu = p.d / |p|, mu_s = p.s / |p|,
 * nu = d.s. */
#ifndef SKYFIT_MODELS_VIEWS_STANDARD_H
#define SKYFIT_MODELS_VIEWS_STANDARD_H

#include <stddef.h>

#include "models/atmosphere.h"

#define SF_VIEW_DEFAULT_WIDTH 192
#define SF_VIEW_DEFAULT_HEIGHT 108
#define SF_VIEW_SUN_IRRADIANCE 6.0

typedef enum sf_view_place {
  SF_PLACE_VIEWER = 0,   /* a viewer at an altitude, looking at the pitch */
  SF_PLACE_SPACE         /* the whole planet from afar */
} sf_view_place;

typedef struct sf_view_def {
  const char *name;          /* seed 000's row name, e.g. "ground-dawn" */
  const char *label;         /* "Ground, dawn (sun -6°)" */
  sf_view_place place;
  double altitude_km;        /* viewer before moving back */
  double pitch_deg;          /* camera pitch; NAN: down to the horizon */
  double move_back_km;
  double vfov_deg;
  double sun_elevation_deg;  /* at the starting viewer */
  double sun_azimuth_deg;    /* from the forward direction, + to the right */
  double exposure;
} sf_view_def;

/* The 12 sky-radiance views of seed 000 App. A/B, in its row order. */
int sf_standard_radiance_views(const sf_view_def **views);
/* The 5 transmittance views of seed 000 App. C/D (ground, plane, orbit,
 * space, planet-shadow-orbit), exposure 1. */
int sf_standard_transmittance_views(const sf_view_def **views);

typedef struct sf_view_camera {
  double position[3];        /* km, planet centre at the origin */
  double forward[3], right[3], up[3];
  double sun[3];             /* unit vector towards the sun */
  double tan_half_h, tan_half_v;
  int width, height;
} sf_view_camera;

void sf_view_camera_make(const sf_view_def *v, const sf_atmosphere *atm, int width, int height,
                         sf_view_camera *cam);
/* Unit direction of pixel (i, j). */
void sf_view_pixel_direction(const sf_view_camera *cam, int i, int j, double d[3]);
/* The model inputs of pixel (i, j): {h_km, mu, mu_s, nu}. h_km is the
 * camera's altitude (it may be above the top of the atmosphere). */
void sf_view_pixel_inputs(const sf_view_camera *cam, const sf_atmosphere *atm, int i, int j,
                          double in[4]);

/* Tone map of seed 000 §11.5: t(x) = 1 - exp(-x) per channel, then the
 * sRGB transfer function, to 8 bits. tonemap = 0 skips t (for
 * transmittance pictures, already in [0, 1]). n pixels of 3 channels. */
void sf_view_to_srgb8(const float *linear, size_t n, int tonemap, unsigned char *out);

#endif
