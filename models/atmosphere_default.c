/* The built-in default atmosphere: Hillaire 2020 Earth as used by seed 000,
 * written exactly as the file of SPEC §4 (the text is the source of truth; the
 * struct is whatever loading it gives). */
#include "models/atmosphere_file.h"

#include <stdio.h>
#include <stdlib.h>

static const char default_atmosphere_json[] =
    "{\n"
    "  \"name\": \"earth-hillaire2020\",\n"
    "  \"bottom_radius_km\": 6360, \"top_radius_km\": 6460,\n"
    "  \"ground_albedo\": [0, 0, 0],\n"
    "  \"sun_irradiance\": [1, 1, 1], \"sun_angular_radius_rad\": 0.004675,\n"
    "  \"channels\": \"rgb\",\n"
    "  \"constituents\": [\n"
    "    {\"name\": \"rayleigh\", \"scattering\": [5.802e-3, 13.558e-3, 33.1e-3],\n"
    "     \"absorption\": [0, 0, 0], \"phase\": {\"kind\": \"rayleigh\"},\n"
    "     \"density\": [{\"width_km\": 0, \"exp_term\": 1, \"exp_scale_per_km\": -0.125,\n"
    "                  \"linear_per_km\": 0, \"constant\": 0}]},\n"
    "    {\"name\": \"mie\", \"scattering\": [3.996e-3, 3.996e-3, 3.996e-3],\n"
    "     \"absorption\": [0.444e-3, 0.444e-3, 0.444e-3],\n"
    "     \"phase\": {\"kind\": \"cornette_shanks\", \"g\": 0.8},\n"
    "     \"density\": [{\"width_km\": 0, \"exp_term\": 1, \"exp_scale_per_km\": -0.8333333,\n"
    "                  \"linear_per_km\": 0, \"constant\": 0}]},\n"
    "    {\"name\": \"ozone\", \"scattering\": [0, 0, 0],\n"
    "     \"absorption\": [0.650e-3, 1.881e-3, 0.085e-3],\n"
    "     \"density\": [{\"width_km\": 25, \"linear_per_km\": 0.0666667, \"constant\": -0.6666667},\n"
    "                 {\"width_km\": 0, \"linear_per_km\": -0.0666667, \"constant\": 2.6666667}]}\n"
    "  ]\n"
    "}\n";

const char *sf_atmosphere_default_json(void) { return default_atmosphere_json; }

void sf_atmosphere_default(sf_atmosphere *out) {
  sf_error err;
  sf_error_clear(&err);
  if (sf_atmosphere_load_string(default_atmosphere_json, "built-in default atmosphere",
                                out, &err) != 0) {
    /* The text above is fixed and tested: failing here is a bug in skyfit. */
    fprintf(stderr, "skyfit: internal error: %s\n", err.message);
    abort();
  }
}
