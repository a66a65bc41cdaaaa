#include "models/air_segment.h"

#include <math.h>

#include "models/ray_geometry.h"

int sf_air_segment_clip(double bottom_radius, double top_radius, double r, double mu,
                        double *t0, double *t1) {
  double a = *t0, b = *t1;
  double top_near, top_far;
  if (!(b > a) ||
      !sf_ray_sphere_intersections(r, mu, top_radius, &top_near, &top_far)) {
    *t1 = *t0;
    return 0;
  }
  if (top_near > a) a = top_near;
  if (top_far < b) b = top_far;
  /* The open interval (ground_near, ground_far) is inside the planet; a line
   * that only touches the ground (equal roots) loses nothing. */
  double ground_near, ground_far;
  if (sf_ray_sphere_intersections(r, mu, bottom_radius, &ground_near, &ground_far) &&
      ground_near < ground_far) {
    if (a <= ground_near) {
      if (ground_near < b) b = ground_near;
    } else if (a < ground_far) {
      a = ground_far;   /* starts inside the planet: only rounding gets here */
    }
  }
  if (!(b > a)) {
    *t0 = *t1 = a;
    return 0;
  }
  *t0 = a;
  *t1 = b;
  return 1;
}

static void describe_end(double r, double mu, double t, double *s, double *radius,
                         double *cosine) {
  *s = t + r * mu;
  *radius = sf_ray_radius_at(r, mu, t);
  double c = *radius > 0.0 ? *s / *radius : mu;
  *cosine = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
}

int sf_air_segment_make(double bottom_radius, double top_radius, double r, double mu,
                        double t0, double t1, sf_air_segment *out) {
  if (!sf_air_segment_clip(bottom_radius, top_radius, r, mu, &t0, &t1)) return 0;
  out->t0 = t0;
  out->t1 = t1;
  describe_end(r, mu, t0, &out->s0, &out->r0, &out->mu0);
  describe_end(r, mu, t1, &out->s1, &out->r1, &out->mu1);
  out->closest_radius = sqrt(sf_ray_closest_radius_sq(r, mu));
  out->shape = out->s0 >= 0.0   ? SF_AIR_SEGMENT_RISING
               : out->s1 <= 0.0 ? SF_AIR_SEGMENT_FALLING
                                : SF_AIR_SEGMENT_THROUGH_P;
  return 1;
}
