#include "models/quadrature.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* QUADPACK qk21 abscissae (positive half, xgk[10] = 0) and weights. */
static const double xgk[11] = {
    0.995657163025808080735527280689003, 0.973906528517171720077964012084452,
    0.930157491355708226001207180059508, 0.865063366688984510732096688423493,
    0.780817726586416897063717578345042, 0.679409568299024406234327365114874,
    0.562757134668604683339000099272694, 0.433395394129247190799265943165784,
    0.294392862701460198131126603103866, 0.148874338981631210884826001129720,
    0.000000000000000000000000000000000};
static const double wgk[11] = {
    0.011694638867371874278064396062192, 0.032558162307964727478818972459390,
    0.054755896574351996031381300244580, 0.075039674810919952767043140916190,
    0.093125454583697605535065465083366, 0.109387158802297641899210590325805,
    0.123491976262065851077208980097160, 0.134709217311473325928054001771707,
    0.142775938577060080797094273138717, 0.147739104901338491374841515972068,
    0.149445554002916905664936468389821};
/* Gauss 10-point weights for the nodes xgk[1], xgk[3], ..., xgk[9]. */
static const double wg[5] = {
    0.066671344308688137593568809893332, 0.149451349150580593145776339657697,
    0.219086362515982043995534934228163, 0.269266719309996355091226921569469,
    0.295524224714752870173892994651338};

const double sf_kronrod21_nodes[21] = {
    -0.995657163025808080735527280689003, -0.973906528517171720077964012084452,
    -0.930157491355708226001207180059508, -0.865063366688984510732096688423493,
    -0.780817726586416897063717578345042, -0.679409568299024406234327365114874,
    -0.562757134668604683339000099272694, -0.433395394129247190799265943165784,
    -0.294392862701460198131126603103866, -0.148874338981631210884826001129720,
    0.0,
    0.148874338981631210884826001129720, 0.294392862701460198131126603103866,
    0.433395394129247190799265943165784, 0.562757134668604683339000099272694,
    0.679409568299024406234327365114874, 0.780817726586416897063717578345042,
    0.865063366688984510732096688423493, 0.930157491355708226001207180059508,
    0.973906528517171720077964012084452, 0.995657163025808080735527280689003};

/* One K21 panel: result and QUADPACK's error estimate per component. */
static void kronrod21(sf_integrand f, void *ctx, double a, double b, int n,
                      double *result, double *error) {
  double centre = 0.5 * (a + b), half = 0.5 * (b - a);
  double fc[SF_QUAD_MAX_COMPONENTS];
  double gauss[SF_QUAD_MAX_COMPONENTS], kron[SF_QUAD_MAX_COMPONENTS];
  double absk[SF_QUAD_MAX_COMPONENTS];
  double fv1[10][SF_QUAD_MAX_COMPONENTS], fv2[10][SF_QUAD_MAX_COMPONENTS];

  f(ctx, centre, fc);
  for (int i = 0; i < n; ++i) {
    gauss[i] = 0.0;
    kron[i] = wgk[10] * fc[i];
    absk[i] = fabs(kron[i]);
  }
  for (int j = 0; j < 10; ++j) {
    double dx = half * xgk[j];
    double *f1 = fv1[j], *f2 = fv2[j];
    f(ctx, centre - dx, f1);
    f(ctx, centre + dx, f2);
    for (int i = 0; i < n; ++i) {
      kron[i] += wgk[j] * (f1[i] + f2[i]);
      absk[i] += wgk[j] * (fabs(f1[i]) + fabs(f2[i]));
      if (j & 1) gauss[i] += wg[j / 2] * (f1[i] + f2[i]);
    }
  }
  for (int i = 0; i < n; ++i) {
    double mean = 0.5 * kron[i];
    double asc = wgk[10] * fabs(fc[i] - mean);
    for (int j = 0; j < 10; ++j)
      asc += wgk[j] * (fabs(fv1[j][i] - mean) + fabs(fv2[j][i] - mean));
    asc *= fabs(half);
    double res = kron[i] * half, err = fabs((kron[i] - gauss[i]) * half);
    /* QUADPACK's scaling: |K - G| overstates K21's error on smooth
     * integrands by orders of magnitude. */
    if (asc != 0.0 && err != 0.0) {
      double x = 200.0 * err / asc, scale = x * sqrt(x);   /* x^1.5 */
      err = scale < 1.0 ? asc * scale : asc;
    }
    double roundoff = 50.0 * DBL_EPSILON * absk[i] * fabs(half);
    if (err < roundoff) err = roundoff;
    result[i] = res;
    error[i] = err;
  }
}

typedef struct panel {
  double a, b;
} panel;

/* Panel storage: starts in a small stack buffer (most optical-depth
 * integrals need a handful of panels) and moves to the heap if it grows. */
typedef struct workspace {
  panel *panels;
  double *res, *err;
  int capacity, on_heap;
} workspace;

static int workspace_grow(workspace *w, int n) {
  int cap = w->capacity * 2;
  if (cap > SF_QUAD_MAX_PANELS) cap = SF_QUAD_MAX_PANELS;
  if (cap <= w->capacity) return 0;
  panel *p = malloc(sizeof(panel) * (size_t)cap);
  double *r = malloc(sizeof(double) * (size_t)n * (size_t)cap);
  double *e = malloc(sizeof(double) * (size_t)n * (size_t)cap);
  if (!p || !r || !e) {
    free(p), free(r), free(e);
    return 0;
  }
  memcpy(p, w->panels, sizeof(panel) * (size_t)w->capacity);
  memcpy(r, w->res, sizeof(double) * (size_t)n * (size_t)w->capacity);
  memcpy(e, w->err, sizeof(double) * (size_t)n * (size_t)w->capacity);
  if (w->on_heap) free(w->panels), free(w->res), free(w->err);
  w->panels = p, w->res = r, w->err = e;
  w->capacity = cap;
  w->on_heap = 1;
  return 1;
}

enum { STACK_PANELS = 32, STACK_VALUES = 32 * 16 };

sf_quad_result sf_integrate_adaptive(sf_integrand f, void *ctx, double a, double b,
                                     int n, double rel_tol, const double *abs_tol,
                                     double *sum) {
  sf_quad_result info = {0, 0, 1};
  if (n <= 0 || n > SF_QUAD_MAX_COMPONENTS || !(b > a)) return info;

  panel stack_panels[STACK_PANELS];
  double stack_res[STACK_VALUES], stack_err[STACK_VALUES];
  workspace w = {stack_panels, stack_res, stack_err, STACK_VALUES / n, 0};
  if (w.capacity > STACK_PANELS) w.capacity = STACK_PANELS;
  if (w.capacity < 1) {
    w.capacity = 1;
    w.panels = malloc(sizeof(panel));
    w.res = malloc(sizeof(double) * (size_t)n);
    w.err = malloc(sizeof(double) * (size_t)n);
    w.on_heap = 1;
    if (!w.panels || !w.res || !w.err) {
      free(w.panels), free(w.res), free(w.err);
      info.converged = 0;
      return info;
    }
  }
  double total[SF_QUAD_MAX_COMPONENTS], total_err[SF_QUAD_MAX_COMPONENTS];
  double tol[SF_QUAD_MAX_COMPONENTS];
  int count = 1;
  w.panels[0].a = a;
  w.panels[0].b = b;
  kronrod21(f, ctx, a, b, n, w.res, w.err);
  info.evaluations = 21;

  for (;;) {
    for (int i = 0; i < n; ++i) total[i] = total_err[i] = 0.0;
    for (int p = 0; p < count; ++p)
      for (int i = 0; i < n; ++i) {
        total[i] += w.res[p * n + i];
        total_err[i] += w.err[p * n + i];
      }
    int done = 1;
    for (int i = 0; i < n; ++i) {
      double t = rel_tol * fabs(total[i]);
      double floor_tol = abs_tol ? abs_tol[i] : 0.0;
      tol[i] = t > floor_tol ? t : floor_tol;
      if (total_err[i] > tol[i]) done = 0;
    }
    if (done) break;
    /* Bisect the panel whose error, against each component's tolerance, is
     * the worst. */
    int worst = 0;
    double worst_ratio = -1.0;
    for (int p = 0; p < count; ++p) {
      for (int i = 0; i < n; ++i) {
        double e = w.err[p * n + i];
        double ratio = tol[i] > 0.0 ? e / tol[i] : (e > 0.0 ? INFINITY : 0.0);
        if (ratio > worst_ratio) {
          worst_ratio = ratio;
          worst = p;
        }
      }
    }
    double pa = w.panels[worst].a, pb = w.panels[worst].b, mid = 0.5 * (pa + pb);
    if (!(mid > pa && mid < pb) || (count >= w.capacity && !workspace_grow(&w, n))) {
      info.converged = 0;
      break;
    }
    /* The worst panel becomes its left half; the right half is appended. */
    w.panels[worst].b = mid;
    w.panels[count].a = mid;
    w.panels[count].b = pb;
    kronrod21(f, ctx, pa, mid, n, w.res + worst * n, w.err + worst * n);
    kronrod21(f, ctx, mid, pb, n, w.res + count * n, w.err + count * n);
    info.evaluations += 42;
    ++count;
  }
  for (int i = 0; i < n; ++i) sum[i] += total[i];
  info.panels = count;
  if (w.on_heap) free(w.panels), free(w.res), free(w.err);
  return info;
}
