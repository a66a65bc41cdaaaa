#include "data/ray_quadrature.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/ray_geometry.h"
#include "models/ray_pieces.h"

/* Steepest decay (kappa_down) and growth (kappa_up) rates, 1/km, of the
 * exponential terms of all densities; 0 where there is none. */
static void grading_rates(const sf_atmosphere *atm, double *kappa_down, double *kappa_up) {
  *kappa_down = *kappa_up = 0.0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    for (int l = 0; l < c->n_layers; ++l) {
      double s = c->layers[l].exp_scale_per_km;
      if (c->layers[l].exp_term == 0.0) continue;
      if (-s > *kappa_down) *kappa_down = -s;
      if (s > *kappa_up) *kappa_up = s;
    }
  }
}

/* Distance along the ray at which it has radius rho, on the rising (sign
 * +1) or falling (-1) side of its closest approach. rho^2 - d^2 is written
 * as (rho - r)(rho + r) + r^2 mu^2 to keep it accurate near the viewer. */
static double distance_at_radius(double r, double mu, double rho, double sign) {
  double s2 = (rho - r) * (rho + r) + r * r * mu * mu;
  return sign * sqrt(s2 > 0.0 ? s2 : 0.0) - r * mu;
}

static int insert_sorted(double *b, int n, int max, double t) {
  if (n >= max || !(t > b[0] && t < b[n - 1])) return n;
  int i = n - 1;
  while (b[i - 1] > t) --i;
  if (b[i - 1] == t) return n;
  memmove(b + i + 1, b + i, sizeof(double) * (size_t)(n - i));
  b[i] = t;
  return n + 1;
}

int sf_ray_quad_breaks(const sf_atmosphere *atm, double r, double mu, double t0, double t1,
                       const double *extra, int n_extra, double *breaks, int max_breaks) {
  double base[SF_MAX_RAY_BREAKS];
  int n_base = sf_ray_breakpoints(atm, r, mu, t0, t1, base);
  for (int e = 0; e < n_extra; ++e) n_base = sf_ray_breaks_insert(base, n_base, extra[e]);
  double kappa_down, kappa_up;
  grading_rates(atm, &kappa_down, &kappa_up);
  double bottom = atm->bottom_radius_km, top = atm->top_radius_km;
  /* The radius is monotone on every piece, so its extremes over the
   * segment are at piece ends. */
  double r_min = top, r_max = bottom;
  double radius[SF_MAX_RAY_BREAKS];
  for (int p = 0; p < n_base; ++p) {
    radius[p] = fmin(fmax(sf_ray_radius_at(r, mu, base[p]), bottom), top);
    r_min = fmin(r_min, radius[p]);
    r_max = fmax(r_max, radius[p]);
  }
  int n = 0;
  breaks[n++] = base[0];
  for (int p = 0; p + 1 < n_base && n < max_breaks; ++p) {
    double a = base[p], b = base[p + 1];
    /* rising after the closest approach (t > -r mu), falling before it */
    double sign = 0.5 * (a + b) + r * mu >= 0.0 ? 1.0 : -1.0;
    double lo = fmin(radius[p], radius[p + 1]), hi = fmax(radius[p], radius[p + 1]);
    /* Cut radii, ascending. A sub-piece starting a height z above the
     * lowest point of the segment may span K/kappa + z: the geometric
     * grading K/kappa (1, 2, 4, ...) of the header, continued across
     * pieces. Growing densities are graded down from the highest point. */
    double cut[2 * 64];
    int n_cut = 0;
    /* (The last sub-piece may stretch to 1.5 spans rather than leave a
     * sliver before the piece's end.) */
    if (kappa_down > 0.0)
      for (double z = lo; n_cut < 64;) {
        double span = SF_RAY_QUAD_GRADING / kappa_down + (z - r_min);
        if (z + 1.5 * span >= hi) break;
        z += span;
        cut[n_cut++] = z;
      }
    if (kappa_up > 0.0)
      for (double z = hi; n_cut < 128;) {
        double span = SF_RAY_QUAD_GRADING / kappa_up + (r_max - z);
        if (z - 1.5 * span <= lo) break;
        z -= span;
        cut[n_cut++] = z;
      }
    int first = n - 1;
    breaks[n++] = b;
    for (int k = 0; k < n_cut && n < max_breaks; ++k)
      n = first + insert_sorted(breaks + first, n - first, max_breaks - first,
                                distance_at_radius(r, mu, cut[k], sign));
  }
  /* Out of room (pathological profiles): the last sub-piece runs to t1. */
  if (breaks[n - 1] != base[n_base - 1]) {
    if (n < 2) breaks[n++] = base[n_base - 1];
    else breaks[n - 1] = base[n_base - 1];
  }
  return n;
}

/* Scattering integrands also carry exp(-optical depth from the viewer),
 * which in an optically thick atmosphere varies far faster than any
 * density. This pass cuts the sub-pieces again so that, estimated from the
 * extinction at their ends, a sub-piece starting at optical depth tau from
 * t0 is at most K + tau thick: the same geometric grading as above, in
 * optical depth (the weight exp(-tau) of the later sub-pieces pays for their
 * coarser rule). */
static double extinction_bound(const sf_atmosphere *atm, const double *beta_max, double r, double mu, double t) {
  double h = sf_ray_radius_at(r, mu, t) - atm->bottom_radius_km;
  double k = 0.0;
  for (int i = 0; i < atm->n_constituents; ++i) k += beta_max[i] * sf_constituent_density(&atm->constituents[i], h);
  return k;
}

static int grade_extinction(const sf_atmosphere *atm, double r, double mu, double *breaks, int n, int max_breaks) {
  double beta_max[SF_MAX_CONSTITUENTS];
  for (int i = 0; i < atm->n_constituents; ++i) {
    beta_max[i] = 0.0;
    for (int ch = 0; ch < atm->n_channels; ++ch) beta_max[i] = fmax(beta_max[i], sf_extinction(atm, i, ch));
  }
  double in[SF_RAY_QUAD_MAX_BREAKS];
  memcpy(in, breaks, sizeof(double) * (size_t)n);
  int m = 0;
  breaks[m++] = in[0];
  double tau = 0.0, k_a = extinction_bound(atm, beta_max, r, mu, in[0]);
  for (int p = 0; p + 1 < n; ++p) {
    double a = in[p], b = in[p + 1];
    double k_b = extinction_bound(atm, beta_max, r, mu, b);
    double thick = 0.5 * (k_a + k_b) * (b - a);   /* trapezoid estimate */
    double allowed = SF_RAY_QUAD_OPTICAL_GRADING + SF_RAY_QUAD_OPTICAL_GROWTH * tau;
    /* at most 64, capped before the conversion: an optical depth of 1e12
     * (a coefficient of 1e12 per km) overflowed int (UBSan) */
    int parts = thick > allowed ? (int)fmin(ceil(thick / allowed), 64.0) : 1;
    if (m + parts > max_breaks) parts = max_breaks - m > 1 ? max_breaks - m : 1;
    for (int j = 1; j < parts; ++j) breaks[m++] = a + (b - a) * j / parts;
    if (m < max_breaks) breaks[m++] = b;
    else breaks[m - 1] = b;
    tau += thick;
    k_a = k_b;
  }
  return m;
}

/* Evaluates the densities at the rule's nodes on [a, b] and adds the
 * piece's integral to depth; optionally records the nodes. */
static void integrate_piece(const sf_atmosphere *atm, const sf_gauss_rule *rule, double r,
                            double mu, double a, double b, double *depth, sf_ray_nodes *nodes) {
  int nc = atm->n_constituents, k = rule->n;
  double len = b - a;
  double dens[SF_GAUSS_MAX_NODES][SF_MAX_CONSTITUENTS];
  double radius[SF_GAUSS_MAX_NODES];
  for (int q = 0; q < k; ++q) {
    double t = a + len * rule->x[q];
    radius[q] = sf_ray_radius_at(r, mu, t);
    double h = radius[q] - atm->bottom_radius_km;
    for (int i = 0; i < nc; ++i) dens[q][i] = sf_constituent_density(&atm->constituents[i], h);
  }
  if (nodes) {
    int piece = nodes->n_pieces++;
    nodes->piece_start[piece] = a;
    nodes->piece_end[piece] = b;
    for (int i = 0; i < nc; ++i) {
      nodes->piece_depth[piece * nc + i] = depth[i];
      double *coef = nodes->piece_coef + ((size_t)piece * nc + i) * k;
      for (int m = 0; m < k; ++m) {
        double c = 0.0;
        for (int j = 0; j < k; ++j) c += rule->to_legendre[m][j] * dens[j][i];
        coef[m] = c;
      }
    }
    for (int q = 0; q < k; ++q) {
      int m = nodes->n + q;
      nodes->t[m] = a + len * rule->x[q];
      nodes->weight[m] = len * rule->w[q];
      nodes->radius[m] = radius[q];
      for (int i = 0; i < nc; ++i) {
        double part = 0.0;
        for (int j = 0; j < k; ++j) part += rule->partial[q][j] * dens[j][i];
        nodes->density[m * nc + i] = dens[q][i];
        nodes->depth[m * nc + i] = depth[i] + len * part;
      }
    }
    nodes->n += k;
  }
  for (int i = 0; i < nc; ++i) {
    double s = 0.0;
    for (int q = 0; q < k; ++q) s += rule->w[q] * dens[q][i];
    depth[i] += len * s;
  }
}

/* [t0, t1] restricted to the inside of the top sphere. */
static int clip_to_top(const sf_atmosphere *atm, double r, double mu, double *t0, double *t1) {
  double t_near, t_far;
  if (!sf_ray_sphere_intersections(r, mu, atm->top_radius_km, &t_near, &t_far)) return 0;
  if (t_near > *t0) *t0 = t_near;
  if (t_far < *t1) *t1 = t_far;
  return *t1 > *t0;
}

void sf_ray_quad_optical_depth(const sf_atmosphere *atm, const sf_gauss_rule *rule, double r,
                               double mu, double t0, double t1, double *out) {
  for (int i = 0; i < atm->n_constituents; ++i) out[i] = 0.0;
  if (!(t1 > t0) || !clip_to_top(atm, r, mu, &t0, &t1)) return;
  double breaks[SF_RAY_QUAD_MAX_BREAKS];
  int n = sf_ray_quad_breaks(atm, r, mu, t0, t1, NULL, 0, breaks, SF_RAY_QUAD_MAX_BREAKS);
  for (int p = 0; p + 1 < n; ++p) integrate_piece(atm, rule, r, mu, breaks[p], breaks[p + 1], out, NULL);
}

int sf_ray_nodes_alloc(sf_ray_nodes *nodes, const sf_gauss_rule *rule, int n_constituents) {
  memset(nodes, 0, sizeof *nodes);
  size_t pieces = SF_RAY_QUAD_MAX_BREAKS;
  size_t cap = pieces * (size_t)rule->n;
  size_t nc = (size_t)(n_constituents > 0 ? n_constituents : 1);
  nodes->t = malloc(sizeof(double) * (cap * (3 + 2 * nc) + pieces * (2 + nc + nc * (size_t)rule->n)));
  if (!nodes->t) return -1;
  nodes->weight = nodes->t + cap;
  nodes->radius = nodes->weight + cap;
  nodes->density = nodes->radius + cap;
  nodes->depth = nodes->density + cap * nc;
  nodes->piece_start = nodes->depth + cap * nc;
  nodes->piece_end = nodes->piece_start + pieces;
  nodes->piece_depth = nodes->piece_end + pieces;
  nodes->piece_coef = nodes->piece_depth + pieces * nc;
  nodes->capacity = (int)cap;
  nodes->n_constituents = n_constituents;
  return 0;
}

void sf_ray_nodes_free(sf_ray_nodes *nodes) {
  free(nodes->t);
  memset(nodes, 0, sizeof *nodes);
}

void sf_ray_nodes_fill(sf_ray_nodes *nodes, const sf_atmosphere *atm, const sf_gauss_rule *rule,
                       double r, double mu, double t0, double t1, const double *extra, int n_extra) {
  nodes->n = 0;
  nodes->n_pieces = 0;
  for (int i = 0; i < atm->n_constituents; ++i) nodes->total_depth[i] = 0.0;
  if (!(t1 > t0) || !clip_to_top(atm, r, mu, &t0, &t1)) return;
  double breaks[SF_RAY_QUAD_MAX_BREAKS];
  int n = sf_ray_quad_breaks(atm, r, mu, t0, t1, extra, n_extra, breaks, SF_RAY_QUAD_MAX_BREAKS);
  n = grade_extinction(atm, r, mu, breaks, n, SF_RAY_QUAD_MAX_BREAKS);
  for (int p = 0; p + 1 < n; ++p)
    integrate_piece(atm, rule, r, mu, breaks[p], breaks[p + 1], nodes->total_depth, nodes);
}

void sf_ray_nodes_depth_at(const sf_ray_nodes *nodes, const sf_gauss_rule *rule, int piece, double t,
                           double *depth) {
  int nc = nodes->n_constituents, k = rule->n;
  double a = nodes->piece_start[piece], len = nodes->piece_end[piece] - a;
  double x = len > 0.0 ? (t - a) / len : 0.0;
  /* Integrals over [-1, y] of P_0..P_{k-1} (see sf_gauss_legendre_integral),
   * shared by every constituent. */
  double y = 2.0 * x - 1.0, basis[SF_GAUSS_MAX_NODES];
  double p_prev = 1.0, p = y;
  basis[0] = y + 1.0;
  for (int m = 1; m < k; ++m) {
    double p_next = rule->rec_a[m] * y * p - rule->rec_b[m] * p_prev;
    basis[m] = (p_next - p_prev) * rule->rec_c[m];
    p_prev = p;
    p = p_next;
  }
  for (int i = 0; i < nc; ++i) {
    const double *coef = nodes->piece_coef + ((size_t)piece * nc + i) * k;
    double s = 0.0;
    for (int m = 0; m < k; ++m) s += coef[m] * basis[m];
    depth[i] = nodes->piece_depth[piece * nc + i] + 0.5 * len * s;
  }
}
