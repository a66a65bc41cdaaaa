/* Gałaj's spline optical depth (models/optical_depth_spline.h, seed 002
 * §IV.E) against closed forms, an independent integration of the Hermite
 * spline on its own nodes, and the exact reference (models/optical_depth.h)
 * over many rays including the SPEC §10 hard cases. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "models/atmosphere.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_spline.h"
#include "models/ray_geometry.h"
#include "models/rng.h"
#include "tests/check.h"

/* ---- independent spline integrals on the nodes ------------------------------ */

/* The region-I integrand and its t derivative, written out again here. */
static double miss_f(double r, double H, double t, double d) {
  return exp(-(sqrt(d * d + t * t) - r) / H);
}
static double miss_ft(double r, double H, double t, double d) {
  double rho = sqrt(d * d + t * t);
  return -miss_f(r, H, t, d) * t / (H * rho);
}

/* Integral over [0, u] of the cubic Hermite basis on [0, 1] (antiderivatives
 * of 2u^3-3u^2+1, u^3-2u^2+u, -2u^3+3u^2, u^3-u^2). */
static double hermite_partial(double p0, double m0, double p1, double m1, double step,
                              double u) {
  double u2 = u * u, u3 = u2 * u, u4 = u3 * u;
  return step * (p0 * (u - u3 + 0.5 * u4) + step * m0 * (0.5 * u2 - 2.0 / 3.0 * u3 + 0.25 * u4) +
                 p1 * (u3 - 0.5 * u4) + step * m1 * (-u3 / 3.0 + 0.25 * u4));
}

/* Integral over t in [0, t_end] of the 1-D Hermite spline through the
 * region-I nodes at distance d: whole cells by the corrected trapezoid rule
 * (exact for a Hermite cubic), the last cell by the basis antiderivatives. */
static double miss_spline_integral(double r, double H, double step, double d, double t_end) {
  int full = (int)floor(t_end / step);
  double sum = 0.0;
  for (int i = 0; i < full; ++i) {
    double a = step * i, b = step * (i + 1);
    sum += 0.5 * step * (miss_f(r, H, a, d) + miss_f(r, H, b, d)) +
           step * step / 12.0 * (miss_ft(r, H, a, d) - miss_ft(r, H, b, d));
  }
  double a = step * full, u = (t_end - a) / step;
  if (u > 0.0)
    sum += hermite_partial(miss_f(r, H, a, d), miss_ft(r, H, a, d), miss_f(r, H, a + step, d),
                           miss_ft(r, H, a + step, d), step, u);
  return sum;
}

/* The region-II smooth factor s = exp(-h/H)(h+r)/sqrt(h+r+d) and its h
 * derivative by a central difference of the closed form (step 1e-5 km). */
static double hit_s(double r, double H, double h, double d) {
  return exp(-h / H) * (h + r) / sqrt(h + r + d);
}

/* Integral over h in [0, h_end] of s_spline(h)/sqrt(h + r - d), s_spline the
 * Hermite spline through the nodes, by composite Simpson in q = sqrt(h+r-d)
 * with 400 panels per cell. */
static double hit_spline_integral(double r, double H, double step, double d, double h_end,
                                  int n_cells) {
  double delta = r - d, sum = 0.0;
  for (int i = 0; i < n_cells; ++i) {
    double x0 = step * i, x1 = step * (i + 1);
    if (x0 >= h_end) break;
    if (x1 > h_end) x1 = h_end;
    double eps = 1e-5;
    double p0 = hit_s(r, H, x0, d), p1 = hit_s(r, H, step * (i + 1), d);
    double m0 = (hit_s(r, H, x0 + eps, d) - hit_s(r, H, x0 - eps, d)) / (2 * eps);
    double m1 = (hit_s(r, H, step * (i + 1) + eps, d) - hit_s(r, H, step * (i + 1) - eps, d)) /
                (2 * eps);
    double qa = sqrt(x0 + delta), qb = sqrt(x1 + delta);
    int panels = 400;
    double hq = (qb - qa) / panels;
    for (int k = 0; k <= panels; ++k) {
      double q = qa + hq * k, x = q * q - delta, u = (x - x0) / step;
      if (u < 0.0) u = 0.0;
      double u2 = u * u, u3 = u2 * u;
      double s = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * step * m0 +
                 (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * step * m1;
      double wgt = (k == 0 || k == panels) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      sum += wgt * 2.0 * s * hq / 3.0;
    }
  }
  return sum;
}

/* ---- comparison against the reference ---------------------------------------- */

typedef struct error_stats {
  double max_rel, sum_sq;
  long n;
  double worst_h, worst_mu;
} error_stats;

static void stats_add(error_stats *s, double got, double want, double h, double mu) {
  if (!(want > 1e-6)) return;   /* negligible columns: see the absolute check */
  double e = fabs(got - want) / want;
  if (e > s->max_rel) {
    s->max_rel = e;
    s->worst_h = h;
    s->worst_mu = mu;
  }
  s->sum_sq += e * e;
  ++s->n;
}

static double stats_rms(const error_stats *s) { return s->n ? sqrt(s->sum_sq / s->n) : 0.0; }

typedef struct ray_sweep {
  error_stats depth[SF_MAX_CONSTITUENTS];
  double max_abs_transmittance;
  double max_abs_transmittance_exp;   /* the shells' depths taken from the reference */
  long rays, non_finite, negative;
} ray_sweep;

static void sweep_ray(const sf_atmosphere *atm, const sf_spline_model *m, double h, double mu,
                      ray_sweep *sw) {
  double want[SF_MAX_CONSTITUENTS], got[SF_MAX_CONSTITUENTS];
  sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, want);
  sf_optical_depth_spline_ray(m, h, mu, SF_RAY_END_NEAREST, got);
  double tw[SF_MAX_CHANNELS], tg[SF_MAX_CHANNELS];
  sf_transmittance_from_depth(atm, want, tw);
  sf_transmittance_from_depth(atm, got, tg);
  ++sw->rays;
  for (int i = 0; i < atm->n_constituents; ++i) {
    if (!isfinite(got[i])) ++sw->non_finite;
    if (got[i] < 0.0) ++sw->negative;
    stats_add(&sw->depth[i], got[i], want[i], h, mu);
  }
  double mixed[SF_MAX_CONSTITUENTS], tm[SF_MAX_CHANNELS];
  for (int i = 0; i < atm->n_constituents; ++i) mixed[i] = m->is_exponential[i] ? got[i] : want[i];
  sf_transmittance_from_depth(atm, mixed, tm);
  for (int ch = 0; ch < atm->n_channels; ++ch) {
    if (!isfinite(tg[ch])) ++sw->non_finite;
    double e = fabs(tg[ch] - tw[ch]);
    if (e > sw->max_abs_transmittance) sw->max_abs_transmittance = e;
    e = fabs(tm[ch] - tw[ch]);
    if (e > sw->max_abs_transmittance_exp) sw->max_abs_transmittance_exp = e;
  }
}

static void sweep(const sf_atmosphere *atm, const sf_spline_model *m, ray_sweep *sw) {
  memset(sw, 0, sizeof *sw);
  double top = atm->top_radius_km - atm->bottom_radius_km;
  static const double heights[] = {0.0, 1e-6, 1e-3, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0,
                                   35.0, 50.0, 75.0, 99.0};
  static const double space[] = {0.0, 1e-6, 20.0, 1000.0};   /* km above the top */
  static const double fixed_mu[] = {-1.0, -0.9, -0.5, -0.2, -0.05, -1e-3, -1e-6, 0.0,
                                    1e-6, 1e-3, 0.05, 0.2, 0.5, 0.9, 1.0};
  int nh = (int)(sizeof heights / sizeof heights[0]);
  for (int k = 0; k < nh + 4; ++k) {
    double h = k < nh ? heights[k] : top + space[k - nh];
    double r = atm->bottom_radius_km + h;
    double mu_hor = h > 0.0 ? sf_horizon_mu(r, atm->bottom_radius_km) : 0.0;
    /* the ground horizon +-1e-6 (SPEC §10), the fixed set, a uniform sweep */
    double extra[2] = {mu_hor - 1e-6, mu_hor + 1e-6};
    for (int e = 0; e < 2; ++e)
      if (extra[e] >= -1.0 && extra[e] <= 1.0) sweep_ray(atm, m, h, extra[e], sw);
    for (size_t e = 0; e < sizeof fixed_mu / sizeof fixed_mu[0]; ++e)
      sweep_ray(atm, m, h, fixed_mu[e], sw);
    for (int e = 0; e < 40; ++e) sweep_ray(atm, m, h, -1.0 + 2.0 * (e + 0.5) / 40.0, sw);
  }
  /* random viewers in the air, and grazing lines near the ground horizon */
  sf_rng rng;
  sf_rng_seed(&rng, 2021, 2, 5);
  for (int e = 0; e < 1500; ++e) {
    double h = top * sf_rng_uniform(&rng);
    double mu = -1.0 + 2.0 * sf_rng_uniform(&rng);
    sweep_ray(atm, m, h, mu, sw);
    double r = atm->bottom_radius_km + h;
    if (h > 0.0) {
      double mu_g = sf_horizon_mu(r, atm->bottom_radius_km) +
                    1e-3 * (2.0 * sf_rng_uniform(&rng) - 1.0);
      if (mu_g >= -1.0 && mu_g <= 1.0) sweep_ray(atm, m, h, mu_g, sw);
    }
  }
}

static void print_sweep(const char *label, const sf_atmosphere *atm, const ray_sweep *sw) {
  printf("%s: %ld rays\n", label, sw->rays);
  for (int i = 0; i < atm->n_constituents; ++i)
    printf("  %-8s depth rel. error: max %.3e (h=%.6g km, mu=%.9g)  RMS %.3e  over %ld rays\n",
           atm->constituents[i].name, sw->depth[i].max_rel, sw->depth[i].worst_h,
           sw->depth[i].worst_mu, stats_rms(&sw->depth[i]), sw->depth[i].n);
  printf("  max |T - T_ref| %.3e (exponential constituents alone %.3e), non-finite %ld, "
         "negative %ld\n", sw->max_abs_transmittance, sw->max_abs_transmittance_exp,
         sw->non_finite, sw->negative);
}

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  int ray = sf_atmosphere_find(&atm, "rayleigh"), mie = sf_atmosphere_find(&atm, "mie"),
      ozone = sf_atmosphere_find(&atm, "ozone");
  CHECK(ray >= 0 && mie >= 0 && ozone >= 0);
  double r = atm.bottom_radius_km, R = atm.top_radius_km;
  sf_spline_model m;
  CHECK(sf_spline_model_make(&atm, SF_SPLINE_HEIGHT_POINTS, SF_SPLINE_DISTANCE_POINTS, &m) == 0);
  CHECK(m.is_exponential[ray] && m.is_exponential[mie] && !m.is_exponential[ozone]);
  CHECK_REL(m.scale_height_km[ray], 8.0, 1e-12);
  sf_spline_model bad;
  CHECK(sf_spline_model_make(&atm, 1, 20, &bad) == -1);

  /* 1. Region I on its own d nodes: the spline integral along t equals the
   * Hermite interpolant of the exact node data, integrated independently. */
  {
    double step_t = sqrt((R - r) * (R + r)) / (SF_SPLINE_HEIGHT_POINTS - 1);
    double step_d = (R - r) / (SF_SPLINE_DISTANCE_POINTS - 1);
    double worst = 0.0, worst_ref[2] = {0.0, 0.0};
    for (int c = 0; c < 2; ++c) {
      int i = c ? mie : ray;
      double H = m.scale_height_km[i];
      for (int j = 1; j < SF_SPLINE_DISTANCE_POINTS - 1; ++j) {
        double d = r + step_d * j;
        /* horizontal viewer at radius d: the line's distance is d, rising */
        double got = sf_spline_exponential_segment(&m, i, d, 0.0, 0.0, 1e9);
        double t_end = sqrt((R - d) * (R + d));
        double want = miss_spline_integral(r, H, step_t, d, t_end);
        double e = fabs(got - want) / want;
        if (e > worst) worst = e;
        double ref[SF_MAX_CONSTITUENTS];
        sf_optical_depth_ray(&atm, d - r, 0.0, SF_RAY_END_TOP, ref);
        e = fabs(got - ref[i] / m.surface_density[i]) / (ref[i] / m.surface_density[i]);
        if (e > worst_ref[c]) worst_ref[c] = e;
      }
    }
    printf("region I node rows: max rel. difference from the independent Hermite integral %.3e\n",
           worst);
    printf("region I node rows vs reference (t interpolation only): rayleigh %.3e, mie %.3e\n",
           worst_ref[0], worst_ref[1]);
    CHECK(worst < 1e-11);
    CHECK(worst_ref[0] < 1e-5);
    CHECK(worst_ref[1] < 1e-3);
  }

  /* 2. Region II on its own d nodes (the line through the node d, seen from
   * the top looking down to the ground). */
  {
    double step_h = (R - r) / (SF_SPLINE_HEIGHT_POINTS - 1);
    double step_d = r / (SF_SPLINE_DISTANCE_POINTS - 1);
    double worst = 0.0;
    for (int c = 0; c < 2; ++c) {
      int i = c ? mie : ray;
      double H = m.scale_height_km[i];
      for (int j = 0; j < SF_SPLINE_DISTANCE_POINTS - 1; ++j) {
        double d = step_d * j;
        double mu = -sqrt((R - d) * (R + d)) / R;
        double got = sf_spline_exponential_segment(&m, i, R, mu, 0.0, 1e9);
        double want = hit_spline_integral(r, H, step_h, d, R - r, SF_SPLINE_HEIGHT_POINTS - 1);
        double e = fabs(got - want) / want;
        if (e > worst) worst = e;
      }
    }
    printf("region II node rows: max rel. difference from the independent Hermite integral "
           "%.3e\n", worst);
    CHECK(worst < 1e-6);   /* bounded by the test's finite-difference slopes */
  }

  /* 3. Closed forms. Vertical (d = 0): H (1 - exp(-(h1 - h0)/H)) exp(-h0/H).
   * The integral of a cubic Hermite interpolant is the corrected trapezoid
   * rule, whose error (Euler-Maclaurin) is dh^4/720 [f'''] = (dh/H)^4/720 of
   * the column for f = exp(-h/H) (the factor sqrt(h + r) of region II's
   * smooth part changes this by < 1 %): the spline must be that far off,
   * not less and not more (within +-30 %). */
  {
    double depth[SF_MAX_CONSTITUENTS];
    sf_optical_depth_spline_ray(&m, 0.0, 1.0, SF_RAY_END_TOP, depth);
    double top = R - r, dh = top / (SF_SPLINE_HEIGHT_POINTS - 1);
    double Hm = m.scale_height_km[mie];
    double ray_want = 8.0 * -expm1(-top / 8.0), mie_want = Hm * -expm1(-top / Hm);
    double ray_pred = pow(dh / 8.0, 4) / 720.0, mie_pred = pow(dh / Hm, 4) / 720.0;
    printf("vertical column: rayleigh rel. error %.4e (Euler-Maclaurin %.4e), mie %.4e (%.4e)\n",
           fabs(depth[ray] - ray_want) / ray_want, ray_pred,
           fabs(depth[mie] - mie_want) / mie_want, mie_pred);
    CHECK_REL(fabs(depth[ray] - ray_want) / ray_want, ray_pred, 0.3);
    CHECK_REL(fabs(depth[mie] - mie_want) / mie_want, mie_pred, 0.3);
    sf_optical_depth_spline_ray(&m, 30.0, -1.0, SF_RAY_END_NEAREST, depth);
    CHECK_REL(depth[ray], 8.0 * exp(-30.0 / 8.0) * expm1(30.0 / 8.0), 1.3 * ray_pred);
    /* ozone: the eq. 59 shell, 15 km thick for the default tent */
    sf_optical_depth_spline_ray(&m, 0.0, 1.0, SF_RAY_END_TOP, depth);
    double lo, hi;
    sf_flat_shell_of(&atm, ozone, &lo, &hi);
    CHECK_REL(depth[ozone], hi - lo, 1e-12);
    CHECK_REL(hi - lo, 15.0, 1e-6);
  }

  /* 4. Ends and degenerate rays. */
  {
    double depth[SF_MAX_CONSTITUENTS];
    CHECK(sf_optical_depth_spline_ray(&m, 10.0, -0.5, SF_RAY_END_TOP, depth) == -1);
    /* from space, missing the atmosphere: zero */
    CHECK(sf_optical_depth_spline_ray(&m, 500.0, 0.5, SF_RAY_END_NEAREST, depth) == 0);
    CHECK(depth[ray] == 0.0 && depth[mie] == 0.0 && depth[ozone] == 0.0);
    /* h = 0 looking down: nothing left */
    sf_optical_depth_spline_ray(&m, 0.0, -1.0, SF_RAY_END_NEAREST, depth);
    CHECK(depth[ray] == 0.0 && depth[mie] == 0.0);
    /* top looking up: nothing left */
    sf_optical_depth_spline_ray(&m, R - r, 1.0, SF_RAY_END_NEAREST, depth);
    CHECK(depth[ray] == 0.0 && depth[mie] == 0.0);
    /* lines grazing the ground, d -> r from below (region II, d = r is the
     * singular corner of the paper's integrand) and from above (region I) */
    double mu_h = sf_horizon_mu(r + 10.0, r);
    double want_b[SF_MAX_CONSTITUENTS], want_a[SF_MAX_CONSTITUENTS];
    sf_optical_depth_ray(&atm, 10.0, mu_h - 1e-9, SF_RAY_END_NEAREST, want_b);
    sf_optical_depth_ray(&atm, 10.0, mu_h + 1e-9, SF_RAY_END_NEAREST, want_a);
    for (int c = 0; c < 2; ++c) {
      int i = c ? mie : ray;
      double d0 = m.surface_density[i];
      double below = sf_spline_exponential_segment(&m, i, r + 10.0, mu_h - 1e-9, 0.0, 1e9);
      double above = sf_spline_exponential_segment(&m, i, r + 10.0, mu_h + 1e-9, 0.0, 1e9);
      printf("grazing the ground from 10 km (%s): to the ground %.9g (ref %.9g), past it %.9g "
             "(ref %.9g)\n", atm.constituents[i].name, below, want_b[i] / d0, above,
             want_a[i] / d0);
      CHECK_REL(below, want_b[i] / d0, c ? 1e-2 : 1e-4);
      CHECK_REL(above, want_a[i] / d0, c ? 1e-2 : 1e-4);
    }
  }

  /* 5. Many rays against the reference. */
  ray_sweep sw;
  sweep(&atm, &m, &sw);
  print_sweep("Table 3 grid (50 x 20) vs reference", &atm, &sw);
  CHECK(sw.non_finite == 0);
  CHECK(sw.negative == 0);
  /* Measured 4.9e-4 / 8.9e-5 (Rayleigh) and 1.0 / 0.12 (Mie: between
   * region-I d nodes 5.3 km = 4.4 H apart the Hermite interpolation in d
   * undershoots, down to the clamp at 0; on the nodes it is 1.2e-6, above). */
  CHECK(sw.depth[ray].max_rel < 1e-3);
  CHECK(stats_rms(&sw.depth[ray]) < 2e-4);
  CHECK(stats_rms(&sw.depth[mie]) < 0.2);
  CHECK(sw.max_abs_transmittance_exp < 0.03);
  /* the ozone shell (the baselines' eq. 59 fallback) dominates: 0.24 */
  CHECK(sw.max_abs_transmittance < 0.3);

  /* 6. Convergence: a 4x finer grid shrinks the interpolation error. */
  {
    sf_spline_model fine;
    CHECK(sf_spline_model_make(&atm, 4 * SF_SPLINE_HEIGHT_POINTS, 4 * SF_SPLINE_DISTANCE_POINTS,
                               &fine) == 0);
    ray_sweep sf;
    sweep(&atm, &fine, &sf);
    print_sweep("4x finer grid (200 x 80) vs reference", &atm, &sf);
    CHECK(sf.non_finite == 0);
    CHECK(sf.depth[ray].max_rel < 5e-6);
    CHECK(sf.depth[mie].max_rel < 1e-2);
    CHECK(sf.max_abs_transmittance_exp < 5e-4);
    CHECK(sf.depth[ray].max_rel < sw.depth[ray].max_rel / 20.0);
    CHECK(sf.depth[mie].max_rel < sw.depth[mie].max_rel / 20.0);
    sf_spline_model_free(&fine);
  }

  /* 7. Segments inside the air against the reference segment integral. */
  {
    sf_rng rng;
    sf_rng_seed(&rng, 2021, 7, 1);
    error_stats seg_ray = {0}, seg_mie = {0};
    long non_finite = 0;
    for (int e = 0; e < 2000; ++e) {
      double h = (R - r) * sf_rng_uniform(&rng), mu = -1.0 + 2.0 * sf_rng_uniform(&rng);
      double rr = r + h, t_enter, t_exit;
      int hits;
      sf_ray_atmosphere_segment(rr, mu, r, R, &t_enter, &t_exit, &hits);
      double t0 = t_exit * sf_rng_uniform(&rng), t1 = t_exit * sf_rng_uniform(&rng);
      if (t0 > t1) { double x = t0; t0 = t1; t1 = x; }
      double want[SF_MAX_CONSTITUENTS], got[SF_MAX_CONSTITUENTS];
      sf_optical_depth_segment(&atm, rr, mu, t0, t1, want);
      sf_optical_depth_spline_segment(&m, rr, mu, t0, t1, got);
      for (int i = 0; i < atm.n_constituents; ++i) non_finite += !isfinite(got[i]);
      stats_add(&seg_ray, got[ray], want[ray], h, mu);
      stats_add(&seg_mie, got[mie], want[mie], h, mu);
    }
    printf("segments: rayleigh max %.3e RMS %.3e; mie max %.3e RMS %.3e (%ld, %ld segments)\n",
           seg_ray.max_rel, stats_rms(&seg_ray), seg_mie.max_rel, stats_rms(&seg_mie), seg_ray.n,
           seg_mie.n);
    CHECK(non_finite == 0);
    CHECK(seg_ray.max_rel < 1e-3);
    CHECK(stats_rms(&seg_mie) < 0.3);
  }

  sf_spline_model_free(&m);
  return check_summary();
}
