#include "fit/spectral4_samples.h"

#include <math.h>
#include <stdlib.h>

#include "models/color_space.h"
#include "util/constants.h"

void sf_spectral4_viewers(const sf_scene *scene, double h_km[SF_SPECTRAL4_VIEWERS]) {
  static const double fraction[SF_SPECTRAL4_VIEWERS] = {0.0, 1.0 / 64.0, 0.25, 1.0};
  double lo = scene->viewer_altitude_km[0], hi = scene->viewer_altitude_km[1];
  for (int i = 0; i < SF_SPECTRAL4_VIEWERS; ++i) h_km[i] = lo + (hi - lo) * fraction[i];
}

int sf_spectral4_sun_range(const sf_scene *scene, double *lo, double *hi, sf_error *err) {
  *lo = fmax(scene->sun_elevation_deg[0], SF_SPECTRAL4_SUN_MIN_DEG);
  *hi = fmin(scene->sun_elevation_deg[1], SF_SPECTRAL4_SUN_MAX_DEG);
  if (!(*hi >= *lo))
    return sf_fail(err, SF_ERR_INPUT, "scene %s: sun_elevation_deg [%g, %g] misses the spectral fit's range [%g, %g]",
                   scene->name, scene->sun_elevation_deg[0], scene->sun_elevation_deg[1], SF_SPECTRAL4_SUN_MIN_DEG,
                   SF_SPECTRAL4_SUN_MAX_DEG);
  return SF_OK;
}

int sf_spectral4_make_samples(const sf_scene *scene, const sf_spectral4_grid *grid, double display_scale,
                              sf_view_sample **out, size_t *n_out, sf_error *err) {
  double lo, hi;
  int rc = sf_spectral4_sun_range(scene, &lo, &hi, err);
  if (rc) return rc;
  const sf_atmosphere *atm = &scene->atmosphere;
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  double viewers[SF_SPECTRAL4_VIEWERS];
  sf_spectral4_viewers(scene, viewers);
  size_t cap = (size_t)SF_SPECTRAL4_VIEWERS * grid->n_sun * grid->n_mu * grid->n_phi;
  sf_view_sample *s = malloc(cap * sizeof *s);
  if (!s) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for %zu samples", cap);
  size_t n = 0;
  for (int v = 0; v < SF_SPECTRAL4_VIEWERS; ++v) {
    double h = viewers[v];
    if (v > 0 && h == viewers[v - 1]) continue;   /* a single-altitude scene */
    double r = R + h;
    /* cosine of the horizon: the ray tangent to the ground */
    double mu_horizon = r > R ? -sqrt(fmax(0.0, 1.0 - (R / r) * (R / r))) : 0.0;
    int in_space = r > Rt;
    for (int e = 0; e < grid->n_sun; ++e) {
      double u = grid->n_sun > 1 ? (double)e / (grid->n_sun - 1) : 0.0;
      double elev = lo + (hi - lo) * (grid->crowd_low_sun ? u * u : u);
      double mu_s = sin(elev * SF_PI / 180.0), sin_s = cos(elev * SF_PI / 180.0);
      double scale = display_scale * sf_standard_exposure(elev, in_space);
      for (int i = 0; i < grid->n_mu; ++i) {
        double mu = -1.0 + 2.0 * (i + 0.5) / grid->n_mu;
        if (scene->view == SF_VIEW_ABOVE_HORIZON && mu < mu_horizon) continue;
        double sin_v = sqrt(fmax(0.0, 1.0 - mu * mu));
        for (int j = 0; j < grid->n_phi; ++j) {
          double phi = SF_PI * (j + 0.5) / grid->n_phi;
          sf_view_sample *x = &s[n++];
          x->h_km = h;
          x->mu = mu;
          x->mu_s = mu_s;
          x->nu = mu * mu_s + sin_v * sin_s * cos(phi);
          x->sun_elevation_deg = elev;
          x->scale = scale;
          x->weight = 1.0;
        }
      }
    }
  }
  *out = s;
  *n_out = n;
  return 0;
}
