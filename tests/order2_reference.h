/* The tests' independent order 2 of the multiple scattering, no tables:
 *   L2(x, v) = integral along the view ray of T(x -> p)
 *              sum_c beta_s,c rho_c(p) integral over 4 pi of P_c(v . w) L1(p, w) dw dt,
 * with L1(p, w) the exact single scattering seen from p along w
 * (tests/exact_single_radiance.h, every constituent times its phase).
 * Quadrature: n->view Gauss nodes along the view ray; in mu 7 Gauss panels
 * of n->mu nodes, split at the local horizon and crowded above it (where
 * the light of the sunlit air over the terminator arrives in the planet's
 * shadow, and the sky is brightest in daylight); n->half_azimuths azimuths
 * over the half circle (L1 is symmetric about the sun's vertical plane). */
#ifndef SKYFIT_TESTS_ORDER2_REFERENCE_H
#define SKYFIT_TESTS_ORDER2_REFERENCE_H

#include <math.h>
#include <stdio.h>

#include "data/gauss_rule.h"
#include "data/sky_lookup.h"
#include "models/atmosphere.h"
#include "models/optical_depth.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"
#include "tests/check.h"
#include "tests/exact_single_radiance.h"
#include "util/constants.h"

typedef struct order2_nodes {
  int view, mu, half_azimuths;
} order2_nodes;

typedef struct vec3 {
  double x, y, z;
} vec3;

static inline double dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 add_scaled(vec3 a, vec3 b, double s) {
  vec3 r = {a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
  return r;
}
static inline vec3 scaled(vec3 a, double s) {
  vec3 r = {a.x * s, a.y * s, a.z * s};
  return r;
}
static inline vec3 cross(vec3 a, vec3 b) {
  vec3 r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  return r;
}

/* G_c(p, v) of every constituent: the incoming single scattering at p
 * (radius rp, unit up, sun s) convolved with P_c(v . w). */
static inline void density_integral(const sf_atmosphere *a, double rp, vec3 up, vec3 s, vec3 v,
                                    const sf_gauss_rule *g, int half_azimuths, double *G) {
  int nch = a->n_channels, nc = a->n_constituents;
  for (int k = 0; k < nc * nch; ++k) G[k] = 0.0;
  double R = a->bottom_radius_km, mu_s = dot(s, up);
  vec3 e1 = add_scaled(s, up, -mu_s);   /* the sun's horizontal direction */
  e1 = scaled(e1, 1.0 / sqrt(dot(e1, e1)));
  vec3 e2 = cross(up, e1);
  double sin_s = sqrt(fmax(0.0, 1.0 - mu_s * mu_s)), mu_h = sf_horizon_mu(rp, R);
  double edge[] = {-1.0, mu_h - 0.05, mu_h, mu_h + 0.01, mu_h + 0.04, mu_h + 0.1, mu_h + 0.3, 1.0};
  double dphi = SF_PI / half_azimuths;
  for (int panel = 0; panel < 7; ++panel)
    for (int k = 0; k < g->n; ++k) {
      double span = edge[panel + 1] - edge[panel], mu = edge[panel] + span * g->x[k];
      double st = sqrt(fmax(0.0, 1.0 - mu * mu));
      for (int j = 0; j < half_azimuths; ++j) {
        double phi = (j + 0.5) * dphi, l1[SF_MAX_CHANNELS];
        exact_single_radiance(a, rp - R, mu, mu_s, mu * mu_s + st * cos(phi) * sin_s, 1e-5, l1);
        for (int side = -1; side <= 1; side += 2) {   /* +-phi see the same L1 */
          vec3 w = add_scaled(add_scaled(scaled(up, mu), e1, st * cos(phi)), e2, side * st * sin(phi));
          double cos_vw = dot(v, w);
          for (int c = 0; c < nc; ++c) {
            double wp = span * g->w[k] * dphi * sf_phase_value(&a->constituents[c].phase, cos_vw);
            for (int ch = 0; ch < nch; ++ch) G[c * nch + ch] += wp * l1[ch];
          }
        }
      }
    }
}

static inline void order2_reference(const sf_atmosphere *a, double h, double mu, double mu_s, double nu,
                                    const order2_nodes *n, double *out) {
  int nch = a->n_channels, nc = a->n_constituents;
  double R = a->bottom_radius_km, r = R + h;
  nu = sf_clamp_nu(mu, mu_s, nu);
  double sin_v = sqrt(1.0 - mu * mu), sin_s = sqrt(1.0 - mu_s * mu_s);
  double sx = (nu - mu * mu_s) / sin_v;
  vec3 x = {0.0, 0.0, r}, v = {sin_v, 0.0, mu};
  vec3 s = {sx, sqrt(fmax(0.0, sin_s * sin_s - sx * sx)), mu_s};
  sf_view_ray ray;
  const char *why;
  sf_view_ray_make(a, h, mu, SF_RAY_END_NEAREST, -1.0, &ray, &why);
  sf_gauss_rule gv, gm;
  sf_gauss_rule_init(&gv, n->view);
  sf_gauss_rule_init(&gm, n->mu);
  for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
  for (int q = 0; q < gv.n; ++q) {
    double t = ray.t0 + (ray.t1 - ray.t0) * gv.x[q], wt = (ray.t1 - ray.t0) * gv.w[q];
    vec3 p = add_scaled(x, v, t);
    double rp = sqrt(dot(p, p)), depth[SF_MAX_CONSTITUENTS], T[SF_MAX_CHANNELS];
    sf_optical_depth_segment(a, r, mu, 0.0, t, depth);
    sf_transmittance_from_depth(a, depth, T);
    double G[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
    density_integral(a, rp, scaled(p, 1.0 / rp), s, v, &gm, n->half_azimuths, G);
    for (int c = 0; c < nc; ++c) {
      double rho = sf_constituent_density(&a->constituents[c], rp - R);
      for (int ch = 0; ch < nch; ++ch) out[ch] += wt * T[ch] * a->constituents[c].scattering[ch] * rho * G[c * nch + ch];
    }
  }
}

/* The lookup's multiple scattering (a table of order 2 alone) at a point
 * against order2_reference, per channel, within rel_bound; prints each. */
static inline void check_order2_point(const sf_sky_tables *sky, const sf_atmosphere *a, const char *name, double h,
                                      double mu, double mu_s, double nu, const order2_nodes *nodes,
                                      double rel_bound) {
  sf_sky_sample table;
  sf_sky_lookup(sky, h, mu, mu_s, nu, &table);
  double want[SF_MAX_CHANNELS];
  order2_reference(a, h, mu, mu_s, nu, nodes, want);
  for (int ch = 0; ch < a->n_channels; ++ch) {
    double rel = table.multiple[ch] / want[ch] - 1.0;
    printf("%-30s ch %d order 2: table %.5g reference %.5g %+.2f%%\n", name, ch, table.multiple[ch], want[ch],
           100.0 * rel);
    check_report(want[ch] > 0.0 && fabs(rel) <= rel_bound, name, __FILE__, __LINE__);
  }
}

#endif
