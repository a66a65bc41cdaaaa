#include "data/sunlit_ray.h"

#include <math.h>

#include "data/sky_lookup.h"
#include "models/optical_depth.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/sun_shadow.h"

/* 8-point Gauss-Legendre on [0, 1] (Abramowitz & Stegun table 25.4):
 * with 4 nodes (and no T_view) daytime lookups came out worse than the
 * samples' own interpolation (sky-relative RMSE 1.2 % against 0.57 %);
 * 16 gained little over 8. */
enum { NODES = 8 };
static const double node_x[NODES] = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355,
                                     0.40828267875217505,  0.591717321247825,   0.7627662049581645,
                                     0.8983332387068134,   0.9801449282487681};
static const double node_w[NODES] = {0.050614268145188126, 0.11119051722668724, 0.15685332293894363,
                                     0.18134189168918097,  0.18134189168918097, 0.15685332293894363,
                                     0.11119051722668724,  0.050614268145188126};

/* T of the ray from altitude h at cosine mu to the top (a sun ray, or a
 * view ray that rises or runs level); 0 where it hits the ground. From
 * Bruneton's table, which holds every ray that misses the ground. Not from
 * Leenman's: its linear mu cannot follow T near the horizontal, where the
 * rays' air deepens by decades within a sample and a falling ray's samples
 * turn from the top to the ground. Interpolated there, T came out far too
 * high for a sun near the point's horizontal: 0.9 km, looking 10.8 deg
 * down towards a sun 0.57 deg below the horizon, the looked-up single
 * scattering was 3.4x the exact in red, 30x in green, 5100x in blue
 * (default resolution, tests/test_single_shadow_leenman.c). With
 * Leenman's tables T is the reference optical depth's instead
 * (models/optical_depth.h, to 1e-6): within 0.32 % there, a low sun's
 * lookups 6-7x as slow (README). */
static void to_top(const sf_atmosphere *atm, const sf_table_params *p, const sf_table *transmittance, int nch,
                   double h, double mu, double *out) {
  if (p->kind != SF_PARAM_LEENMAN) {
    if (sf_transmittance_table_to_top(p, transmittance, h, mu, out) != 0)
      for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
    return;
  }
  double R = atm->bottom_radius_km, r = R + h, t_near, t_far, depth[SF_MAX_CONSTITUENTS];
  if (sf_ray_hits_sphere_from_above(r, mu, R)) {
    for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
    return;
  }
  if (!sf_ray_sphere_intersections(r, mu, atm->top_radius_km, &t_near, &t_far) || !(t_far > 0.0)) {
    for (int ch = 0; ch < nch; ++ch) out[ch] = 1.0;
    return;
  }
  sf_optical_depth_segment_tol(atm, r, mu, 0.0, t_far, 1e-6, depth);
  sf_transmittance_from_depth(atm, depth, out);
}

/* The factors of T_view that do not depend on the point: T to the top
 * from the viewer along the ray upward (the ray itself if it rises, else
 * reversed), and, for a ray that falls to a lowest point above the ground,
 * the distance t_low to that point and T to the top from it along the
 * horizontal. */
typedef struct view_ends {
  double t_low;
  double viewer[SF_MAX_CHANNELS], low[SF_MAX_CHANNELS];
} view_ends;

static view_ends view_ends_make(const sf_atmosphere *atm, const sf_table_params *p, const sf_table *transmittance,
                                int nch, double R, double h, double mu, int hits_ground) {
  view_ends e;
  double r = R + h;
  e.t_low = mu < 0.0 && !hits_ground ? -r * mu : 0.0;
  to_top(atm, p, transmittance, nch, h, fabs(mu), e.viewer);
  if (e.t_low > 0.0)
    to_top(atm, p, transmittance, nch, fmax(0.0, sqrt(sf_ray_closest_radius_sq(r, mu)) - R), 0.0, e.low);
  return e;
}

/* T from the viewer (radius r, cosine mu) to distance t along its ray, as
 * a ratio of rays to the top (Bruneton 2017 GetTransmittance) taken, as
 * his are for a ray to the ground, upward or level only: on the way down
 * (a ray to the ground, or before its lowest point) the reversed rays,
 * T(p, -mu_p) / T(viewer, -mu); past the lowest point the ray goes through
 * it, T(viewer -> low) T(low -> p) = [T(low, 0) / T(viewer, -mu)]
 * [T(low, 0) / T(p, mu_p)]; a rising ray's own, T(viewer, mu) / T(p, mu_p).
 * Bruneton's own ratio for a falling ray to the top, T(viewer, mu) /
 * T(p, mu_p), divides two rays that both pass the lowest point, tiny where
 * that is near the ground, and their table errors do not cancel: from
 * 220 km, sun 2.5 deg down, 45 deg from it, the exact single scattering
 * over F came out 23 % (blue Rayleigh), 29 % (blue Mie) low for a ray 1 km
 * above the ground against a ray that hits it, and wavered by several %
 * up to 12 km; now within 0.1 % over -3..12 km (F on a fine rule).
 * e: view_ends_make of the same ray. */
static void view_transmittance(const sf_atmosphere *atm, const sf_table_params *p, const sf_table *transmittance,
                               int nch, double R, double r, double mu, int hits_ground, double t, const view_ends *e,
                               double *out) {
  double rp = sf_ray_radius_at(r, mu, t), mu_p = fmax(-1.0, fmin(1.0, (r * mu + t) / rp)), T[SF_MAX_CHANNELS];
  int falling = mu < 0.0 && (hits_ground || t <= e->t_low);
  to_top(atm, p, transmittance, nch, fmax(0.0, rp - R), falling ? -mu_p : mu_p, T);
  for (int ch = 0; ch < nch; ++ch) {
    double v = e->viewer[ch], ratio;
    if (falling) ratio = v > 0.0 ? T[ch] / v : 0.0;
    else if (mu < 0.0) ratio = v > 0.0 && T[ch] > 0.0 ? e->low[ch] / v * (e->low[ch] / T[ch]) : 0.0;
    else ratio = T[ch] > 0.0 ? v / T[ch] : 0.0;
    out[ch] = fmin(1.0, ratio);
  }
}

/* Length of the table's view ray: to the ground or to the top. */
static double ray_length(const sf_atmosphere *atm, double r, double mu, int hits_ground) {
  double t_near, t_far;
  int ground = hits_ground && sf_ray_sphere_intersections(r, mu, atm->bottom_radius_km, &t_near, &t_far);
  if (ground && t_near > 0.0) return t_near;
  if (sf_ray_sphere_intersections(r, mu, atm->top_radius_km, &t_near, &t_far) && t_far > 0.0) return t_far;
  return 0.0;
}

void sf_sunlit_ray(const sf_atmosphere *atm, const sf_table_params *p, const sf_table *transmittance, int n,
                   const int *constituents, const sf_scattering_coord *c, double out[][SF_MAX_CHANNELS]) {
  int nch = atm->n_channels;
  for (int k = 0; k < n; ++k)
    for (int ch = 0; ch < nch; ++ch) out[k][ch] = 0.0;
  double R = atm->bottom_radius_km, r = R + c->h, mu = c->mu, mu_s = c->mu_s;
  double nu = sf_clamp_nu(mu, mu_s, c->nu);
  double length = ray_length(atm, r, mu, c->hits_ground);
  if (!(length > 0.0)) return;
  view_ends ends = view_ends_make(atm, p, transmittance, nch, R, c->h, mu, c->hits_ground);
  /* the parts: cut where the sun ray grazes the ground, where the sun
   * crosses the point's horizon (p.s = 0) and at the ray's lowest point,
   * where the density peaks and T_view changes its rays (see
   * view_transmittance); sorted by insertion. Without the last cut, over
   * random views from 100-400 km, suns -10..10 deg, rays whose lowest
   * point lies -3..10 km (3 channels), the lookups' relative RMS error was
   * 2.2 % against 0.7 %; it adds 8 nodes on such rays (F 4.2 -> 5.5 us,
   * a lookup 6.9 -> 8.1 us on them, low suns) */
  sf_sun_line line = sf_sun_line_make(r, mu, mu_s, nu, R);
  double cuts[6], roots[2];
  int n_cuts = 0, n_roots = sf_sun_line_tangent_distances(&line, roots);
  cuts[n_cuts++] = 0.0;
  for (int k = 0; k < n_roots; ++k)
    if (roots[k] > 0.0 && roots[k] < length) cuts[n_cuts++] = roots[k];
  if (nu != 0.0 && -r * mu_s / nu > 0.0 && -r * mu_s / nu < length) cuts[n_cuts++] = -r * mu_s / nu;
  if (ends.t_low > 0.0 && ends.t_low < length) cuts[n_cuts++] = ends.t_low;
  cuts[n_cuts++] = length;
  for (int i = 1; i < n_cuts; ++i)
    for (int j = i; j > 0 && cuts[j] < cuts[j - 1]; --j) {
      double x = cuts[j];
      cuts[j] = cuts[j - 1];
      cuts[j - 1] = x;
    }
  for (int i = 0; i + 1 < n_cuts; ++i) {
    double t0 = cuts[i], span = cuts[i + 1] - t0;
    if (!(span > 0.0) || sf_sun_line_hidden(&line, t0 + 0.5 * span)) continue;
    for (int q = 0; q < NODES; ++q) {
      double t = t0 + span * node_x[q];
      double rp = sf_ray_radius_at(r, mu, t), hp = fmax(0.0, rp - R);
      double mu_sp = fmax(-1.0, fmin(1.0, (r * mu_s + t * nu) / rp));
      double T[SF_MAX_CHANNELS];
      to_top(atm, p, transmittance, nch, hp, mu_sp, T);
      double V[SF_MAX_CHANNELS];
      view_transmittance(atm, p, transmittance, nch, R, r, mu, c->hits_ground, t, &ends, V);
      for (int ch = 0; ch < nch; ++ch) T[ch] *= V[ch];
      for (int k = 0; k < n; ++k) {
        double w = span * node_w[q] * sf_constituent_density(&atm->constituents[constituents[k]], hp);
        for (int ch = 0; ch < nch; ++ch) out[k][ch] += w * T[ch];
      }
    }
  }
}
