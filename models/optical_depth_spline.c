#include "models/optical_depth_spline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/air_segment.h"
#include "models/optical_depth_flat.h"
#include "models/ray_geometry.h"

/* ---- cubic Hermite basis on [0, 1] ---------------------------------------- */

typedef struct hermite_weights {
  double h00, h10, h01, h11;   /* value at 0, slope at 0, value at 1, slope at 1 */
} hermite_weights;

static hermite_weights hermite_at(double u) {
  double u2 = u * u, u3 = u2 * u;
  hermite_weights w = {2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u,
                       -2.0 * u3 + 3.0 * u2, u3 - u2};
  return w;
}

/* ---- exact node data --------------------------------------------------------- */

/* Region I: f = exp(-(rho - r)/H), rho = sqrt(d^2 + t^2); rho - r as
 * ((d - r)(d + r) + t^2) / (rho + r) against cancellation. */
static void miss_node(double r, double H, double t, double d, double out[4]) {
  double rho = sqrt(d * d + t * t);
  double f = exp(-(((d - r) * (d + r) + t * t) / (rho + r)) / H);
  out[0] = f;
  out[1] = -f * t / (H * rho);
  out[2] = -f * d / (H * rho);
  out[3] = f * t * d / (H * rho * rho) * (1.0 / H + 1.0 / rho);
}

/* Region II, the smooth factor s = exp(-h/H) u / sqrt(w), u = h + r,
 * w = u + d, of the paper's integrand s / sqrt(u - d). */
static void hit_node(double r, double H, double h, double d, double out[4]) {
  double e = exp(-h / H), u = h + r, w = u + d;
  double inv_sqrt_w = 1.0 / sqrt(w);
  double slope_factor = 1.0 - u / H - u / (2.0 * w);
  out[0] = e * u * inv_sqrt_w;
  out[1] = e * inv_sqrt_w * slope_factor;
  out[2] = -0.5 * e * u * inv_sqrt_w / w;
  out[3] = -0.5 * e * inv_sqrt_w / w * (1.0 - u / H - 1.5 * u / w);
}

typedef void (*node_function)(double r, double H, double x, double d, double out[4]);

static void grid_fill(sf_spline_grid *g, node_function node, double r, double H) {
  for (int j = 0; j < g->n_d; ++j) {
    double d = g->d_first + g->d_step * j;
    for (int i = 0; i < g->n_x; ++i) {
      double v[4];
      node(r, H, g->x_step * i, d, v);
      int k = j * g->n_x + i;
      g->value[k] = v[0];
      g->d_dx[k] = v[1];
      g->d_dd[k] = v[2];
      g->d_dxdd[k] = v[3];
    }
  }
}

static double *grid_attach(sf_spline_grid *g, double *next, int n_x, int n_d,
                           double x_step, double d_first, double d_step) {
  size_t n = (size_t)n_x * (size_t)n_d;
  g->n_x = n_x;
  g->n_d = n_d;
  g->x_step = x_step;
  g->d_first = d_first;
  g->d_step = d_step;
  g->value = next;
  g->d_dx = next + n;
  g->d_dd = next + 2 * n;
  g->d_dxdd = next + 3 * n;
  return next + 4 * n;
}

int sf_spline_model_make(const sf_atmosphere *atm, int height_points, int distance_points,
                         sf_spline_model *model) {
  memset(model, 0, sizeof *model);
  if (height_points < 2 || distance_points < 2 || height_points > 100000 ||
      distance_points > 100000)
    return -1;
  double r = atm->bottom_radius_km, R = atm->top_radius_km;
  int n_exp = sf_atmosphere_exponential_count(atm);
  size_t per_grid = 4 * (size_t)height_points * (size_t)distance_points;
  double *storage = NULL;
  if (n_exp > 0) {
    storage = malloc(sizeof(double) * per_grid * 2 * (size_t)n_exp);
    if (!storage) return -1;
  }
  model->storage = storage;
  model->bottom_radius_km = r;
  model->top_radius_km = R;
  model->n_constituents = atm->n_constituents;
  double *next = storage;
  /* seed 002 §IV.E: region I t in [0, sqrt(R^2 - r^2)], d in [r, R];
   * region II h in [0, R - r], d in [0, r] (see the header on d = r). */
  double t_span = sqrt((R - r) * (R + r));
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      sf_flat_shell_of(atm, i, &model->shell_bottom_km[i], &model->shell_top_km[i]);
      continue;
    }
    model->is_exponential[i] = 1;
    model->scale_height_km[i] = H;
    model->surface_density[i] = d0;
    next = grid_attach(&model->miss[i], next, height_points, distance_points,
                       t_span / (height_points - 1), r, (R - r) / (distance_points - 1));
    next = grid_attach(&model->hit[i], next, height_points, distance_points,
                       (R - r) / (height_points - 1), 0.0, r / (distance_points - 1));
    grid_fill(&model->miss[i], miss_node, r, H);
    grid_fill(&model->hit[i], hit_node, r, H);
  }
  return 0;
}

void sf_spline_model_free(sf_spline_model *model) {
  free(model->storage);
  memset(model, 0, sizeof *model);
}

/* ---- the 1-D spline for one d ------------------------------------------------ */

typedef struct spline_slice {
  const sf_spline_grid *grid;
  int j;                 /* d cell */
  hermite_weights wd;    /* Hermite weights across it */
  double d_step;
} spline_slice;

static spline_slice slice_make(const sf_spline_grid *g, double d) {
  spline_slice s;
  double x = (d - g->d_first) / g->d_step;
  int j = (int)floor(x);
  if (j < 0) j = 0;
  if (j > g->n_d - 2) j = g->n_d - 2;
  double v = x - j;
  if (v < 0.0) v = 0.0;
  if (v > 1.0) v = 1.0;
  s.grid = g;
  s.j = j;
  s.wd = hermite_at(v);
  s.d_step = g->d_step;
  return s;
}

/* Value and x-slope of the 1-D spline at node i (step 3 of seed 002 §IV.E). */
static void slice_node(const spline_slice *s, int i, double *value, double *slope) {
  const sf_spline_grid *g = s->grid;
  int k0 = s->j * g->n_x + i, k1 = k0 + g->n_x;
  *value = s->wd.h00 * g->value[k0] + s->wd.h10 * s->d_step * g->d_dd[k0] +
           s->wd.h01 * g->value[k1] + s->wd.h11 * s->d_step * g->d_dd[k1];
  *slope = s->wd.h00 * g->d_dx[k0] + s->wd.h10 * s->d_step * g->d_dxdd[k0] +
           s->wd.h01 * g->d_dx[k1] + s->wd.h11 * s->d_step * g->d_dxdd[k1];
}

typedef struct hermite_cell {
  double x0, step;
  double p0, m0, p1, m1;
} hermite_cell;

static double cell_value(const hermite_cell *c, double x) {
  hermite_weights w = hermite_at((x - c->x0) / c->step);
  return w.h00 * c->p0 + w.h10 * c->step * c->m0 + w.h01 * c->p1 + w.h11 * c->step * c->m1;
}

/* Region I piece: a cubic, integrated exactly by 2-point Gauss-Legendre. */
static double miss_piece(const hermite_cell *c, double a, double b, double unused) {
  (void)unused;
  double half = 0.5 * (b - a), mid = 0.5 * (a + b), g = half / sqrt(3.0);
  return half * (cell_value(c, mid - g) + cell_value(c, mid + g));
}

/* Region II piece: integral of s(h) / sqrt(h + delta), delta = r - d >= 0;
 * with q = sqrt(h + delta) it is 2 s(q^2 - delta) dq, degree 6 in q, which
 * 4-point Gauss-Legendre integrates exactly. */
static double hit_piece(const hermite_cell *c, double a, double b, double delta) {
  static const double node[2] = {0.33998104358485626, 0.86113631159405258};
  static const double weight[2] = {0.65214515486254614, 0.34785484513745386};
  double qa = sqrt(a + delta), qb = sqrt(b + delta);
  double half = 0.5 * (b - a) / (qa + qb), mid = 0.5 * (qa + qb);
  double qc = sqrt(c->x0 + delta);
  double sum = 0.0;
  for (int k = 0; k < 2; ++k) {
    for (int sign = -1; sign <= 1; sign += 2) {
      double q = mid + sign * half * node[k];
      /* h = q^2 - delta, measured from the cell start as (q - qc)(q + qc) */
      double x = c->x0 + (q - qc) * (q + qc);
      sum += weight[k] * cell_value(c, x);
    }
  }
  return 2.0 * half * sum;
}

typedef double (*piece_function)(const hermite_cell *c, double a, double b, double delta);

/* Step 4 of seed 002 §IV.E: the 1-D spline's integral over [a, b]. */
static double slice_integral(const spline_slice *s, double a, double b, piece_function piece,
                             double delta) {
  const sf_spline_grid *g = s->grid;
  double x_end = g->x_step * (g->n_x - 1);
  if (a < 0.0) a = 0.0;
  if (b > x_end) b = x_end;
  if (!(b > a)) return 0.0;
  int i = (int)floor(a / g->x_step);
  if (i > g->n_x - 2) i = g->n_x - 2;
  double sum = 0.0;
  hermite_cell c;
  c.step = g->x_step;
  slice_node(s, i, &c.p0, &c.m0);
  for (; i <= g->n_x - 2; ++i) {
    c.x0 = g->x_step * i;
    slice_node(s, i + 1, &c.p1, &c.m1);
    double lo = a > c.x0 ? a : c.x0;
    double cell_end = g->x_step * (i + 1);
    double hi = b < cell_end ? b : cell_end;
    if (i == g->n_x - 2) hi = b;
    if (hi > lo) sum += piece(&c, lo, hi, delta);
    if (b <= cell_end) break;
    c.p0 = c.p1;
    c.m0 = c.m1;
  }
  return sum;
}

/* ---- segments ------------------------------------------------------------------ */

static double spline_segment(const sf_spline_model *m, int constituent,
                             const sf_air_segment *seg) {
  double r = m->bottom_radius_km, d = seg->closest_radius;
  double total;
  if (d >= r || seg->shape == SF_AIR_SEGMENT_THROUGH_P) {
    /* region I in t = |s|; eq. 13 (through P_O) or eq. 14. A segment through
     * P_O stays above the ground, so its line misses it (d < r only by
     * rounding; the d interpolation clamps to the node d = r). */
    spline_slice s = slice_make(&m->miss[constituent], d);
    double u0 = fabs(seg->s0), u1 = fabs(seg->s1);
    if (seg->shape == SF_AIR_SEGMENT_THROUGH_P)
      total = slice_integral(&s, 0.0, u0, miss_piece, 0.0) +
              slice_integral(&s, 0.0, u1, miss_piece, 0.0);
    else
      total = slice_integral(&s, fmin(u0, u1), fmax(u0, u1), miss_piece, 0.0);
  } else {
    /* region II in h, after the substitution of seed 002 §IV.E */
    spline_slice s = slice_make(&m->hit[constituent], d);
    double delta = r - d;
    double h0 = seg->r0 - r, h1 = seg->r1 - r;
    if (seg->shape == SF_AIR_SEGMENT_THROUGH_P)
      total = slice_integral(&s, 0.0, h0, hit_piece, delta) +
              slice_integral(&s, 0.0, h1, hit_piece, delta);
    else
      total = slice_integral(&s, fmin(h0, h1), fmax(h0, h1), hit_piece, delta);
  }
  return total > 0.0 ? total : 0.0;
}

double sf_spline_exponential_segment(const sf_spline_model *model, int constituent,
                                     double r, double mu, double t0, double t1) {
  if (constituent < 0 || constituent >= model->n_constituents ||
      !model->is_exponential[constituent])
    return NAN;
  sf_air_segment seg;
  if (!sf_air_segment_make(model->bottom_radius_km, model->top_radius_km, r, mu, t0, t1, &seg))
    return 0.0;
  return spline_segment(model, constituent, &seg);
}

int sf_optical_depth_spline_segment(const sf_spline_model *model, double r, double mu,
                                    double t0, double t1, double *out) {
  double R0 = model->bottom_radius_km;
  sf_air_segment seg;
  int inside = sf_air_segment_make(R0, model->top_radius_km, r, mu, t0, t1, &seg);
  int handled = 0;
  for (int i = 0; i < model->n_constituents; ++i) {
    if (model->is_exponential[i]) {
      ++handled;
      out[i] = inside ? model->surface_density[i] * spline_segment(model, i, &seg) : 0.0;
    } else {
      out[i] = inside ? sf_flat_shell_chord(R0 + model->shell_bottom_km[i],
                                            R0 + model->shell_top_km[i], r, mu, seg.t0,
                                            seg.t1)
                      : 0.0;
    }
  }
  return handled;
}

int sf_optical_depth_spline_ray(const sf_spline_model *model, double h_km, double mu,
                                sf_ray_end end, double *out) {
  for (int i = 0; i < model->n_constituents; ++i) out[i] = 0.0;
  double r = model->bottom_radius_km + h_km;
  double t_enter, t_exit;
  int hits_ground;
  if (!sf_ray_atmosphere_segment(r, mu, model->bottom_radius_km, model->top_radius_km,
                                 &t_enter, &t_exit, &hits_ground))
    return 0;
  if (hits_ground && end == SF_RAY_END_TOP) return -1;
  sf_optical_depth_spline_segment(model, r, mu, t_enter, t_exit, out);
  return 0;
}

int sf_transmittance_spline_ray(const sf_spline_model *model, const sf_atmosphere *atm,
                                double h_km, double mu, sf_ray_end end,
                                double *transmittance) {
  double depth[SF_MAX_CONSTITUENTS];
  int rc = sf_optical_depth_spline_ray(model, h_km, mu, end, depth);
  sf_transmittance_from_depth(atm, depth, transmittance);
  return rc;
}
