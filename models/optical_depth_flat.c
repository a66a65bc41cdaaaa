#include "models/optical_depth_flat.h"

#include <math.h>
#include <stddef.h>

#include "models/air_segment.h"
#include "models/quadrature.h"
#include "models/ray_geometry.h"

/* sqrt((rho + H)^2 - rho^2) of eq. 48-53 is sqrt(A) with A = H (2 rho + H). */
static double shell_area_term(double rho, double H) { return H * (2.0 * rho + H); }

double sf_flat_tau_up(double bottom_radius, double scale_height_km, double rho,
                      double cos_up) {
  double H = scale_height_km;
  double A = shell_area_term(rho, H);
  double rc = rho * cos_up;
  /* seed 000 eq. 51, sqrt(A + rho^2 cos^2) - rho cos written as
   * A / (sqrt(A + rho^2 cos^2) + rho cos): no cancellation for cos >= 0. */
  return exp(-(rho - bottom_radius) / H) * A / (sqrt(A + rc * rc) + rc);
}

static double flat_tau_horizontal(double bottom_radius, double H, double rho) {
  return exp(-(rho - bottom_radius) / H) * sqrt(shell_area_term(rho, H));
}

double sf_flat_tau_down(double bottom_radius, double scale_height_km, double rho,
                        double cos_down) {
  /* seed 000 eq. 53: 2 sqrt(A) - (sqrt(A + rho^2 cos^2) + rho cos), i.e. twice
   * the horizontal column minus the up-looking one behind the point, scaled
   * by the point's density as eq. 51 does. */
  return 2.0 * flat_tau_horizontal(bottom_radius, scale_height_km, rho) -
         sf_flat_tau_up(bottom_radius, scale_height_km, rho, -cos_down);
}

/* eq. 51 or eq. 53 by the sign of the direction's zenith cosine. */
static double flat_tau_along(double bottom_radius, double H, double rho, double cosine) {
  return cosine >= 0.0 ? sf_flat_tau_up(bottom_radius, H, rho, cosine)
                       : sf_flat_tau_down(bottom_radius, H, rho, cosine);
}

static double flat_segment_tau(const sf_air_segment *seg, double bottom_radius,
                               double H, sf_flat_descent descent) {
  int line_hits_ground = seg->closest_radius <= bottom_radius;
  if (seg->shape == SF_AIR_SEGMENT_RISING)
    return sf_flat_tau_up(bottom_radius, H, seg->r0, seg->mu0) -
           sf_flat_tau_up(bottom_radius, H, seg->r1, seg->mu1);
  if (seg->shape == SF_AIR_SEGMENT_FALLING &&
      (line_hits_ground || descent == SF_FLAT_DESCENT_CLOSEST))
    /* seed 000 §11.3.3: reversed, with the lower end as the midpoint. */
    return sf_flat_tau_up(bottom_radius, H, seg->r1, -seg->mu1) -
           sf_flat_tau_up(bottom_radius, H, seg->r0, -seg->mu0);
  if (descent == SF_FLAT_DESCENT_CLOSEST)
    /* eq. 53 about the closest point c: both halves of the line through c. */
    return 2.0 * flat_tau_horizontal(bottom_radius, H, seg->closest_radius) -
           sf_flat_tau_up(bottom_radius, H, seg->r0, -seg->mu0) -
           sf_flat_tau_up(bottom_radius, H, seg->r1, seg->mu1);
  /* eq. 53 at the segment's start, minus the same-direction value at its end. */
  return flat_tau_along(bottom_radius, H, seg->r0, seg->mu0) -
         flat_tau_along(bottom_radius, H, seg->r1, seg->mu1);
}

double sf_flat_exponential_segment(double bottom_radius, double top_radius,
                                   double scale_height_km, sf_flat_descent descent,
                                   double r, double mu, double t0, double t1) {
  sf_air_segment seg;
  if (!sf_air_segment_make(bottom_radius, top_radius, r, mu, t0, t1, &seg)) return 0.0;
  double tau = flat_segment_tau(&seg, bottom_radius, scale_height_km, descent);
  return tau > 0.0 ? tau : 0.0;
}

/* Length of [t0, t1] inside the sphere of radius R. */
static double inside_sphere_length(double R, double r, double mu, double t0, double t1) {
  double t_near, t_far;
  if (!(R > 0.0) || !sf_ray_sphere_intersections(r, mu, R, &t_near, &t_far)) return 0.0;
  double a = t0 > t_near ? t0 : t_near;
  double b = t1 < t_far ? t1 : t_far;
  return b > a ? b - a : 0.0;
}

double sf_flat_shell_chord(double shell_bottom_radius, double shell_top_radius,
                           double r, double mu, double t0, double t1) {
  /* seed 000 §10.5: the path inside the top sphere of the shell minus the
   * path inside its bottom sphere. */
  double chord = inside_sphere_length(shell_top_radius, r, mu, t0, t1) -
                 inside_sphere_length(shell_bottom_radius, r, mu, t0, t1);
  return chord > 0.0 ? chord : 0.0;
}

typedef struct profile_moments {
  const sf_constituent *constituent;
} profile_moments;

static void density_and_moment(void *ctx, double h, double *values) {
  const profile_moments *p = ctx;
  double density = sf_constituent_density(p->constituent, h);
  values[0] = density;
  values[1] = h * density;
}

void sf_flat_shell_of(const sf_atmosphere *atm, int constituent, double *bottom_km,
                      double *top_km) {
  profile_moments p = {&atm->constituents[constituent]};
  double sums[2] = {0.0, 0.0};
  double lo = 0.0, thickness = sf_atmosphere_thickness_km(atm);
  for (int k = 0; k <= atm->n_kinks; ++k) {
    double hi = k < atm->n_kinks ? atm->kink_altitudes_km[k] : thickness;
    if (hi > lo) sf_integrate_adaptive(density_and_moment, &p, lo, hi, 2, 1e-13, NULL, sums);
    lo = hi;
  }
  double column = sums[0];
  double mean = column > 0.0 ? sums[1] / column : 0.0;
  /* seed 000 eq. 59 generalised: density 1 over a width equal to the column
   * keeps the vertical column; centring it at the mean keeps its first
   * moment. */
  *bottom_km = mean - 0.5 * column;
  *top_km = mean + 0.5 * column;
}

void sf_flat_model_make(const sf_atmosphere *atm, sf_flat_descent descent,
                        sf_flat_model *model) {
  model->descent = descent;
  for (int i = 0; i < SF_MAX_CONSTITUENTS; ++i) {
    model->is_shell[i] = 0;
    model->shell_bottom_km[i] = model->shell_top_km[i] = 0.0;
  }
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (sf_constituent_exponential(&atm->constituents[i], &H, &d0)) continue;
    model->is_shell[i] = 1;
    sf_flat_shell_of(atm, i, &model->shell_bottom_km[i], &model->shell_top_km[i]);
  }
}

/* clip_radius: the ground's radius, or 0 to take the line through it. */
static int flat_columns(const sf_atmosphere *atm, double clip_radius, double r, double mu, double t0,
                        double t1, const sf_flat_model *model, double *out) {
  int n = atm->n_constituents;
  sf_air_segment seg;
  int inside = sf_air_segment_make(clip_radius, atm->top_radius_km, r, mu, t0, t1, &seg);
  for (int i = 0; i < n; ++i) {
    out[i] = 0.0;
    if (!inside) continue;
    if (model->is_shell[i]) {
      out[i] = sf_flat_shell_chord(atm->bottom_radius_km + model->shell_bottom_km[i],
                                   atm->bottom_radius_km + model->shell_top_km[i], r, mu,
                                   seg.t0, seg.t1);
      continue;
    }
    double H, d0;
    sf_constituent_exponential(&atm->constituents[i], &H, &d0);
    double tau = flat_segment_tau(&seg, atm->bottom_radius_km, H, model->descent);
    out[i] = tau > 0.0 ? d0 * tau : 0.0;
  }
  return n;
}

int sf_optical_depth_flat_segment(const sf_atmosphere *atm, double r, double mu,
                                  double t0, double t1, const sf_flat_model *model,
                                  double *out) {
  return flat_columns(atm, atm->bottom_radius_km, r, mu, t0, t1, model, out);
}

int sf_optical_depth_flat_line_segment(const sf_atmosphere *atm, double r, double mu, double t0, double t1,
                                       const sf_flat_model *model, double *out) {
  return flat_columns(atm, 0.0, r, mu, t0, t1, model, out);
}
