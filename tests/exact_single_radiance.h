/* The tests' exact single scattering seen from a viewer: the adaptive
 * quadrature of models/single_scattering.h (to relative tolerance tol) of
 * every constituent times its phase function at nu, the ray from altitude
 * h along mu to the ground or the top; out[ch] (0 where there is no ray). */
#ifndef SKYFIT_TESTS_EXACT_SINGLE_RADIANCE_H
#define SKYFIT_TESTS_EXACT_SINGLE_RADIANCE_H

#include "models/atmosphere.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

static inline void exact_single_radiance(const sf_atmosphere *a, double h, double mu, double mu_s, double nu,
                                         double tol, double *out) {
  for (int ch = 0; ch < a->n_channels; ++ch) out[ch] = 0.0;
  sf_view_ray ray;
  const char *why;
  if (sf_view_ray_make(a, h, mu, SF_RAY_END_NEAREST, -1.0, &ray, &why)) return;
  double s[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_single_scattering_tol(a, &ray, mu_s, nu, tol, s);
  for (int c = 0; c < a->n_constituents; ++c) {
    double phase = sf_phase_value(&a->constituents[c].phase, nu);
    for (int ch = 0; ch < a->n_channels; ++ch) out[ch] += phase * s[c * a->n_channels + ch];
  }
}

#endif
