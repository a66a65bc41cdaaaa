/* An independent reference for the tests: tanh-sinh (double exponential)
 * quadrature in long double, with its own density formula, its own ray
 * geometry and kink positions supplied by each test from closed forms. It
 * shares no code with models/, so agreement is evidence, not tautology. */
#ifndef SKYFIT_TESTS_INDEPENDENT_INTEGRALS_H
#define SKYFIT_TESTS_INDEPENDENT_INTEGRALS_H

#include <math.h>

#include "models/atmosphere.h"

typedef long double ld;

/* Bruneton's layered density, written out again in long double. */
static inline ld ind_density(const sf_constituent *c, ld h) {
  ld top_of_layer = 0;
  int k = c->n_layers - 1;
  for (int i = 0; i < c->n_layers - 1; ++i) {
    top_of_layer += c->layers[i].width_km;
    if (h < top_of_layer) { k = i; break; }
  }
  const sf_density_layer *l = &c->layers[k];
  ld v = (ld)l->exp_term * expl((ld)l->exp_scale_per_km * h) + (ld)l->linear_per_km * h + (ld)l->constant;
  return v < 0 ? 0 : (v > 1 ? 1 : v);
}

typedef ld (*ind_fn)(void *ctx, ld t);

/* Tanh-sinh on [a, b], refining the step until two levels agree to rel_tol
 * (or 12 levels). Converges double-exponentially for integrands analytic on
 * the piece; the error is then far below the last change. */
static inline ld ind_tanh_sinh_tol(ind_fn f, void *ctx, ld a, ld b, ld rel_tol) {
  if (!(b > a)) return 0;
  const ld half_pi = 1.5707963267948966192313216916397514L;
  ld c = 0.5L * (a + b), hw = 0.5L * (b - a);
  ld step = 0.5L, sum = half_pi * f(ctx, c), previous = 0;
  for (int k = 1; k <= 60; ++k) {      /* level 0 */
    ld x = k * step;
    ld u = half_pi * sinhl(x), ch = coshl(u);
    ld w = half_pi * coshl(x) / (ch * ch);
    ld d = tanhl(u);
    if (w < 1e-40L) break;
    sum += w * (f(ctx, c - hw * d) + f(ctx, c + hw * d));
  }
  ld estimate = sum * step;
  for (int level = 1; level <= 12; ++level) {
    previous = estimate;
    step *= 0.5L;
    for (int k = 1; k <= 60 * (1 << level); k += 2) {
      ld x = k * step;
      ld u = half_pi * sinhl(x), ch = coshl(u);
      ld w = half_pi * coshl(x) / (ch * ch);
      ld d = tanhl(u);
      if (w < 1e-40L) break;
      /* 1 - tanh(u) underflows for large u: the nodes have reached the
       * ends, where the integrand is bounded and the weight negligible. */
      sum += w * (f(ctx, c - hw * d) + f(ctx, c + hw * d));
    }
    estimate = sum * step;
    if (level >= 4 && fabsl(estimate - previous) <= rel_tol * fabsl(estimate)) break;
  }
  return estimate * hw;
}

static inline ld ind_tanh_sinh(ind_fn f, void *ctx, ld a, ld b) {
  return ind_tanh_sinh_tol(f, ctx, a, b, 1e-17L);
}

typedef struct ind_ray {
  const sf_constituent *c;
  ld r, mu, bottom, top;
} ind_ray;

static inline ld ind_density_along(void *ctx, ld t) {
  const ind_ray *ray = ctx;
  ld rr = sqrtl(ray->r * ray->r + t * t + 2 * ray->r * ray->mu * t);
  if (rr > ray->top) return 0;
  return ind_density(ray->c, rr - ray->bottom);
}

static inline int ind_compare(const void *a, const void *b) {
  ld x = *(const ld *)a, y = *(const ld *)b;
  return (x > y) - (x < y);
}

/* Split points of [t0, t1] on the ray (r, mu): the closest approach and the
 * crossings of the kink altitudes (km above bottom). Returns the sorted
 * count, ends included. */
static inline int ind_ray_cuts(ld bottom, const double *kinks, int n_kinks, ld r, ld mu, ld t0, ld t1,
                               ld *cuts) {
  int n = 0;
  cuts[n++] = t0;
  cuts[n++] = t1;
  ld tc = -r * mu;
  if (tc > t0 && tc < t1) cuts[n++] = tc;
  ld d2 = r * r * (1 - mu) * (1 + mu);
  for (int k = 0; k < n_kinks && n < 60; ++k) {
    ld R = bottom + kinks[k];
    ld disc = R * R - d2;
    if (disc < 0) continue;
    ld s = sqrtl(disc);
    if (tc - s > t0 && tc - s < t1) cuts[n++] = tc - s;
    if (tc + s > t0 && tc + s < t1) cuts[n++] = tc + s;
  }
  qsort(cuts, (size_t)n, sizeof cuts[0], ind_compare);
  return n;
}

/* Optical depth of constituent c over [t0, t1], split at the closest
 * approach and at the crossings of the given kink altitudes. */
static inline ld ind_optical_depth_tol(const sf_constituent *c, ld bottom, ld top, ld r, ld mu, ld t0,
                                       ld t1, const double *kinks, int n_kinks, ld rel_tol) {
  ld cuts[64];
  int n = ind_ray_cuts(bottom, kinks, n_kinks, r, mu, t0, t1, cuts);
  ind_ray ray = {c, r, mu, bottom, top};
  ld sum = 0;
  for (int i = 0; i + 1 < n; ++i)
    sum += ind_tanh_sinh_tol(ind_density_along, &ray, cuts[i], cuts[i + 1], rel_tol);
  return sum;
}

static inline ld ind_optical_depth(const sf_constituent *c, ld bottom, ld top, ld r, ld mu, ld t0, ld t1,
                            const double *kinks, int n_kinks) {
  return ind_optical_depth_tol(c, bottom, top, r, mu, t0, t1, kinks, n_kinks, 1e-17L);
}

/* Distance to the sphere of radius R along (r, mu): the far root (which > 0
 * for r <= R), or the near root when near is set; stable in long double. */
static inline ld ind_sphere_distance(ld r, ld mu, ld R, int near) {
  ld disc = (R - r) * (R + r) + r * r * mu * mu;
  if (disc < 0) return -1;
  ld s = sqrtl(disc);
  ld q = -(r * mu + (mu >= 0 ? s : -s));
  ld c = (r - R) * (r + R);
  ld a = q, b = q != 0 ? c / q : 0;
  ld lo = a < b ? a : b, hi = a < b ? b : a;
  return near ? lo : hi;
}

/* Vector-valued tanh-sinh: n components at once (n <= 16), converged when
 * every component's last change is <= rel_tol of its value. */
typedef void (*ind_vec_fn)(void *ctx, ld t, ld *values);

static inline void ind_tanh_sinh_vec(ind_vec_fn f, void *ctx, ld a, ld b, int n, ld rel_tol, ld *out) {
  for (int i = 0; i < n; ++i) out[i] = 0;
  if (!(b > a)) return;
  const ld half_pi = 1.5707963267948966192313216916397514L;
  ld c = 0.5L * (a + b), hw = 0.5L * (b - a);
  ld step = 0.5L, sum[16], est[16], prev[16], v1[16], v2[16];
  f(ctx, c, v1);
  for (int i = 0; i < n; ++i) sum[i] = half_pi * v1[i];
  for (int level = 0; level <= 12; ++level) {
    if (level > 0) step *= 0.5L;
    int stride = level == 0 ? 1 : 2;
    for (int k = 1; k <= 60 * (1 << level); k += stride) {
      ld x = k * step;
      ld u = half_pi * sinhl(x), ch = coshl(u);
      ld w = half_pi * coshl(x) / (ch * ch);
      ld d = tanhl(u);
      if (w < 1e-40L) break;
      f(ctx, c - hw * d, v1);
      f(ctx, c + hw * d, v2);
      for (int i = 0; i < n; ++i) sum[i] += w * (v1[i] + v2[i]);
    }
    int done = level >= 4;
    for (int i = 0; i < n; ++i) {
      prev[i] = est[i];
      est[i] = sum[i] * step;
      if (level < 1 || fabsl(est[i] - prev[i]) > rel_tol * fabsl(est[i])) done = 0;
    }
    if (done) break;
  }
  for (int i = 0; i < n; ++i) out[i] = est[i] * hw;
}

typedef struct ind_ray_all {
  const sf_atmosphere *atm;
  ld r, mu;
} ind_ray_all;

static inline void ind_densities_along(void *ctx, ld t, ld *values) {
  const ind_ray_all *ray = ctx;
  ld rr = sqrtl(ray->r * ray->r + t * t + 2 * ray->r * ray->mu * t);
  for (int i = 0; i < ray->atm->n_constituents; ++i)
    values[i] = rr > (ld)ray->atm->top_radius_km
                    ? 0
                    : ind_density(&ray->atm->constituents[i], rr - (ld)ray->atm->bottom_radius_km);
}

/* Optical depth of every constituent over [t0, t1] (split as above). */
static inline void ind_optical_depth_all(const sf_atmosphere *atm, ld r, ld mu, ld t0, ld t1,
                                         const double *kinks, int n_kinks, ld rel_tol, ld *out) {
  ld cuts[64];
  int n = ind_ray_cuts(atm->bottom_radius_km, kinks, n_kinks, r, mu, t0, t1, cuts);
  ind_ray_all ray = {atm, r, mu};
  for (int i = 0; i < atm->n_constituents; ++i) out[i] = 0;
  for (int p = 0; p + 1 < n; ++p) {
    ld piece[16];
    ind_tanh_sinh_vec(ind_densities_along, &ray, cuts[p], cuts[p + 1], atm->n_constituents, rel_tol, piece);
    for (int i = 0; i < atm->n_constituents; ++i) out[i] += piece[i];
  }
}

/* Gauss-Legendre nodes x[i] and weights w[i] on [-1, 1], n of them, by
 * Newton's iteration on P_n from the Chebyshev-like guess (converges for
 * the n the tests use; Golub-Welsch is not needed). */
static inline void ind_gauss_legendre(int n, ld *x, ld *w) {
  const ld pi = 3.14159265358979323846264338327950288L;
  for (int i = 0; i < n; ++i) {
    ld z = cosl(pi * (i + 0.75L) / (n + 0.5L)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      ld p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        ld p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      ld dz = p1 / dp;
      z -= dz;
      if (fabsl(dz) < 1e-19L) break;
    }
    x[i] = z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

#endif
