/* The Monte Carlo path tracer (models/path_tracer.h) against independent
 * deterministic single-scattering integrals written here (closed-form chord
 * transmittances in a constant-density shell; nested Gauss-Legendre for the
 * default atmosphere, planet shadow included), flux conservation in a
 * conservative optically thick shell over a white ground (all orders), paired
 * monotonicity checks, determinism across thread counts, input validation,
 * and the throughput figure. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "models/atmosphere.h"
#include "models/density_bound.h"
#include "models/path_tracer.h"
#include "models/rng.h"
#include "tests/check.h"
#include "util/clock.h"

#define PI 3.14159265358979323846

/* ---- phase functions, written out again so the reference is independent */

static double ref_phase(const sf_phase *p, double nu) {
  double g = p->g;
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH: return 3.0 / (16.0 * PI) * (1.0 + nu * nu);
    case SF_PHASE_ISOTROPIC: return 1.0 / (4.0 * PI);
    case SF_PHASE_HENYEY_GREENSTEIN:
      return (1.0 - g * g) / (4.0 * PI * pow(1.0 + g * g - 2.0 * g * nu, 1.5));
    case SF_PHASE_CORNETTE_SHANKS:
      return 3.0 * (1.0 - g * g) * (1.0 + nu * nu) /
             (8.0 * PI * (2.0 + g * g) * pow(1.0 + g * g - 2.0 * g * nu, 1.5));
    default: return 0.0;
  }
}

/* ---- atmospheres -------------------------------------------------------- */

static void set_exponential(sf_constituent *c, double scale_per_km) {
  c->n_layers = 1;
  memset(c->layers, 0, sizeof c->layers);
  c->layers[0].exp_term = 1.0;
  c->layers[0].exp_scale_per_km = scale_per_km;
}

static void set_constant(sf_constituent *c, double density) {
  c->n_layers = 1;
  memset(c->layers, 0, sizeof c->layers);
  c->layers[0].constant = density;
}

/* SPEC §4, typed in from the table (not loaded through the file parser). */
static void make_default_atmosphere(sf_atmosphere *a) {
  memset(a, 0, sizeof *a);
  a->bottom_radius_km = 6360.0;
  a->top_radius_km = 6460.0;
  a->n_channels = 3;
  a->n_constituents = 3;
  const double ray[3] = {5.802e-3, 13.558e-3, 33.1e-3};
  const double ozone[3] = {0.650e-3, 1.881e-3, 0.085e-3};
  sf_constituent *r = &a->constituents[0], *m = &a->constituents[1], *o = &a->constituents[2];
  for (int ch = 0; ch < 3; ++ch) {
    a->sun_irradiance[ch] = 1.0;
    r->scattering[ch] = ray[ch];
    m->scattering[ch] = 3.996e-3;
    m->absorption[ch] = 0.444e-3;
    o->absorption[ch] = ozone[ch];
  }
  r->phase.kind = SF_PHASE_RAYLEIGH;
  set_exponential(r, -0.125);
  m->phase.kind = SF_PHASE_CORNETTE_SHANKS;
  m->phase.g = 0.8;
  set_exponential(m, -0.8333333);
  o->n_layers = 2;
  o->layers[0].width_km = 25.0;
  o->layers[0].linear_per_km = 0.0666667;
  o->layers[0].constant = -0.6666667;
  o->layers[1].linear_per_km = -0.0666667;
  o->layers[1].constant = 2.6666667;
  sf_atmosphere_finalize(a);
}

/* A 20 km shell of two constant-density constituents, one isotropic and one
 * Henyey-Greenstein, both absorbing. */
static void make_constant_shell(sf_atmosphere *a) {
  memset(a, 0, sizeof *a);
  a->bottom_radius_km = 6360.0;
  a->top_radius_km = 6380.0;
  a->n_channels = 3;
  a->n_constituents = 2;
  const double sun[3] = {1.0, 2.0, 0.5};
  const double s0[3] = {0.01, 0.02, 0.04}, a0[3] = {0.005, 0.0, 0.01};
  for (int ch = 0; ch < 3; ++ch) {
    a->sun_irradiance[ch] = sun[ch];
    a->ground_albedo[ch] = 0.2;
    a->constituents[0].scattering[ch] = s0[ch];
    a->constituents[0].absorption[ch] = a0[ch];
    a->constituents[1].scattering[ch] = 0.01;
    a->constituents[1].absorption[ch] = 0.002;
  }
  a->constituents[0].phase.kind = SF_PHASE_ISOTROPIC;
  set_constant(&a->constituents[0], 0.5);
  a->constituents[1].phase.kind = SF_PHASE_HENYEY_GREENSTEIN;
  a->constituents[1].phase.g = 0.6;
  set_constant(&a->constituents[1], 1.0);
  sf_atmosphere_finalize(a);
}

/* ---- geometry of the reference, in the frame the tracer documents ------- */

typedef struct frame {
  double r;               /* viewer radius */
  double vx, vz;          /* view direction (vx, 0, vz) */
  double sx, sy, sz;      /* sun direction */
  double nu;              /* the view-sun cosine actually used */
} frame;

static frame make_frame(const sf_atmosphere *a, double h, double mu, double mu_s, double nu) {
  frame f;
  f.r = a->bottom_radius_km + h;
  f.vx = sqrt(fmax(0.0, 1.0 - mu * mu));
  f.vz = mu;
  double ss = sqrt(fmax(0.0, 1.0 - mu_s * mu_s));
  double lo = mu * mu_s - f.vx * ss, hi = mu * mu_s + f.vx * ss;
  f.nu = nu < lo ? lo : (nu > hi ? hi : nu);
  f.sx = f.vx > 0.0 ? (f.nu - mu * mu_s) / f.vx : ss;
  if (fabs(f.sx) > ss) f.sx = f.sx > 0 ? ss : -ss;
  f.sy = sqrt(fmax(0.0, ss * ss - f.sx * f.sx));
  f.sz = mu_s;
  return f;
}

/* Distance from a point at radius^2 rr, with p.d = b, to the sphere of radius
 * R it is inside of, along d. */
static double distance_to_sphere_from_inside(double rr, double b, double R) {
  double c = rr - R * R;           /* <= 0 */
  double disc = b * b - c;
  if (disc < 0.0) disc = 0.0;
  return b > 0.0 ? -c / (b + sqrt(disc)) : -b + sqrt(disc);
}

/* [t0, t1]: where the view ray is inside the atmosphere. Returns 0 if never. */
static int view_segment(const sf_atmosphere *a, const frame *f, double *t0, double *t1) {
  double b = f->r * f->vz, Rt = a->top_radius_km, Rb = a->bottom_radius_km;
  double c = f->r * f->r - Rt * Rt;
  double disc = b * b - c;
  if (disc <= 0.0) return 0;
  double q = sqrt(disc);
  double enter = -b - q, exit = -b + q;
  if (exit <= 0.0) return 0;
  *t0 = enter > 0.0 ? enter : 0.0;
  *t1 = exit;
  double cg = f->r * f->r - Rb * Rb, dg = b * b - cg;
  if (f->vz < 0.0 && dg >= 0.0) {
    double tg = -b - sqrt(dg);
    if (tg > *t0 && tg < *t1) *t1 = tg;
  }
  return 1;
}

static void point_at(const frame *f, double t, double p[3]) {
  p[0] = t * f->vx;
  p[1] = 0.0;
  p[2] = f->r + t * f->vz;
}

/* The planet's shadow: the ray from p towards the sun meets the ground. */
static int in_shadow(const sf_atmosphere *a, const frame *f, double t) {
  double p[3];
  point_at(f, t, p);
  double ps = p[0] * f->sx + p[2] * f->sz;
  double rr = p[0] * p[0] + p[2] * p[2];
  double Rb = a->bottom_radius_km;
  return ps < 0.0 && rr - ps * ps <= Rb * Rb;
}

/* Breakpoints of [t0, t1] where the shadow starts or ends: a line meets the
 * (convex) shadow cylinder in one interval, found by scanning and bisection. */
static int shadow_breaks(const sf_atmosphere *a, const frame *f, double t0, double t1, double *out) {
  int n = 0;
  const int scan = 20000;
  int prev = in_shadow(a, f, t0);
  for (int i = 1; i <= scan && n < 4; ++i) {
    double tb = t0 + (t1 - t0) * i / scan;
    int cur = in_shadow(a, f, tb);
    if (cur != prev) {
      double lo = t0 + (t1 - t0) * (i - 1) / scan, hi = tb;
      for (int it = 0; it < 200 && hi - lo > 1e-13 * (1.0 + hi); ++it) {
        double mid = 0.5 * (lo + hi);
        if (in_shadow(a, f, mid) == prev) lo = mid; else hi = mid;
      }
      out[n++] = 0.5 * (lo + hi);
      prev = cur;
    }
  }
  return n;
}

static const double gl8_x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                0.7966664774136267,  0.9602898564975363};
static const double gl8_w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                0.2223810344533745, 0.1012285362903763};

/* ---- reference 1: constant densities, exact chord-length transmittance -- */

/* Single scattering per channel, E beta_s rho p(nu) integrated against
 * exp(-sigma_t (t - t0)) exp(-sigma_t chord_to_top) over the lit parts. */
static void shell_single_scattering(const sf_atmosphere *a, double h, double mu, double mu_s,
                                    double nu, double *out) {
  frame f = make_frame(a, h, mu, mu_s, nu);
  double t0, t1;
  for (int ch = 0; ch < a->n_channels; ++ch) out[ch] = 0.0;
  if (!view_segment(a, &f, &t0, &t1)) return;
  double cuts[6];
  int n_cuts = 0;
  cuts[n_cuts++] = t0;
  double br[4];
  int nb = shadow_breaks(a, &f, t0, t1, br);
  for (int i = 0; i < nb; ++i) cuts[n_cuts++] = br[i];
  cuts[n_cuts++] = t1;
  for (int ch = 0; ch < a->n_channels; ++ch) {
    double sigma_t = 0.0, source = 0.0;
    for (int i = 0; i < a->n_constituents; ++i) {
      const sf_constituent *c = &a->constituents[i];
      double rho = c->layers[0].constant;
      sigma_t += (c->scattering[ch] + c->absorption[ch]) * rho;
      source += c->scattering[ch] * rho * ref_phase(&c->phase, f.nu);
    }
    double sum = 0.0;
    for (int piece = 0; piece + 1 < n_cuts; ++piece) {
      double a0 = cuts[piece], a1 = cuts[piece + 1];
      if (in_shadow(a, &f, 0.5 * (a0 + a1))) continue;
      const int panels = 400;
      for (int k = 0; k < panels; ++k) {
        double pa = a0 + (a1 - a0) * k / panels, pb = a0 + (a1 - a0) * (k + 1) / panels;
        for (int j = 0; j < 8; ++j) {
          double t = 0.5 * (pa + pb) + 0.5 * (pb - pa) * gl8_x[j];
          double p[3];
          point_at(&f, t, p);
          double rr = p[0] * p[0] + p[2] * p[2];
          double chord = distance_to_sphere_from_inside(rr, p[0] * f.sx + p[2] * f.sz, a->top_radius_km);
          sum += 0.5 * (pb - pa) * gl8_w[j] * exp(-sigma_t * (t - t0 + chord));
        }
      }
    }
    out[ch] = a->sun_irradiance[ch] * source * sum;
  }
}

/* ---- reference 2: any profile, nested Gauss-Legendre -------------------- */

static double height_at(const sf_atmosphere *a, const double p[3]) {
  return sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - a->bottom_radius_km;
}

/* Density integral of each constituent from p along d to the top. */
static void depth_to_top(const sf_atmosphere *a, const double p[3], const double d[3], int panels,
                         double *depth) {
  double rr = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  double b = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
  double length = distance_to_sphere_from_inside(rr, b, a->top_radius_km);
  for (int i = 0; i < a->n_constituents; ++i) depth[i] = 0.0;
  for (int k = 0; k < panels; ++k) {
    double pa = length * k / panels, pb = length * (k + 1) / panels;
    for (int j = 0; j < 8; ++j) {
      double s = 0.5 * (pa + pb) + 0.5 * (pb - pa) * gl8_x[j];
      double q[3] = {p[0] + s * d[0], p[1] + s * d[1], p[2] + s * d[2]};
      double h = height_at(a, q);
      for (int i = 0; i < a->n_constituents; ++i)
        depth[i] += 0.5 * (pb - pa) * gl8_w[j] * sf_constituent_density(&a->constituents[i], h);
    }
  }
}

/* Density integral of each constituent along the view ray over [ta, tb]. */
static void depth_along_view(const sf_atmosphere *a, const frame *f, double ta, double tb,
                             double *depth) {
  for (int i = 0; i < a->n_constituents; ++i) depth[i] = 0.0;
  for (int j = 0; j < 8; ++j) {
    double t = 0.5 * (ta + tb) + 0.5 * (tb - ta) * gl8_x[j];
    double p[3];
    point_at(f, t, p);
    double h = height_at(a, p);
    for (int i = 0; i < a->n_constituents; ++i)
      depth[i] += 0.5 * (tb - ta) * gl8_w[j] * sf_constituent_density(&a->constituents[i], h);
  }
}

static void numeric_single_scattering(const sf_atmosphere *a, double h, double mu, double mu_s,
                                      double nu, int outer_panels, int inner_panels, double *out,
                                      int *n_shadow_breaks) {
  frame f = make_frame(a, h, mu, mu_s, nu);
  double t0, t1;
  int nc = a->n_constituents, nch = a->n_channels;
  for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
  *n_shadow_breaks = 0;
  if (!view_segment(a, &f, &t0, &t1)) return;
  double br[4];
  int nb = shadow_breaks(a, &f, t0, t1, br);
  *n_shadow_breaks = nb;
  double sun[3] = {f.sx, f.sy, f.sz};
  double phase[SF_MAX_CONSTITUENTS];
  for (int i = 0; i < nc; ++i) phase[i] = ref_phase(&a->constituents[i].phase, f.nu);
  double view_depth[SF_MAX_CONSTITUENTS] = {0};   /* from t0 to the panel start */
  double cuts[6];
  int n_cuts = 0;
  cuts[n_cuts++] = t0;
  for (int i = 0; i < nb; ++i) cuts[n_cuts++] = br[i];
  cuts[n_cuts++] = t1;
  for (int piece = 0; piece + 1 < n_cuts; ++piece) {
    double a0 = cuts[piece], a1 = cuts[piece + 1];
    int lit = !in_shadow(a, &f, 0.5 * (a0 + a1));
    int panels = (int)ceil(outer_panels * (a1 - a0) / (t1 - t0)) + 1;
    for (int k = 0; k < panels; ++k) {
      double pa = a0 + (a1 - a0) * k / panels, pb = a0 + (a1 - a0) * (k + 1) / panels;
      if (lit) {
        for (int j = 0; j < 8; ++j) {
          double t = 0.5 * (pa + pb) + 0.5 * (pb - pa) * gl8_x[j];
          double partial[SF_MAX_CONSTITUENTS], to_sun[SF_MAX_CONSTITUENTS], p[3];
          depth_along_view(a, &f, pa, t, partial);
          point_at(&f, t, p);
          depth_to_top(a, p, sun, inner_panels, to_sun);
          double hp = height_at(a, p);
          for (int ch = 0; ch < nch; ++ch) {
            double tau = 0.0, source = 0.0;
            for (int i = 0; i < nc; ++i) {
              const sf_constituent *c = &a->constituents[i];
              tau += (c->scattering[ch] + c->absorption[ch]) * (view_depth[i] + partial[i] + to_sun[i]);
              source += c->scattering[ch] * sf_constituent_density(c, hp) * phase[i];
            }
            out[ch] += 0.5 * (pb - pa) * gl8_w[j] * a->sun_irradiance[ch] * source * exp(-tau);
          }
        }
      }
      double whole[SF_MAX_CONSTITUENTS];
      depth_along_view(a, &f, pa, pb, whole);
      for (int i = 0; i < nc; ++i) view_depth[i] += whole[i];
    }
  }
}

/* ---- the checks --------------------------------------------------------- */

static sf_path_tracer_result trace(const sf_atmosphere *a, double h, double mu, double mu_s, double nu,
                                   long long samples, unsigned long long seed, int max_order, int threads) {
  sf_path_tracer_options opt = {samples, seed, max_order, threads};
  sf_path_tracer_result res;
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_path_trace_sky_radiance(a, h, mu, mu_s, nu, &opt, &res, &err);
  if (rc != 0) {
    printf("path tracer failed: %s\n", err.message);
    memset(&res, 0, sizeof res);
    res.radiance[0] = NAN;
  }
  return res;
}

static void compare(const char *what, int ch, double mc, double se, double ref, double rel_floor) {
  double bound = fmax(3.0 * se, rel_floor * fabs(ref));
  double diff = fabs(mc - ref);
  int ok = isfinite(mc) && diff <= bound;
  printf("%s %-34s ch %d  MC %.6e +- %.2e (%.3f%%)  ref %.6e  diff %.2e = %.2f se  bound %.2e\n",
         ok ? "ok  " : "FAIL", what, ch, mc, se, 100.0 * se / fabs(ref), ref, diff,
         se > 0 ? diff / se : 0.0, bound);
  check_report(ok, what, __FILE__, __LINE__);
}

static void test_constant_shell(void) {
  printf("-- constant-density shell, single scattering vs exact-chord quadrature\n");
  sf_atmosphere a;
  make_constant_shell(&a);
  struct { const char *name; double h, mu, mu_s, nu; } cases[] = {
      {"ground, looking up", 0.0, 1.0, 0.6, 0.6},
      {"30 km, down, night side (shadow)", 30.0, -0.1, 0.0, -0.5},
      {"space 40 km, looking down", 40.0, -0.4, 0.3, 0.2},
      {"5 km, towards the sun", 5.0, 0.2, 0.25, 0.99},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    double ref[3], num[3];
    int nb;
    shell_single_scattering(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu, ref);
    numeric_single_scattering(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu, 200, 50, num, &nb);
    printf("   case '%s': %d shadow boundaries on the view ray\n", cases[k].name, nb);
    for (int ch = 0; ch < 3; ++ch) CHECK_REL(num[ch], ref[ch], 1e-9);   /* the two references agree */
    sf_path_tracer_result r =
        trace(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu, 200000, 11 + k, 1, 0);
    for (int ch = 0; ch < 3; ++ch) compare(cases[k].name, ch, r.radiance[ch], r.std_error[ch], ref[ch], 0.0);
  }
  /* The shadow case must really be partly shadowed. */
  {
    frame f = make_frame(&a, 30.0, -0.1, 0.0, -0.5);
    double t0, t1, br[4];
    view_segment(&a, &f, &t0, &t1);
    CHECK(shadow_breaks(&a, &f, t0, t1, br) >= 1);
  }
}

static void test_default_single(void) {
  printf("-- default atmosphere, max_order 1 vs nested Gauss-Legendre\n");
  sf_atmosphere a;
  make_default_atmosphere(&a);
  struct { const char *name; double h, mu, mu_s, nu; long long samples; } cases[] = {
      {"ground noon, looking up", 0.0, 1.0, 0.9, 0.9, 1500000},
      {"ground sunset, horizon", 0.0, 0.0, 0.0, 0.9, 600000},
      {"100 km, grazing, shadow", 100.0, -0.15, -0.1, 0.0, 1000000},
      {"100 km, down, sun 60 deg", 100.0, -0.5, 0.5, -0.3, 500000},
      {"space 1000 km, down", 1000.0, -0.99, 0.3, -0.2, 1000000},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    double ref[3], fine[3];
    int nb, nb2;
    numeric_single_scattering(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu, 150, 100, ref, &nb);
    /* Quadrature convergence: doubling both resolutions changes little. */
    numeric_single_scattering(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu, 300, 200, fine, &nb2);
    printf("   case '%s': %d shadow boundaries\n", cases[k].name, nb);
    for (int ch = 0; ch < 3; ++ch) CHECK_REL(ref[ch], fine[ch], 1e-5);
    sf_path_tracer_result r = trace(&a, cases[k].h, cases[k].mu, cases[k].mu_s, cases[k].nu,
                                    cases[k].samples, 101 + k, 1, 0);
    for (int ch = 0; ch < 3; ++ch) compare(cases[k].name, ch, r.radiance[ch], r.std_error[ch], fine[ch], 0.01);
    if (k == 2) CHECK(nb == 2);
  }
}

/* Conservative (no absorption) thick shell over a white ground: every photon
 * leaves through the top, so the upward flux through the top at the viewer
 * equals the incident E mu_s (plane-parallel limit: the shell is 1 km thick
 * on a 6360 km planet). The flux pi E_cos[L] is estimated by Monte Carlo over
 * cosine-distributed downward view directions (stratified in mu^2; mirror
 * symmetry: phi in [0, pi]), so no angular quadrature error enters: a
 * Gauss-Legendre rule with 8 x 6 nodes is off by 0.4 % here. */
static void test_flux_conservation(void) {
  printf("-- conservative thick shell over a white ground: upward flux = E mu_s\n");
  sf_atmosphere a;
  memset(&a, 0, sizeof a);
  a.bottom_radius_km = 6360.0;
  a.top_radius_km = 6361.0;
  a.n_channels = 2;
  a.n_constituents = 2;
  /* optical thickness 12 and 16 (the ground seen through them, which the sky
   * radiance leaves out, carries < 2e-6 of the flux) */
  const double ray[2] = {6.0, 4.0}, mie[2] = {6.0, 12.0};
  for (int ch = 0; ch < 2; ++ch) {
    a.sun_irradiance[ch] = 1.0;
    a.ground_albedo[ch] = 1.0;
    a.constituents[0].scattering[ch] = ray[ch];
    a.constituents[1].scattering[ch] = mie[ch];
  }
  a.constituents[0].phase.kind = SF_PHASE_RAYLEIGH;
  set_constant(&a.constituents[0], 1.0);
  a.constituents[1].phase.kind = SF_PHASE_CORNETTE_SHANKS;
  a.constituents[1].phase.g = 0.5;
  set_constant(&a.constituents[1], 1.0);
  sf_atmosphere_finalize(&a);
  const double mu_s = 0.6;
  const int directions = 4500;
  sf_rng rng;
  sf_rng_seed(&rng, 2024, 0, 0);
  double sum[2] = {0, 0}, sum_sq[2] = {0, 0};
  for (int k = 0; k < directions; ++k) {
    double amu = sqrt((k + sf_rng_uniform(&rng)) / directions);
    double phi = PI * sf_rng_uniform(&rng);
    double mu = -amu;
    double nu = mu * mu_s + sqrt((1 - mu * mu) * (1 - mu_s * mu_s)) * cos(phi);
    sf_path_tracer_result r = trace(&a, 1.0, mu, mu_s, nu, 32, 5000 + (unsigned long long)k, 0, 0);
    for (int ch = 0; ch < 2; ++ch) {
      sum[ch] += PI * r.radiance[ch];
      sum_sq[ch] += PI * PI * r.radiance[ch] * r.radiance[ch];
    }
  }
  for (int ch = 0; ch < 2; ++ch) {
    double flux = sum[ch] / directions;
    double se = sqrt((sum_sq[ch] / directions - flux * flux) / (directions - 1));
    printf("   channel %d: upward flux %.5f +- %.5f, incident %.5f\n", ch, flux, se, mu_s);
    compare("upward flux = E mu_s", ch, flux, se, mu_s, 0.0);
  }
}

static void test_paired(void) {
  printf("-- paired seeds: all orders >= single; ground albedo 0.3 > 0\n");
  sf_atmosphere a;
  make_default_atmosphere(&a);
  sf_path_tracer_result single = trace(&a, 0.0, 0.5, 0.9, 0.7, 100000, 7, 1, 0);
  sf_path_tracer_result all = trace(&a, 0.0, 0.5, 0.9, 0.7, 100000, 7, 0, 0);
  sf_atmosphere bright = a;
  for (int ch = 0; ch < 3; ++ch) bright.ground_albedo[ch] = 0.3;
  sf_path_tracer_result lit = trace(&bright, 0.0, 0.5, 0.9, 0.7, 100000, 7, 0, 0);
  for (int ch = 0; ch < 3; ++ch) {
    printf("   ch %d: single %.6e  all orders %.6e (+%.1f%%)  albedo 0.3 %.6e (+%.1f%%)\n", ch,
           single.radiance[ch], all.radiance[ch],
           100.0 * (all.radiance[ch] / single.radiance[ch] - 1.0), lit.radiance[ch],
           100.0 * (lit.radiance[ch] / all.radiance[ch] - 1.0));
    /* Each path's sum only gains terms, so the means are ordered, and the
     * gains are far above the noise. */
    CHECK(all.radiance[ch] >= single.radiance[ch]);
    CHECK(all.radiance[ch] - single.radiance[ch] > 3.0 * all.std_error[ch]);
    CHECK(lit.radiance[ch] >= all.radiance[ch]);
    CHECK(lit.radiance[ch] - all.radiance[ch] > 3.0 * lit.std_error[ch]);
  }
}

static void test_determinism(void) {
  printf("-- determinism: 1 and 2 threads, same seed\n");
  sf_atmosphere a;
  make_default_atmosphere(&a);
  a.ground_albedo[0] = a.ground_albedo[1] = a.ground_albedo[2] = 0.3;
  sf_path_tracer_result one = trace(&a, 2.0, 0.1, 0.2, 0.5, 20000, 42, 0, 1);
  sf_path_tracer_result two = trace(&a, 2.0, 0.1, 0.2, 0.5, 20000, 42, 0, 2);
  sf_path_tracer_result other = trace(&a, 2.0, 0.1, 0.2, 0.5, 20000, 43, 0, 2);
  for (int ch = 0; ch < 3; ++ch)
    printf("   ch %d: 1 thread %.17g, 2 threads %.17g, seed 43: %.17g\n", ch, one.radiance[ch],
           two.radiance[ch], other.radiance[ch]);
  CHECK(memcmp(one.radiance, two.radiance, sizeof one.radiance) == 0);
  CHECK(memcmp(one.std_error, two.std_error, sizeof one.std_error) == 0);
  CHECK(memcmp(one.radiance, other.radiance, sizeof one.radiance) != 0);
}

static void test_edges_and_inputs(void) {
  printf("-- rays that miss, bad inputs\n");
  sf_atmosphere a;
  make_default_atmosphere(&a);
  /* From 1000 km looking up: the ray never enters. */
  sf_path_tracer_result miss = trace(&a, 1000.0, 0.5, 0.5, 0.5, 1000, 1, 0, 1);
  CHECK(miss.radiance[0] == 0.0 && miss.radiance[2] == 0.0 && miss.std_error[1] == 0.0);
  /* Looking straight down from the ground: no air in front of the viewer. */
  sf_path_tracer_result down = trace(&a, 0.0, -1.0, 0.5, -0.5, 1000, 1, 0, 1);
  CHECK(down.radiance[0] == 0.0 && down.radiance[2] == 0.0);
  /* An out-of-range nu is clamped: the same as the clamped value. */
  sf_path_tracer_result clamped = trace(&a, 0.0, 0.3, 0.4, 5.0, 2000, 3, 0, 1);
  double nu_hi = 0.3 * 0.4 + sqrt((1 - 0.09) * (1 - 0.16));
  sf_path_tracer_result at_max = trace(&a, 0.0, 0.3, 0.4, nu_hi, 2000, 3, 0, 1);
  CHECK(memcmp(clamped.radiance, at_max.radiance, sizeof clamped.radiance) == 0);

  sf_path_tracer_options opt = {0, 1, 0, 1};
  sf_path_tracer_result res;
  sf_error err;
  sf_error_clear(&err);
  CHECK(sf_path_trace_sky_radiance(&a, 0.0, 0.5, 0.5, 0.5, &opt, &res, &err) == SF_ERR_INPUT);
  printf("   samples 0: %s\n", err.message);
  opt.samples = 10;
  sf_error_clear(&err);
  CHECK(sf_path_trace_sky_radiance(&a, -1.0, 0.5, 0.5, 0.5, &opt, &res, &err) == SF_ERR_INPUT);
  printf("   h -1: %s\n", err.message);
  sf_error_clear(&err);
  CHECK(sf_path_trace_sky_radiance(&a, 0.0, 1.5, 0.5, 0.5, &opt, &res, &err) == SF_ERR_INPUT);
  printf("   mu 1.5: %s\n", err.message);
  sf_error_clear(&err);
  CHECK(sf_path_trace_sky_radiance(&a, 0.0, 0.5, NAN, 0.5, &opt, &res, &err) == SF_ERR_INPUT);
  printf("   mu_s NaN: %s\n", err.message);
}

/* The majorant bound: never below the density anywhere in the range (a
 * dense scan), and tight (a dense scan gets within 1e-6 of it). */
static void test_density_bound(void) {
  printf("-- density maxima over altitude ranges (the majorants)\n");
  sf_atmosphere a;
  make_default_atmosphere(&a);
  sf_constituent odd[3];
  memset(odd, 0, sizeof odd);
  /* concave: 0.2 + 0.05 h - 0.9 exp(-0.3 h), peak inside, clamped below 0 */
  odd[0].n_layers = 1;
  odd[0].layers[0] = (sf_density_layer){0.0, -0.9, -0.3, -0.02, 0.9};
  /* three layers: rising exponential clipped at 1, a flat step, a decaying tail */
  odd[1].n_layers = 3;
  odd[1].layers[0] = (sf_density_layer){10.0, 0.1, 0.3, 0.0, 0.0};
  odd[1].layers[1] = (sf_density_layer){5.0, 0.0, 0.0, 0.0, 0.4};
  odd[1].layers[2] = (sf_density_layer){0.0, 5.0, -0.1, 0.0, 0.0};
  /* decaying exponential plus a rising line */
  odd[2].n_layers = 1;
  odd[2].layers[0] = (sf_density_layer){0.0, 0.8, -0.5, 0.004, 0.0};
  const sf_constituent *cs[6] = {&a.constituents[0], &a.constituents[1], &a.constituents[2],
                                 &odd[0], &odd[1], &odd[2]};
  sf_rng rng;
  sf_rng_seed(&rng, 9, 0, 0);
  double worst_under = 0.0, worst_loose = 0.0;
  for (int c = 0; c < 6; ++c) {
    for (int trial = 0; trial < 60; ++trial) {
      double lo = 100.0 * sf_rng_uniform(&rng), hi = 100.0 * sf_rng_uniform(&rng);
      if (trial % 3 == 0) lo = 0.0;
      if (lo > hi) { double t = lo; lo = hi; hi = t; }
      double bound = sf_constituent_max_density(cs[c], lo, hi), scanned = 0.0;
      int best = 0;
      for (int i = 0; i <= 20000; ++i) {
        double v = sf_constituent_density(cs[c], lo + (hi - lo) * i / 20000.0);
        if (v > scanned) { scanned = v; best = i; }
      }
      /* refine around the best scan point, 2000 times finer */
      for (int i = -2000; i <= 2000; ++i) {
        double h = lo + (hi - lo) * (best + i / 2000.0) / 20000.0;
        if (h < lo || h > hi) continue;
        double v = sf_constituent_density(cs[c], h);
        if (v > scanned) scanned = v;
      }
      if (scanned - bound > worst_under) worst_under = scanned - bound;
      if (bound - scanned > worst_loose) worst_loose = bound - scanned;
    }
  }
  printf("   360 ranges: scan above bound by at most %.3g; bound above scan by at most %.3g\n",
         worst_under, worst_loose);
  CHECK(worst_under <= 1e-15);
  CHECK(worst_loose <= 1e-6);
  CHECK_ABS(sf_constituent_max_density(&a.constituents[2], 0.0, 100.0), 1.0, 1e-6);   /* ozone peak */
  CHECK_ABS(sf_constituent_max_density(&a.constituents[0], 8.0, 50.0), exp(-1.0), 1e-15);
}

static void report_throughput(void) {
  sf_atmosphere a;
  make_default_atmosphere(&a);
  long long samples = 100000;
  double t0 = sf_wall_seconds();
  sf_path_tracer_result r = trace(&a, 0.0, 0.5, 0.9, 0.7, samples, 5, 0, 1);
  double dt = sf_wall_seconds() - t0;
  printf("-- throughput, default atmosphere, ground noon (mu 0.5, mu_s 0.9), all orders, 1 thread:\n"
         "   %lld samples x 3 channels in %.3f s = %.3g paths/s per core; radiance %.5e %.5e %.5e\n",
         samples, dt, 3.0 * samples / dt, r.radiance[0], r.radiance[1], r.radiance[2]);
  CHECK(isfinite(r.radiance[0]) && r.radiance[2] > r.radiance[0]);   /* the sky is blue */
}

int main(void) {
  double t = sf_wall_seconds();
  test_constant_shell();
  printf("   (%.2f s)\n", sf_wall_seconds() - t);
  t = sf_wall_seconds();
  test_default_single();
  printf("   (%.2f s)\n", sf_wall_seconds() - t);
  t = sf_wall_seconds();
  test_flux_conservation();
  printf("   (%.2f s)\n", sf_wall_seconds() - t);
  t = sf_wall_seconds();
  test_density_bound();
  test_paired();
  test_determinism();
  test_edges_and_inputs();
  printf("   (%.2f s)\n", sf_wall_seconds() - t);
  report_throughput();
  return check_summary();
}
