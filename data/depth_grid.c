#include "data/depth_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "data/gauss_rule.h"
#include "data/parallel_rows.h"
#include "data/ray_quadrature.h"
#include "data/table_params.h"
#include "models/ray_geometry.h"

typedef struct grid_job {
  sf_depth_grid *grid;
  const sf_atmosphere *atm;
  sf_gauss_rule rule;
} grid_job;

static void grid_row(void *ctx, int thread, long row) {
  (void)thread;
  grid_job *job = ctx;
  sf_depth_grid *g = job->grid;
  double R = g->bottom_radius_km, Rt = g->top_radius_km;
  double h = sf_bruneton_h_from_x(R, Rt, (double)row / (g->n_h - 1));
  double r = R + h;
  for (int i = 0; i < g->n_mu; ++i) {
    double mu = sf_bruneton_mu_top_from_x(R, Rt, h, (double)i / (g->n_mu - 1));
    double t_near, t_far = 0.0;
    sf_ray_sphere_intersections(r, mu, Rt, &t_near, &t_far);
    sf_ray_quad_optical_depth(job->atm, &job->rule, r, mu, 0.0, t_far > 0.0 ? t_far : 0.0,
                              g->depth + ((size_t)row * g->n_mu + i) * g->n_constituents);
  }
}

int sf_depth_grid_build(sf_depth_grid *grid, const sf_atmosphere *atm, int n_mu, int n_h,
                        const sf_precompute_options *opt, sf_error *err) {
  memset(grid, 0, sizeof *grid);
  size_t n = (size_t)n_mu * (size_t)n_h * (size_t)(atm->n_constituents ? atm->n_constituents : 1);
  grid->depth = malloc(sizeof(double) * n);
  if (!grid->depth) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the optical depth grid");
  grid->bottom_radius_km = atm->bottom_radius_km;
  grid->top_radius_km = atm->top_radius_km;
  grid->horizon_km = sqrt((atm->top_radius_km - atm->bottom_radius_km) *
                          (atm->top_radius_km + atm->bottom_radius_km));
  grid->n_mu = n_mu;
  grid->n_h = n_h;
  grid->n_constituents = atm->n_constituents;
  grid_job job = {grid, atm, {0}};
  sf_gauss_rule_init(&job.rule, 10);
  sf_parallel_rows(n_h, opt, "optical depth grid", grid_row, &job);
  return SF_OK;
}

void sf_depth_grid_free(sf_depth_grid *grid) {
  free(grid->depth);
  memset(grid, 0, sizeof *grid);
}

/* Cubic Lagrange weights on the 4 samples i-1..i+2 around pos; the stencil
 * is shifted inwards at the ends so that it never leaves the grid. */
static inline int cubic_stencil(double pos, int n, double w[4]) {
  if (pos < 0.0) pos = 0.0;
  if (pos > n - 1) pos = n - 1;
  int i = (int)pos;
  if (i < 1) i = 1;
  if (i > n - 3) i = n - 3;
  double f = pos - i;
  double fm = f - 1.0, fp = f + 1.0, f2 = f - 2.0;
  w[0] = -f * fm * f2 * (1.0 / 6.0);
  w[1] = fp * fm * f2 * 0.5;
  w[2] = -fp * f * f2 * 0.5;
  w[3] = fp * f * fm * (1.0 / 6.0);
  return i - 1;
}

void sf_depth_grid_at_radius(const sf_depth_grid *g, double r, sf_depth_grid_radius *at) {
  double R = g->bottom_radius_km, Rt = g->top_radius_km, H = g->horizon_km;
  if (r < R) r = R;
  if (r > Rt) r = Rt;
  double h = r - R;
  double rho = sqrt(h * (2.0 * R + h));
  at->r = r;
  at->r2 = r * r;
  at->inside = (Rt - r) * (Rt + r);
  at->d_min = Rt - r;
  double span = rho + H - at->d_min;
  at->inv_span = span > 0.0 ? 1.0 / span : 0.0;
  at->i_h = cubic_stencil(rho / H * (g->n_h - 1), g->n_h, at->w_h);
}

void sf_depth_grid_lookup_at(const sf_depth_grid *g, const sf_depth_grid_radius *at, double mu,
                             double *depth) {
  /* Bruneton's transmittance mapping (data/table_params.h), inlined: this
   * runs at every node of every scattering integral. */
  double root = sqrt(at->inside + at->r2 * mu * mu);
  double d = mu > 0.0 ? at->inside / (at->r * mu + root) : root - at->r * mu;
  double x_mu = (d - at->d_min) * at->inv_span;
  if (x_mu > 1.0) x_mu = 1.0;   /* below the horizon: the horizon */
  double wm[4];
  int im = cubic_stencil(x_mu * (g->n_mu - 1), g->n_mu, wm);
  int nc = g->n_constituents;
  const double *base = g->depth + ((size_t)at->i_h * g->n_mu + im) * nc;
  size_t row_stride = (size_t)g->n_mu * nc;
  if (nc == 3) {
    /* the common case (air, aerosols, ozone), written out so that the
     * compiler keeps the three sums in registers */
    double a0 = 0.0, a1 = 0.0, a2 = 0.0;
    const double *p = base;
    for (int a = 0; a < 4; ++a, p += row_stride) {
      double w0 = at->w_h[a] * wm[0], w1 = at->w_h[a] * wm[1], w2 = at->w_h[a] * wm[2], w3 = at->w_h[a] * wm[3];
      a0 += w0 * p[0] + w1 * p[3] + w2 * p[6] + w3 * p[9];
      a1 += w0 * p[1] + w1 * p[4] + w2 * p[7] + w3 * p[10];
      a2 += w0 * p[2] + w1 * p[5] + w2 * p[8] + w3 * p[11];
    }
    depth[0] = a0 > 0.0 ? a0 : 0.0;
    depth[1] = a1 > 0.0 ? a1 : 0.0;
    depth[2] = a2 > 0.0 ? a2 : 0.0;
    return;
  }
  for (int c = 0; c < nc; ++c) {
    const double *p = base + c;
    double acc = 0.0;
    for (int a = 0; a < 4; ++a, p += row_stride)
      acc += at->w_h[a] * (wm[0] * p[0] + wm[1] * p[nc] + wm[2] * p[2 * nc] + wm[3] * p[3 * nc]);
    depth[c] = acc > 0.0 ? acc : 0.0;
  }
}

void sf_depth_grid_lookup(const sf_depth_grid *g, double r, double mu, double *depth) {
  sf_depth_grid_radius at;
  sf_depth_grid_at_radius(g, r, &at);
  sf_depth_grid_lookup_at(g, &at, mu, depth);
}
