/* The built-in scene (SPEC §5): "ground to space, sun -10°…90°, RGB" over the
 * built-in atmosphere, for both quantities. */
#include <string.h>

#include "models/atmosphere_file.h"
#include "models/scene_file.h"

void sf_scene_default(sf_scene *out) {
  memset(out, 0, sizeof *out); /* "" paths: built-in atmosphere, no outputs */
  strcpy(out->name, "default");
  sf_atmosphere_default(&out->atmosphere);
  out->viewer_altitude_km[0] = 0.0;
  out->viewer_altitude_km[1] = SF_DEFAULT_SCENE_VIEWER_MAX_KM;
  out->view = SF_VIEW_ALL;
  out->sun_elevation_deg[0] = -10.0; /* civil twilight reaches -6°, a little margin */
  out->sun_elevation_deg[1] = 90.0;
  out->quantities = SF_QUANTITY_SKY_RADIANCE | SF_QUANTITY_TRANSMITTANCE;
  out->color = SF_COLOR_RGB;
  out->transmittance_rmse_budget = SF_DEFAULT_TRANSMITTANCE_RMSE;
  out->sky_radiance_rel_rmse_budget = SF_DEFAULT_SKY_RADIANCE_REL_RMSE;
}
