#include "models/optical_depth_taylor.h"

#include <math.h>

#include "models/air_segment.h"

/* The part of eq. 12-17 that depends only on the line, not on H. */
typedef struct taylor_line {
  double t_min, t_max;   /* seed 002 eq. 12 */
  double tau;            /* tau_b(d) = t_min + b (t_max - t_min) */
  double h0, h1, h2;     /* h(tau_b), h'(tau_b), h''(tau_b) */
  double half_a;         /* a / 2 */
  double d, bottom_radius;
  double u0, u1;         /* the segment's ends as distances from P_O */
  sf_air_segment_shape shape;
} taylor_line;

static double clamp(double x, double lo, double hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}

static void taylor_line_make(const sf_air_segment *seg, double bottom_radius,
                             double top_radius, double a, double b, taylor_line *line) {
  double d = seg->closest_radius, r = bottom_radius, R = top_radius;
  /* seed 002 eq. 12, with x^2 - d^2 as (x - d)(x + d) */
  line->t_min = d < r ? sqrt((r - d) * (r + d)) : 0.0;
  line->t_max = d < R ? sqrt((R - d) * (R + d)) : 0.0;
  if (line->t_max < line->t_min) line->t_max = line->t_min;
  line->tau = line->t_min + b * (line->t_max - line->t_min);
  /* h(t) = sqrt(d^2 + t^2) - r (seed 002 §IV.B) and its derivatives at tau_b;
   * h(tau_b) = (d^2 - r^2 + tau^2) / (rho + r) avoids cancelling r. */
  double rho = sqrt(d * d + line->tau * line->tau);
  line->h0 = ((d - r) * (d + r) + line->tau * line->tau) / (rho + r);
  line->h1 = rho > 0.0 ? line->tau / rho : 0.0;
  line->h2 = rho > 0.0 ? d * d / (rho * rho * rho) : 0.0;
  line->half_a = 0.5 * a;
  line->d = d;
  line->bottom_radius = r;
  line->u0 = clamp(fabs(seg->s0), line->t_min, line->t_max);
  line->u1 = clamp(fabs(seg->s1), line->t_min, line->t_max);
  line->shape = seg->shape;
}

/* The expanded altitude h~(u) of seed 002 §IV.F. */
static double expanded_altitude(const taylor_line *line, double u) {
  double x = u - line->tau;
  return (line->half_a * line->h2 * x + line->h1) * x + line->h0;
}

/* The exact altitude at distance u from P_O; the integrand is largest at the
 * end of a piece nearer P_O. */
static double true_altitude(const taylor_line *line, double u) {
  double d = line->d, r = line->bottom_radius;
  return ((d - r) * (d + r) + u * u) / (sqrt(d * d + u * u) + r);
}

/* seed 002 eq. 17 between u_lo <= u_hi (eq. 17 is the case u_lo = t_min):
 * -H / h'(tau_b) [exp(-h~(u_hi)/H) - exp(-h~(u_lo)/H)], with
 * h~(u_hi) - h~(u_lo) = (u_hi - u_lo)(h' + (a/2) h'' (u_lo + u_hi - 2 tau_b)). */
static double taylor_piece(const taylor_line *line, double H, double u_lo, double u_hi) {
  double length = u_hi - u_lo;
  if (!(length > 0.0)) return 0.0;
  double h_lo = expanded_altitude(line, u_lo);
  if (!(line->h1 > 0.0)) return length * exp(-line->h0 / H);
  double rise = length * (line->h1 + line->half_a * line->h2 * (u_lo + u_hi - 2.0 * line->tau));
  double piece = H / line->h1 * exp(-h_lo / H) * -expm1(-rise / H);
  if (!isfinite(piece)) return length * exp(-true_altitude(line, u_lo) / H);
  return piece > 0.0 ? piece : 0.0;
}

static double taylor_segment(const taylor_line *line, double H) {
  switch (line->shape) {
    case SF_AIR_SEGMENT_RISING: return taylor_piece(line, H, line->u0, line->u1);
    case SF_AIR_SEGMENT_FALLING: return taylor_piece(line, H, line->u1, line->u0);
    case SF_AIR_SEGMENT_THROUGH_P:
    default:  /* seed 002 eq. 13 */
      return taylor_piece(line, H, line->t_min, line->u0) +
             taylor_piece(line, H, line->t_min, line->u1);
  }
}

static int parameters_valid(double a, double b) {
  return a >= 0.0 && a <= 1.0 && b > 0.0 && b <= 1.0;
}

double sf_taylor_exponential_segment(double bottom_radius, double top_radius,
                                     double scale_height_km, double a, double b,
                                     double r, double mu, double t0, double t1) {
  if (!parameters_valid(a, b)) return NAN;
  sf_air_segment seg;
  if (!sf_air_segment_make(bottom_radius, top_radius, r, mu, t0, t1, &seg)) return 0.0;
  taylor_line line;
  taylor_line_make(&seg, bottom_radius, top_radius, a, b, &line);
  return taylor_segment(&line, scale_height_km);
}

int sf_optical_depth_taylor_segment(const sf_atmosphere *atm, double r, double mu,
                                    double t0, double t1, double a, double b,
                                    double *out) {
  int n = atm->n_constituents;
  if (!parameters_valid(a, b)) {
    for (int i = 0; i < n; ++i) out[i] = NAN;
    return 0;
  }
  sf_air_segment seg;
  int inside = sf_air_segment_make(atm->bottom_radius_km, atm->top_radius_km, r, mu,
                                   t0, t1, &seg);
  taylor_line line;
  if (inside) taylor_line_make(&seg, atm->bottom_radius_km, atm->top_radius_km, a, b, &line);
  int handled = 0;
  for (int i = 0; i < n; ++i) {
    double H, d0;
    if (!sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      out[i] = NAN;
      continue;
    }
    ++handled;
    out[i] = inside ? d0 * taylor_segment(&line, H) : 0.0;
  }
  return handled;
}
