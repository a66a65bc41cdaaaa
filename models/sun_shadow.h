/* The sun seen from the points of a view ray: where the planet hides it,
 * and where the sun ray grazes a sphere (the ground: the shadow's edge; a
 * density kink: a corner of the sun's optical depth).
 *
 * A viewer at radius r looks along v (cosine mu with its zenith); the sun
 * is s (cosine mu_s with the viewer's zenith, nu with v). The sun ray from
 * p = viewer + t v passes the planet centre at distance d, with
 *   d^2 - rho^2 = |p|^2 - (p.s)^2 - rho^2
 *               = (1 - nu^2) t^2 + 2 r (mu - mu_s nu) t + (r^2 - rho^2) - r^2 mu_s^2,
 * and comes closest ahead of p where p.s = r mu_s + t nu < 0. Both are
 * taken from the ray's own parameters, not from p's radius and sun cosine
 * (rounded through a square root and a division): a sun ray exactly
 * tangent to the sphere gives exactly 0, and the shadow's edge is where the
 * tangent points say it is. */
#ifndef SKYFIT_MODELS_SUN_SHADOW_H
#define SKYFIT_MODELS_SUN_SHADOW_H

/* d^2 - rho^2 as a t^2 + b t + c, and p.s as r_mu_s + t nu. */
typedef struct sf_sun_line {
  double a, b, c;
  double r_mu_s, nu;
} sf_sun_line;

/* The sun lines of a view ray against the sphere of radius rho (nu within
 * what mu and mu_s allow: sf_clamp_nu). */
sf_sun_line sf_sun_line_make(double r, double mu, double mu_s, double nu, double rho);

/* d^2 - rho^2 for the sun ray from distance t along the view ray. */
double sf_sun_line_clearance(const sf_sun_line *line, double t);

/* Whether the sphere hides the sun from distance t along the view ray: the
 * sun ray goes down from there (p.s < 0) and its line passes strictly
 * inside the sphere. A sun ray tangent to it is not hidden: the sun on the
 * horizon of a viewer on the ground lights the viewer, and (mu = 0, mu_s =
 * 0, nu = -1 at h = 0) every point of the horizontal ray away from it, whose
 * sun rays all graze the ground at the viewer (they had been hidden or not
 * by rounding, point by point: half the light). */
int sf_sun_line_hidden(const sf_sun_line *line, double t);

/* Distances t where the sun line touches the sphere (d = rho): at most 2,
 * written to out; returns their count (unsorted, any sign). */
int sf_sun_line_tangent_distances(const sf_sun_line *line, double out[2]);

#endif
