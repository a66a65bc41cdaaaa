/* The part of a ray segment that lies in the air, described the way the
 * analytic optical-depth approximations (SPEC §7.6) need it. They integrate
 * over the same stretch as the reference (models/optical_depth.h): nothing
 * above the top radius, never below the ground. Along the ray (r, mu) a point
 * at distance t has signed distance s = t + r*mu from the ray's closest
 * approach P to the planet centre (seed 002 eq. 10-11: t_P), radius
 * sqrt(d^2 + s^2) with d = r*sqrt(1 - mu^2), and zenith cosine s / radius. */
#ifndef SKYFIT_MODELS_AIR_SEGMENT_H
#define SKYFIT_MODELS_AIR_SEGMENT_H

typedef enum sf_air_segment_shape {
  SF_AIR_SEGMENT_RISING = 0,   /* wholly at or after P: the radius grows */
  SF_AIR_SEGMENT_FALLING,      /* wholly at or before P: the radius shrinks */
  SF_AIR_SEGMENT_THROUGH_P     /* P lies strictly inside */
} sf_air_segment_shape;

typedef struct sf_air_segment {
  double t0, t1;              /* the clipped segment, t0 < t1 */
  double s0, s1;              /* signed distances from P, s = t + r*mu */
  double r0, r1;              /* radii at the ends */
  double mu0, mu1;            /* zenith cosines of the ray direction at the ends */
  double closest_radius;      /* d: the line's distance from the centre */
  sf_air_segment_shape shape;
} sf_air_segment;

/* Restricts [t0, t1] along the ray (r, mu) to where it is inside the top
 * sphere and, if the ray's line crosses the ground sphere, to the part before
 * the ground (a segment that starts above the ground stops where it meets
 * it). Returns 0 and leaves *t0 == *t1 when nothing is left, else 1. */
int sf_air_segment_clip(double bottom_radius, double top_radius, double r, double mu,
                        double *t0, double *t1);

/* Clips as above and describes what is left. Returns 0 (out untouched) when
 * nothing is left, else 1. */
int sf_air_segment_make(double bottom_radius, double top_radius, double r, double mu,
                        double t0, double t1, sf_air_segment *out);

#endif
