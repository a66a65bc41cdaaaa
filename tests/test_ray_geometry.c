/* Ray/sphere geometry (models/ray_geometry.h), double and float, against the
 * textbook quadratic t^2 + 2 r mu t + (r^2 - R^2) = 0 solved in long double.
 *
 * Error bounds are derived, not tuned. With c = r^2 - R^2 and the computed
 * discriminant D = (R - r)(R + r) + (r mu)^2, each term carries a relative
 * rounding of a few eps, so |dD| <~ 3 eps (|c| + r^2 mu^2) and
 * |d sqrt(D)| <~ eps (|c| + r^2 mu^2) / sqrt(D): the distance is
 * ill-conditioned only near tangency, where sqrt(D) -> 0. The large root
 * q = -(r mu + sign(mu) sqrt(D)) adds eps (r|mu| + sqrt(D)); the small one,
 * c / q, has the relative error of q plus ~3 eps. So for a root t:
 *   |dt| <= K (eps |t| + |t|/|q| * eps ((|c| + r^2 mu^2)/sqrt(D) + r|mu| + sqrt(D)))
 * with K = 4. The same formula with the float eps bounds the float version
 * against the double one evaluated at the float-rounded inputs (the rounding
 * of the inputs themselves is not the algorithm's error: r = 6360.001 km is
 * not a float). Away from tangency this is a few float ulps, <= 1e-6
 * relative for distances > 1 km; near tangency it grows like 1/sqrt(D). */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "models/ray_geometry.h"

typedef long double ld;

static const double R_GROUND = 6360.0, R_TOP = 6460.0;

/* The textbook quadratic in long double: the independent reference. */
static int ld_roots(ld r, ld mu, ld R, ld *t_near, ld *t_far) {
  ld disc = r * r * mu * mu - (r * r - R * R);
  if (disc < 0) return 0;
  ld s = sqrtl(disc);
  *t_near = -r * mu - s;
  *t_far = -r * mu + s;
  return 1;
}

/* Its own error: the cancellations in disc and in -r mu - s, at the long
 * double epsilon. */
static double ld_reference_error(double r, double mu, double R) {
  ld disc = (ld)r * r * mu * mu - ((ld)r * r - (ld)R * R);
  ld s = sqrtl(disc > 0 ? disc : 0);
  ld scale = (ld)r * r * mu * mu + (ld)r * r + (ld)R * R;
  ld e = 4 * LDBL_EPSILON * (s > 0 ? scale / s : 1e30L) + 4 * LDBL_EPSILON * ((ld)r * fabs(mu) + s);
  return (double)e;
}

/* The derived bound of the header comment for root t, with rounding unit eps. */
static double root_bound(double r, double mu, double R, double t, double eps) {
  double c = (r - R) * (r + R);
  double disc = (R - r) * (R + r) + (r * mu) * (r * mu);
  double s = sqrt(disc > 0 ? disc : 0);
  double q = r * fabs(mu) + s;
  double cond = eps * ((fabs(c) + r * r * mu * mu) / (s > 0 ? s : 1e-300) + r * fabs(mu) + s);
  return 4.0 * (eps * fabs(t) + (q > 0 ? fabs(t) / q : 1.0) * cond);
}

static void check_dist(const char *label, double got, double want, double abs_bound) {
  double err = fabs(got - want);
  int ok = isfinite(got) && err <= abs_bound;
  printf("%s %-40s got %.17g want %.17g abs.err %.3g (bound %.3g, rel.err %.3g)\n",
         ok ? "ok  " : "FAIL", label, got, want, err, abs_bound,
         want != 0 ? err / fabs(want) : err);
  check_report(ok, label, __FILE__, __LINE__);
}

static void check_int(const char *label, int got, int want) {
  int ok = got == want;
  printf("%s %-40s got %d want %d\n", ok ? "ok  " : "FAIL", label, got, want);
  check_report(ok, label, __FILE__, __LINE__);
}

/* Expected atmosphere segment from the long-double roots. */
static int ld_segment(double r, double mu, ld *t_enter, ld *t_exit, int *hits_ground) {
  ld tn, tf, gn, gf;
  *hits_ground = 0;
  if (!ld_roots(r, mu, R_TOP, &tn, &tf) || tf <= 0) return 0;
  *t_enter = tn > 0 ? tn : 0;
  *t_exit = tf;
  if (mu < 0 && ld_roots(r, mu, R_GROUND, &gn, &gf) && gn >= 0 && gn < *t_exit) {
    *t_exit = gn;
    *hits_ground = 1;
  }
  return 1;
}

static int well_conditioned(double r, double mu, double R) {
  double c = (r - R) * (r + R);
  double disc = (R - r) * (R + r) + (r * mu) * (r * mu);
  return disc > 0 && 16 * disc >= fabs(c) + r * r * mu * mu;
}

/* Double segment vs long double; float segment vs double at float inputs. */
static void check_segment(double h, double mu) {
  double r = R_GROUND + h;
  char label[128];
  ld le, lx;
  int lg;
  int lok = ld_segment(r, mu, &le, &lx, &lg);
  double te = -1, tx = -1;
  int g = -1;
  int ok = sf_ray_atmosphere_segment(r, mu, R_GROUND, R_TOP, &te, &tx, &g);
  snprintf(label, sizeof label, "h=%g mu=%g: enters", h, mu);
  check_int(label, ok, lok);
  if (!ok || !lok) return;
  snprintf(label, sizeof label, "h=%g mu=%g: hits ground", h, mu);
  check_int(label, g, lg);
  double ref_e = ld_reference_error(r, mu, g ? R_GROUND : R_TOP);
  snprintf(label, sizeof label, "h=%g mu=%g: t_enter", h, mu);
  check_dist(label, te, (double)le,
             root_bound(r, mu, R_TOP, (double)le, DBL_EPSILON) + ld_reference_error(r, mu, R_TOP));
  snprintf(label, sizeof label, "h=%g mu=%g: t_exit", h, mu);
  check_dist(label, tx, (double)lx, root_bound(r, mu, g ? R_GROUND : R_TOP, (double)lx, DBL_EPSILON) + ref_e);
  /* The end point lies on the sphere it stops at. */
  snprintf(label, sizeof label, "h=%g mu=%g: radius at t_exit", h, mu);
  check_dist(label, sf_ray_radius_at(r, mu, tx), g ? R_GROUND : R_TOP, 1e-9 * R_TOP);

  /* float at float-rounded inputs vs double at the same inputs */
  float rf = (float)r, muf = (float)mu;
  float tef = -1, txf = -1;
  int gf = -1;
  double ted, txd;
  int gd;
  int okd = sf_ray_atmosphere_segment(rf, muf, R_GROUND, R_TOP, &ted, &txd, &gd);
  int okf = sf_ray_atmosphere_segment_f(rf, muf, (float)R_GROUND, (float)R_TOP, &tef, &txf, &gf);
  snprintf(label, sizeof label, "float h=%g mu=%g: enters", h, mu);
  check_int(label, okf, okd);
  if (!okf || !okd) return;
  snprintf(label, sizeof label, "float h=%g mu=%g: hits ground", h, mu);
  check_int(label, gf, gd);
  snprintf(label, sizeof label, "float h=%g mu=%g: t_enter", h, mu);
  check_dist(label, tef, ted, root_bound(rf, muf, R_TOP, ted, FLT_EPSILON) + 1e-30);
  double bx = root_bound(rf, muf, gd ? R_GROUND : R_TOP, txd, FLT_EPSILON);
  snprintf(label, sizeof label, "float h=%g mu=%g: t_exit", h, mu);
  check_dist(label, txf, txd, bx + 1e-30);
  /* Well conditioned (sqrt(D) >= sqrt(|c| + r^2 mu^2) / 4, so the
   * amplification above is <= 16) and longer than 1 km: a few float ulps,
   * <= 1e-6 relative. */
  if (txd > 1.0 && well_conditioned(rf, muf, gd ? R_GROUND : R_TOP)) {
    snprintf(label, sizeof label, "float h=%g mu=%g: t_exit 1e-6 rel", h, mu);
    check_dist(label, txf, txd, 1e-6 * txd);
  }
  if (ted > 1.0 && well_conditioned(rf, muf, R_TOP)) {
    snprintf(label, sizeof label, "float h=%g mu=%g: t_enter 1e-6 rel", h, mu);
    check_dist(label, tef, ted, 1e-6 * ted);
  }
}

static void test_inside_viewers(void) {
  printf("-- viewers inside: segment vs long-double quadratic, float vs double\n");
  const double hs[] = {0.01, 1.0, 10.0, 50.0, 99.9};
  const double mus[] = {-1.0, -0.7, -0.3, -0.1, -0.02, 0.0, 0.05, 0.3, 0.8, 1.0};
  for (size_t i = 0; i < sizeof hs / sizeof hs[0]; ++i)
    for (size_t j = 0; j < sizeof mus / sizeof mus[0]; ++j) check_segment(hs[i], mus[j]);
}

static void test_horizon(void) {
  printf("-- horizon cosine vs -sqrt(1 - (R/r)^2) in long double; tangency decides hits\n");
  const double hs[] = {1e-4, 0.01, 1.0, 10.0, 100.0, 200.0, 10000.0};
  char label[128];
  for (size_t i = 0; i < sizeof hs / sizeof hs[0]; ++i) {
    double r = R_GROUND + hs[i];
    ld x = (ld)R_GROUND / r;
    ld want = -sqrtl(1 - x * x);
    /* rounding of R/r (LDBL_EPSILON) is amplified by 1/(1 - x^2) in the
     * reference; the double result carries a few DBL_EPSILON. */
    double bound = 8 * DBL_EPSILON * fabs((double)want) +
                   4 * LDBL_EPSILON / (double)(1 - x * x) * fabs((double)want);
    double mu_h = sf_horizon_mu(r, R_GROUND);
    printf("   h=%g: horizon mu %.17g, discriminant (R-r)(R+r)+(r mu_h)^2 = %.3g\n", hs[i], mu_h,
           (R_GROUND - r) * (R_GROUND + r) + (r * mu_h) * (r * mu_h));
    snprintf(label, sizeof label, "horizon mu, h=%g", hs[i]);
    check_dist(label, mu_h, (double)want, bound);
    /* API consistency: a ray at mu = sf_horizon_mu(r, R) is the tangent
     * ray, and the header says tangent rays hit. A horizon rounded to
     * nearest can land on the missing side (by ~1 ulp); then this fails. */
    snprintf(label, sizeof label, "tangent ray hits, h=%g", hs[i]);
    check_int(label, sf_ray_hits_sphere_from_above(r, mu_h, R_GROUND), 1);
    snprintf(label, sizeof label, "mu_h - 1e-6 hits, h=%g", hs[i]);
    check_int(label, sf_ray_hits_sphere_from_above(r, mu_h - 1e-6, R_GROUND), 1);
    snprintf(label, sizeof label, "mu_h + 1e-6 misses, h=%g", hs[i]);
    check_int(label, sf_ray_hits_sphere_from_above(r, mu_h + 1e-6, R_GROUND), 0);

    float rf = (float)r;
    float mu_hf = sf_horizon_mu_f(rf, (float)R_GROUND);
    double want_f = sf_horizon_mu(rf, R_GROUND);
    snprintf(label, sizeof label, "float horizon mu, h=%g", hs[i]);
    check_dist(label, mu_hf, want_f, 8 * FLT_EPSILON * fabs(want_f) + 1e-30);
    if (hs[i] >= 1.0) { /* below 1 km the float horizon is within ~1e-6 of 0 */
      snprintf(label, sizeof label, "float tangent ray hits, h=%g", hs[i]);
      check_int(label, sf_ray_hits_sphere_from_above_f(rf, mu_hf, (float)R_GROUND), 1);
      snprintf(label, sizeof label, "float mu_h - 1e-6 hits, h=%g", hs[i]);
      check_int(label, sf_ray_hits_sphere_from_above_f(rf, mu_hf - 1e-6f, (float)R_GROUND), 1);
      snprintf(label, sizeof label, "float mu_h + 1e-6 misses, h=%g", hs[i]);
      check_int(label, sf_ray_hits_sphere_from_above_f(rf, mu_hf + 1e-6f, (float)R_GROUND), 0);
    }
  }
  /* No ray with binary r, R, mu != 0 is exactly tangent (mu^2 + (R/r)^2 = 1
   * would need a Pythagorean triple with a power-of-two hypotenuse), so the
   * contract tested is the header's: a computed discriminant of exactly 0
   * counts as hitting. r = 10, R = 8, mu = -0.6: 10 * fl(0.6) rounds to 6,
   * 36 - 36 = 0. */
  printf("   r=10 R=8 mu=-0.6: discriminant %.17g\n", 8.0 * 8.0 - 10.0 * 10.0 * (1 - 0.36));
  check_int("exact tangency r=10 R=8 mu=-0.6 hits", sf_ray_hits_sphere_from_above(10.0, -0.6, 8.0), 1);
  double tn, tf;
  check_int("exact tangency: line meets the sphere", sf_ray_sphere_intersections(10.0, -0.6, 8.0, &tn, &tf), 1);
  /* the tangent point is at t = -r mu = 6 */
  check_dist("exact tangency: t_near = 6", tn, 6.0, 4 * DBL_EPSILON * 6);
  check_dist("exact tangency: t_far = 6", tf, 6.0, 4 * DBL_EPSILON * 6);
  check_int("float exact tangency hits", sf_ray_hits_sphere_from_above_f(10.0f, -0.6f, 8.0f), 1);
  /* Near-tangent ground hits: ill-conditioned, bound grows as 1/sqrt(D). */
  for (size_t i = 2; i < 6; ++i) {
    double h = hs[i], r = R_GROUND + h, mu = sf_horizon_mu(r, R_GROUND) - 1e-6;
    double n, f;
    ld ln = 0, lf = 0;
    sf_ray_sphere_intersections(r, mu, R_GROUND, &n, &f);
    ld_roots(r, mu, R_GROUND, &ln, &lf);
    snprintf(label, sizeof label, "near-tangent ground t, h=%g mu_h-1e-6", h);
    check_dist(label, n, (double)ln, root_bound(r, mu, R_GROUND, (double)ln, DBL_EPSILON) +
                                         ld_reference_error(r, mu, R_GROUND));
    float rf = (float)r, muf = (float)mu, nf, ff;
    sf_ray_sphere_intersections(rf, muf, R_GROUND, &n, &f);
    int okf = sf_ray_sphere_intersections_f(rf, muf, (float)R_GROUND, &nf, &ff);
    snprintf(label, sizeof label, "float near-tangent: line meets, h=%g", h);
    check_int(label, okf, 1);
    snprintf(label, sizeof label, "float near-tangent ground t, h=%g", h);
    check_dist(label, nf, n, root_bound(rf, muf, R_GROUND, n, FLT_EPSILON));
  }
}

static void test_boundaries(void) {
  printf("-- viewers exactly on the ground / on the top\n");
  const double mus[] = {-1.0, -0.5, -1e-3, 1e-3, 0.5, 1.0};
  char label[128];
  for (size_t j = 0; j < sizeof mus / sizeof mus[0]; ++j) {
    double mu = mus[j], te, tx;
    int g;
    /* on the ground */
    int ok = sf_ray_atmosphere_segment(R_GROUND, mu, R_GROUND, R_TOP, &te, &tx, &g);
    snprintf(label, sizeof label, "on ground mu=%g: in atmosphere", mu);
    check_int(label, ok, 1);
    snprintf(label, sizeof label, "on ground mu=%g: hits ground", mu);
    check_int(label, g, mu < 0);
    ld ln = 0, lf = 0;
    ld_roots(R_GROUND, mu, R_TOP, &ln, &lf);
    snprintf(label, sizeof label, "on ground mu=%g: t_exit", mu);
    if (mu < 0) check_dist(label, tx, 0.0, 0.0);
    else check_dist(label, tx, (double)lf, root_bound(R_GROUND, mu, R_TOP, (double)lf, DBL_EPSILON) +
                                                ld_reference_error(R_GROUND, mu, R_TOP));
    float tef, txf;
    int gf;
    sf_ray_atmosphere_segment_f((float)R_GROUND, (float)mu, (float)R_GROUND, (float)R_TOP, &tef, &txf, &gf);
    snprintf(label, sizeof label, "float on ground mu=%g: t_exit", mu);
    if (mu < 0) check_dist(label, txf, 0.0, 0.0);
    else check_dist(label, txf, tx, root_bound(R_GROUND, (float)mu, R_TOP, tx, FLT_EPSILON));
    /* on the top */
    ok = sf_ray_atmosphere_segment(R_TOP, mu, R_GROUND, R_TOP, &te, &tx, &g);
    snprintf(label, sizeof label, "on top mu=%g: in atmosphere", mu);
    check_int(label, ok, 1);
    ld_segment(R_TOP, mu, &ln, &lf, &g);
    snprintf(label, sizeof label, "on top mu=%g: t_exit", mu);
    if (mu > 0) check_dist(label, tx, 0.0, 0.0);
    else check_dist(label, tx, (double)lf, root_bound(R_TOP, mu, g ? R_GROUND : R_TOP, (double)lf, DBL_EPSILON) +
                                                ld_reference_error(R_TOP, mu, g ? R_GROUND : R_TOP));
    sf_ray_atmosphere_segment_f((float)R_TOP, (float)mu, (float)R_GROUND, (float)R_TOP, &tef, &txf, &gf);
    if (mu > 0) {
      snprintf(label, sizeof label, "float on top mu=%g: t_exit", mu);
      check_dist(label, txf, 0.0, 0.0);
    }
  }
}

static void test_space_viewers(void) {
  printf("-- viewers outside the atmosphere\n");
  const double hs[] = {200.0, 10000.0};
  char label[160];
  for (int i = 0; i < 2; ++i) {
    double h = hs[i], r = R_GROUND + h;
    double mu_top = sf_horizon_mu(r, R_TOP), mu_ground = sf_horizon_mu(r, R_GROUND);
    printf("   h=%g: ground horizon mu %.17g, top horizon mu %.17g\n", h, mu_ground, mu_top);
    /* miss: looking up, and just above the top sphere's horizon */
    double te, tx;
    int g;
    snprintf(label, sizeof label, "h=%g mu=0.3 misses", h);
    check_int(label, sf_ray_atmosphere_segment(r, 0.3, R_GROUND, R_TOP, &te, &tx, &g), 0);
    snprintf(label, sizeof label, "h=%g mu=0 misses", h);
    check_int(label, sf_ray_atmosphere_segment(r, 0.0, R_GROUND, R_TOP, &te, &tx, &g), 0);
    snprintf(label, sizeof label, "h=%g mu=mu_top+1e-6 misses", h);
    check_int(label, sf_ray_atmosphere_segment(r, mu_top + 1e-6, R_GROUND, R_TOP, &te, &tx, &g), 0);
    float tef, txf;
    int gf;
    snprintf(label, sizeof label, "float h=%g mu=mu_top+1e-6 misses", h);
    check_int(label, sf_ray_atmosphere_segment_f((float)r, (float)(mu_top + 1e-6), (float)R_GROUND,
                                                 (float)R_TOP, &tef, &txf, &gf), 0);
    /* graze: tangent to the top sphere -> no path, or one of (near) zero
     * length: the computed discriminant there is only known to
     * ~3 eps (|c| + r^2 mu^2), so the chord 2 sqrt(D) is below
     * 2 sqrt(3 eps (|c| + r^2 mu^2)). */
    int ok = sf_ray_atmosphere_segment(r, mu_top, R_GROUND, R_TOP, &te, &tx, &g);
    double scale = fabs((r - R_TOP) * (r + R_TOP)) + r * r * mu_top * mu_top;
    double chord_bound = 2 * sqrt(3 * DBL_EPSILON * scale);
    printf("   h=%g grazing: entered %d, length %.17g (bound %.3g)\n", h, ok, ok ? tx - te : 0.0, chord_bound);
    snprintf(label, sizeof label, "h=%g grazing top: no path or ~0 length", h);
    check_report(!ok || (tx - te >= 0 && tx - te <= chord_bound && !g), label, __FILE__, __LINE__);
    ok = sf_ray_atmosphere_segment_f((float)r, (float)mu_top, (float)R_GROUND, (float)R_TOP, &tef, &txf, &gf);
    double chord_bound_f = 2 * sqrt(3 * FLT_EPSILON * scale) + 2 * r * sqrt(2 * FLT_EPSILON * fabs(mu_top));
    printf("   float h=%g grazing: entered %d, length %.9g (bound %.3g)\n", h, ok, ok ? txf - tef : 0.0,
           chord_bound_f);
    snprintf(label, sizeof label, "float h=%g grazing top: no path or short", h);
    check_report(!ok || (txf - tef >= 0 && txf - tef <= chord_bound_f && !gf), label, __FILE__, __LINE__);
    /* enter and hit the ground; enter and leave (between the two horizons) */
    check_segment(h, -0.999);
    check_segment(h, 0.5 * (mu_top + mu_ground));
    check_segment(h, mu_ground - 1e-3);
    check_segment(h, mu_top - 1e-3);
  }
}

/* Cancellation: the textbook small root -r mu - sqrt(r^2 mu^2 - (r^2 - R^2))
 * in float subtracts two numbers ~3180 km that agree to the first ~6 digits
 * when the viewer is a metre above the ground. The altitude is 2^-11 km
 * (0.49 m), the smallest above 6360 km that a float radius can hold:
 * 6360.0001 km rounds to 6360 in float, which would hide the effect. */
static void test_cancellation(void) {
  printf("-- cancellation: viewer at h = 2^-11 km, mu = -0.5, distance to the ground\n");
  const double hs[] = {0x1p-11, 0x1p-9, 0x1p-7};
  char label[128];
  for (int i = 0; i < 3; ++i) {
    float rf = (float)(R_GROUND + hs[i]), muf = -0.5f, Rf = (float)R_GROUND;
    ld ln = 0, lf = 1;
    ld_roots(rf, muf, R_GROUND, &ln, &lf);
    /* ln * lf = r^2 - R^2: the small root by Vieta from the large one, which has no cancellation */
    ld want = ((ld)rf - R_GROUND) * ((ld)rf + R_GROUND) / lf;
    volatile float rr = rf * rf, RR = Rf * Rf, b = rf * muf;
    volatile float naive = -b - sqrtf(b * b - (rr - RR));
    float tn, tf;
    sf_ray_sphere_intersections_f(rf, muf, Rf, &tn, &tf);
    double naive_err = fabs(naive - (double)want) / (double)want;
    double err = fabs(tn - (double)want) / (double)want;
    printf("   h=%.9g km: exact %.12Lg, naive float %.9g (rel.err %.3g), "
           "sf_ray_sphere_intersections_f %.9g (rel.err %.3g)\n",
           hs[i], want, (double)naive, naive_err, (double)tn, err);
    snprintf(label, sizeof label, "h=%g: cancellation-free float", hs[i]);
    check_dist(label, tn, (double)want, 1e-5 * (double)want);
    if (i == 0) {
      snprintf(label, sizeof label, "h=%g: naive float loses > 1e-2", hs[i]);
      check_report(naive_err > 1e-2, label, __FILE__, __LINE__);
    }
  }
}

/* Viewers far out (geostationary to 1e9 km): the discriminant R^2 - r^2 (1
 * - mu^2) in float against long double at the same float inputs. Its terms
 * carry a few float roundings of R^2 and of p^2 = r^2 (1 - mu^2), so
 * |dD| <= 8 eps (R^2 + p^2); (R - r)(R + r) + (r mu)^2 would lose eps r^2
 * (at 1e7 km, 2.5 R^2: a viewer looking straight down missed the planet).
 * mu from -1 up through rays that pass the planet; straight down, the
 * atmosphere is entered at r - R_top and the ground hit. */
static void test_far_viewers(void) {
  printf("-- viewers far out: the float discriminant\n");
  const double hs[] = {3.6e4, 1e5, 1e6, 1e7, 1e9};
  const double radii[] = {R_GROUND, R_TOP};
  char label[160];
  double worst = 0.0;
  int all_in = 1;
  for (int i = 0; i < 5; ++i) {
    float rf = (float)(R_GROUND + hs[i]);
    /* the planet's angular radius from there, and the cosines across it */
    double edge = sqrt(1.0 - (R_TOP / rf) * (R_TOP / rf));
    for (int k = 0; k <= 40; ++k) {
      float muf = k == 0 ? -1.0f : (float)-(edge + (1.0 - edge) * (1.0 - k / 30.0));
      if (!(muf >= -1.0f)) muf = -1.0f;
      for (int s = 0; s < 2; ++s) {
        double R = radii[s];
        ld p2 = (ld)rf * rf * (1.0L - (ld)muf * muf);
        ld want = (ld)R * R - p2;
        double got = sf_ray_sphere_discriminant_f(rf, muf, (float)R);
        double err = (double)(fabsl((ld)got - want) / ((ld)R * R + p2));
        if (err > worst) worst = err;
        all_in &= err <= 8 * FLT_EPSILON;
      }
    }
    float te, tx;
    int g;
    int in = sf_ray_atmosphere_segment_f(rf, -1.0f, (float)R_GROUND, (float)R_TOP, &te, &tx, &g);
    snprintf(label, sizeof label, "float h=%g straight down: enters at r - R_top and hits the ground", hs[i]);
    check_report(in && g && fabs(te - ((double)rf - R_TOP)) <= 4 * FLT_EPSILON * (double)rf &&
                     fabs(tx - ((double)rf - R_GROUND)) <= 4 * FLT_EPSILON * (double)rf,
                 label, __FILE__, __LINE__);
  }
  printf("   worst |D_f - D| / (R^2 + p^2) over 5 distances x 41 cosines x 2 spheres: %.3g (bound 8 eps = %.3g)\n",
         worst, 8 * FLT_EPSILON);
  check_report(all_in, "far viewers: float discriminant within 8 eps (R^2 + p^2)", __FILE__, __LINE__);
}

/* Altitude along the ray (sf_ray_altitude_at): (h (r + R) + t (t + 2 r mu))
 * / (r_t + R) is r_t - R without the cancellation, so its error is a few
 * eps of the altitude itself plus the rounding of t (t + 2 r mu), not of the
 * radius. The same identity in long double is the reference; in float the
 * radius of a 6360 km planet alone is 4.9e-4 km coarse. */
static void test_altitude_at(void) {
  printf("-- altitude along the ray, double and float, against long double\n");
  const double R = 6360.0;
  const double hs[] = {0.0, 0.005, 0.5, 10.0, 99.0};
  const double mus[] = {-0.3, -1e-4, 0.0, 1e-6, 0.2, 1.0};
  const double ts[] = {1e-4, 0.0037, 1.0, 50.0};
  double worst_d = 0.0, worst_f = 0.0;
  for (size_t i = 0; i < sizeof hs / sizeof hs[0]; ++i)
    for (size_t j = 0; j < sizeof mus / sizeof mus[0]; ++j)
      for (size_t k = 0; k < sizeof ts / sizeof ts[0]; ++k) {
        /* the float inputs exactly, so that both see the same ray */
        float hf = (float)hs[i], mf = (float)mus[j], tf = (float)ts[k];
        long double r = (long double)R + hf;
        /* r_t^2 - R^2 with r - R = h exact, over r_t + R: sqrtl(r2) - R
         * itself loses 3e-16 km to the radius, 4e-4 of a 7.9e-13 km rise */
        long double rise = (long double)hf * (r + (long double)R) + (long double)tf * ((long double)tf + 2.0L * r * mf);
        if (rise < 0.0L) continue;   /* below the ground: not an altitude */
        long double want = rise / (sqrtl(r * r + (long double)tf * ((long double)tf + 2.0L * r * mf)) + (long double)R);
        double scale = (double)want + 1e-3 * tf;   /* altitude plus the rounding of t's terms */
        worst_d = worst_of(worst_d, fabs(sf_ray_altitude_at(R, hf, mf, tf) - (double)want) / scale);
        worst_f = worst_of(worst_f, fabs((double)sf_ray_altitude_at_f((float)R, hf, mf, tf) - (double)want) / scale);
      }
  printf("   worst |error| / (altitude + 1e-3 t): double %.3g, float %.3g\n", worst_d, worst_f);
  CHECK(worst_d <= 16 * DBL_EPSILON);
  CHECK(worst_f <= 16 * FLT_EPSILON);
  /* the thin shell's case: 3.7 m along a level ray 5 m up (r_t - R in float: 0 or 4.9e-4 km) */
  float h_thin = sf_ray_altitude_at_f(6360.0f, 0.005f, 0.0f, 0.0037f);
  CHECK_REL(h_thin, 0.005 + 0.0037 * 0.0037 / (2.0 * 6360.005), 1e-6);
}

/* Viewers just above the top, rays grazing into it (SPEC §10): where the
 * ray enters, against long double at the same double inputs. The chord's
 * half length s = sqrt(top^2 - p^2) had been formed from the closest
 * approach p, whose top - p cancelled: a viewer 1e-12 km above the top
 * looking at mu -1e-7 had s (and its column) 7.5e-3 off. */
static void test_just_above_top(void) {
  printf("-- viewers just above the top, grazing rays: the entry point\n");
  const double above[] = {1e-12, 1e-9, 1e-6, 1e-3};
  const double cosines[] = {-1e-7, -1e-6, -2e-5, -1e-3, -0.3};
  double worst = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 5; ++k) {
      double r = R_TOP + above[i], mu = cosines[k];
      ld disc = ((ld)R_TOP - r) * ((ld)R_TOP + r) + ((ld)r * mu) * ((ld)r * mu);
      if (disc <= 0) continue;   /* misses */
      ld s = sqrtl(disc), t_want = ((ld)r - R_TOP) * ((ld)r + R_TOP) / (s - (ld)r * mu);
      double t, mu_e;
      if (!sf_ray_enter_from_above(r, mu, 0.5, 0.0, R_TOP, &t, &mu_e, NULL)) {
        check_report(0, "a grazing ray that enters is entered", __FILE__, __LINE__);
        continue;
      }
      double err_t = (double)(fabsl(t - t_want) / t_want), err_mu = (double)(fabsl(mu_e + s / R_TOP) / (s / R_TOP));
      if (err_t > worst) worst = err_t;
      if (err_mu > worst) worst = err_mu;
    }
  printf("   worst relative error of t_enter and mu_e over 4 heights x 5 cosines: %.3g (bound 1e-12)\n", worst);
  check_report(worst <= 1e-12, "just above the top: entry within 1e-12 of long double", __FILE__, __LINE__);
}

int main(void) {
  test_just_above_top();
  test_altitude_at();
  test_inside_viewers();
  test_horizon();
  test_boundaries();
  test_space_viewers();
  test_far_viewers();
  test_cancellation();
  return check_summary();
}
