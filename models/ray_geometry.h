/* Ray geometry in a spherical atmosphere, in double and float (the float
 * forms are what emitted shaders do). A ray starts at radius r (km from the
 * planet centre) with direction cosine mu against the local zenith; a point at
 * distance t along it has radius sqrt(r^2 + t^2 + 2 r mu t). Every formula
 * avoids the cancellations of the textbook quadratic (SPEC §10): the small
 * root is computed as c/q, and r^2 - R^2 as (r - R)(r + R). */
#ifndef SKYFIT_MODELS_RAY_GEOMETRY_H
#define SKYFIT_MODELS_RAY_GEOMETRY_H

/* Squared distance of the ray's line from the planet centre, r^2 (1 - mu^2). */
double sf_ray_closest_radius_sq(double r, double mu);
/* Radius at distance t along the ray, clamped to be non-negative. */
double sf_ray_radius_at(double r, double mu, double t);
/* Cosine of the zenith angle at distance t along the ray. */
double sf_ray_mu_at(double r, double mu, double t);
/* Altitude above the sphere of radius bottom at distance t along the ray
 * from altitude h: (h (r + bottom) + t (t + 2 r mu)) / (radius + bottom),
 * without radius - bottom's cancellation (in float32 the radius of a
 * 6360 km planet is 5e-4 km coarse: 5 % of a 10 m atmosphere), as the
 * emitted skyfit_altitude_at computes it. */
double sf_ray_altitude_at(double bottom, double h, double mu, double t);

/* R^2 - r^2 (1 - mu^2), whose sign says whether the ray's line meets the
 * sphere of radius R, without cancellation near the sphere (from (R - r)(R
 * + r)) and far outside it (from the closest approach). */
double sf_ray_sphere_discriminant(double r, double mu, double sphere_radius);
/* Does the ray from radius r hit the sphere of radius R_ground? A ray tangent
 * to it (discriminant exactly 0) counts as hitting, as in Bruneton 2017. */
int sf_ray_hits_sphere_from_above(double r, double mu, double sphere_radius);
/* Horizon cosine: mu of the ray tangent to the sphere of radius R (< r),
 * -sqrt(1 - (R/r)^2). */
double sf_horizon_mu(double r, double sphere_radius);

/* Both intersections t_near <= t_far of the ray's line with the sphere of
 * radius R, as distances along the ray (they may be negative: behind the
 * viewer). Returns 0 and leaves them untouched if the line misses. */
int sf_ray_sphere_intersections(double r, double mu, double sphere_radius,
                                double *t_near, double *t_far);

/* Where the ray (inside or outside the atmosphere) is within it:
 * [t_enter, t_exit] from the viewer, stopping at the ground if it hits it.
 * t_enter is 0 for viewers inside. Returns 0 if the ray never enters the
 * atmosphere. *hits_ground says whether the segment ends on the ground. */
int sf_ray_atmosphere_segment(double r, double mu, double bottom_radius,
                              double top_radius, double *t_enter,
                              double *t_exit, int *hits_ground);

/* Where the ray of a viewer above the sphere of radius top (r > top) enters
 * it: with s^2 = top^2 - p^2, p = r sqrt((1 - mu)(1 + mu)) the ray's closest
 * approach (formed as sf_ray_sphere_discriminant forms it, without
 * cancellation near the sphere or far out), the distance t_enter = -r mu - s
 * (computed as (r - top)(r + top) / (s - r mu)), the view
 * cosine there mu_e = -s / top and, with the sun at mu_s and view-sun cosine
 * nu, the sun cosine there (r (mu_s - mu nu) - s nu) / top (mu_s_e may be
 * NULL). (r mu + t_enter) / top and (r mu_s + t_enter nu) / top cancel for
 * r >> top: a viewer 1e12 km out looking straight down had seen a column of
 * 2e-282. Returns 0, leaving the outputs untouched, if the ray misses or
 * only touches the sphere, or the viewer is not above it. */
int sf_ray_enter_from_above(double r, double mu, double mu_s, double nu, double top, double *t_enter, double *mu_e,
                            double *mu_s_e);

/* The same in float32. */
float sf_ray_closest_radius_sq_f(float r, float mu);
float sf_ray_radius_at_f(float r, float mu, float t);
float sf_ray_altitude_at_f(float bottom, float h, float mu, float t);
float sf_ray_sphere_discriminant_f(float r, float mu, float sphere_radius);
int sf_ray_hits_sphere_from_above_f(float r, float mu, float sphere_radius);
float sf_horizon_mu_f(float r, float sphere_radius);
int sf_ray_sphere_intersections_f(float r, float mu, float sphere_radius,
                                  float *t_near, float *t_far);
int sf_ray_atmosphere_segment_f(float r, float mu, float bottom_radius,
                                float top_radius, float *t_enter, float *t_exit,
                                int *hits_ground);

#endif
