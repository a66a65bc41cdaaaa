/* The tangent sweep: the (h, mu) points where transmittance models err
 * most, for the maximum error a weights file or header states.
 *
 * A model of the full-ray transmittance changes its form where the ray
 * grazes a sphere: at the horizon it switches from rays that reach the top
 * to rays that end on the ground (eq. 43's ratio T(viewer)/T(ground point)
 * for the sigmoid, a step in path length for Taylor); the baselines that
 * replace the ozone by a constant shell (seed 000 §10.5) jump where the
 * ray starts to cross the shell, with a chord that is longest when it
 * grazes it. The error peaks or jumps there, in a band narrower than any
 * (h, mu) grid's column spacing: the sigmoid errs 0.655 at the horizon
 * 0.36 km up where a 48 x 96 grid found 0.467; Chapman's ozone shell
 * 0.306 where a 64 x 384 grid found 0.295.
 *
 * For a sphere of altitude sphere_h_km (0: the ground), the sweep visits
 * 1e-6 either side of the cosine of the ray tangent to it (SPEC §10), on
 * SF_TANGENT_SWEEP_ROWS rows h = lo + (h_max - lo) u^2, u uniform in
 * [0, 1], lo = max(h_min, sphere_h): squared spacing puts rows 0.4 m
 * apart just above the sphere (where the horizon error peaks) and 0.4 km
 * apart at the top of a 100 km domain. Rows on the sphere itself and
 * points whose mu lies outside [mu_min, mu_max] are skipped. These points
 * belong in a maximum, not in an RMSE: they are not a sample of the
 * domain. The tangent ray itself is left out: whether it ends at the
 * tangent point (the reference, as Bruneton) or passes it (the naive
 * raymarch's clip) is a convention, and a model that passes it differs
 * there by the whole far part of the ray (0.85 for the naive model 6 m
 * up), not by an error of its approximation. */
#ifndef SKYFIT_MODELS_TANGENT_SWEEP_H
#define SKYFIT_MODELS_TANGENT_SWEEP_H

enum { SF_TANGENT_SWEEP_ROWS = 512 };

typedef void (*sf_tangent_visit)(void *ctx, double h_km, double mu);

/* Calls visit for each point in order (rows by increasing h, then mu);
 * returns the number of points visited. */
long sf_tangent_sweep(double bottom_radius_km, double sphere_h_km, double h_min_km, double h_max_km,
                      double mu_min, double mu_max, sf_tangent_visit visit, void *ctx);

#endif
