/* The scene file (SPEC §5): what a renderer needs modelled — which viewers,
 * which view directions, which sun elevations, which quantities — so that
 * `skyfit build` samples and fits only that domain.
 *
 * Every key is optional; an omitted one keeps the built-in default scene's
 * value (sf_scene_default), except "name" ("unnamed"). Paths in the file
 * ("atmosphere", "outputs") are relative to the scene file's folder.
 *
 * Errors are SF_ERR_INPUT with a one-line message
 * "<source>: <key path>: <problem>", as for the atmosphere file (SPEC §4),
 * e.g. "flight.json: sun_elevation_deg[1]: must be in [-90, 90], got 95".
 * An invalid atmosphere file is reported as
 * "<scene source>: atmosphere: <the atmosphere loader's message>". */
#ifndef SKYFIT_MODELS_SCENE_FILE_H
#define SKYFIT_MODELS_SCENE_FILE_H

#include "models/atmosphere.h"
#include "util/error.h"

typedef enum { SF_VIEW_ALL, SF_VIEW_ABOVE_HORIZON } sf_view_range;
typedef enum { SF_COLOR_RGB, SF_COLOR_SPECTRAL4 } sf_scene_color;

/* Bit flags for sf_scene.quantities. */
#define SF_QUANTITY_SKY_RADIANCE 1u
#define SF_QUANTITY_TRANSMITTANCE 2u

/* Error budgets used when "error_budget" leaves one out. */
#define SF_DEFAULT_TRANSMITTANCE_RMSE 1e-3
#define SF_DEFAULT_SKY_RADIANCE_REL_RMSE 0.05

/* The built-in scene's viewer range: ground to space. 400 km is a low Earth
 * orbit (the ISS), well above the 100 km default atmosphere; every higher
 * viewer sees the same atmosphere from outside it (sf_scene_domain moves
 * viewers above the top to the top), so going higher adds nothing. */
#define SF_DEFAULT_SCENE_VIEWER_MAX_KM 400.0

#define SF_SCENE_PATH_LEN 4096

typedef struct sf_scene {
  char name[96];
  /* Resolved against the scene file's folder; "" = the built-in default. */
  char atmosphere_path[SF_SCENE_PATH_LEN];
  sf_atmosphere atmosphere;        /* loaded from atmosphere_path, or the default */
  double viewer_altitude_km[2];    /* [min, max], >= 0; may exceed the top of the atmosphere */
  sf_view_range view;
  double sun_elevation_deg[2];     /* [min, max] within [-90, 90] */
  unsigned quantities;             /* SF_QUANTITY_* flags, at least one */
  sf_scene_color color;
  double transmittance_rmse_budget;      /* > 0; an unreachable budget is valid */
  double sky_radiance_rel_rmse_budget;   /* > 0 */
  /* Resolved against the scene file's folder; "" if not set. */
  char output_glsl[SF_SCENE_PATH_LEN], output_c[SF_SCENE_PATH_LEN];
} sf_scene;

/* Parse and validate; on failure fill err and return nonzero, *out untouched.
 * sf_scene is large (it holds an sf_atmosphere): allocate it, don't put it on
 * a small stack. */
int sf_scene_load_file(const char *path, sf_scene *out, sf_error *err);
/* source_name names the text in messages (NULL: "<string>"); base_dir is the
 * folder relative paths resolve against (NULL or "": the working directory). */
int sf_scene_load_string(const char *json, const char *source_name, const char *base_dir,
                         sf_scene *out, sf_error *err);

/* Built-in scene (SPEC §5): default atmosphere, viewer 0 ..
 * SF_DEFAULT_SCENE_VIEWER_MAX_KM, view all, sun -10 .. 90 deg, both
 * quantities, rgb, default budgets, no outputs. */
void sf_scene_default(sf_scene *out);

/* The domain in table coordinates (SPEC §3: h above the bottom radius, mu,
 * mu_s):
 *  - h: the viewer range, with viewers above the top of the atmosphere moved
 *    to the top (along a ray from space nothing happens before it enters);
 *  - mu: view all -> [-1, 1]; above_horizon -> [horizon cosine of the highest
 *    (clamped) viewer, 1], which is the lowest horizon of all viewers, so
 *    every viewer's whole sky above its own horizon is inside the box;
 *  - mu_s = sin(sun elevation).
 * Returns 0, or SF_ERR_INPUT naming the scene and the key when the domain is
 * empty or the ranges are invalid (for scenes built by hand). The function
 * is not called sf_scene_domain: C cannot give a function and a type one
 * name. */
typedef struct sf_scene_domain {
  double h_min_km, h_max_km, mu_min, mu_max, mu_s_min, mu_s_max;
} sf_scene_domain;
int sf_scene_get_domain(const sf_scene *s, sf_scene_domain *out, sf_error *err);

/* Whether a point (h above the bottom radius, mu, and with has_sun mu_s)
 * lies outside d, for an atmosphere thickness_km deep. A viewer above the
 * top is checked at the top, as the domain moves it there; its mu, the
 * direction of a ray from space, is not checked against the box's view
 * cosines, which are those where rays enter. */
int sf_scene_domain_outside(const sf_scene_domain *d, double thickness_km, double h, double mu, int has_sun,
                            double mu_s);

/* Whether a and b are the same box, bit for bit (a weights file's domain
 * read back is its writer's exactly: numbers print round-trip). */
int sf_scene_domain_same(const sf_scene_domain *a, const sf_scene_domain *b);

const char *sf_view_range_name(sf_view_range v);
const char *sf_scene_color_name(sf_scene_color c);

#endif
