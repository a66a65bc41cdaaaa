/* The view ray of a query (SPEC §11 "eval"): a viewer at altitude h looking
 * along mu, and the stretch of that ray the quantity integrates over. */
#ifndef SKYFIT_MODELS_VIEW_RAY_H
#define SKYFIT_MODELS_VIEW_RAY_H

#include "models/atmosphere.h"
#include "models/optical_depth.h"

typedef struct sf_view_ray {
  double r, mu;       /* viewer radius (km from the centre) and view cosine */
  double t0, t1;      /* integrate over t in [t0, t1]; t0 = t1 when empty */
  int hits_ground;    /* the stretch ends on the ground */
} sf_view_ray;

/* Builds the stretch: by default (distance < 0) from where the ray is first
 * inside the atmosphere to the ground or the top, whichever is first
 * (end = SF_RAY_END_NEAREST), or to the top (SF_RAY_END_TOP: fails if the
 * ray hits the ground first). With distance >= 0, the segment from the viewer
 * to the point at that distance (parts outside the atmosphere count for
 * nothing; fails if it would pass below the ground by more than 1e-12 of
 * the distance, and ends on the ground if by less). A ray that never enters
 * the atmosphere gives an empty stretch. Returns 0, or -1 with *why set. */
int sf_view_ray_make(const sf_atmosphere *atm, double h_km, double mu, sf_ray_end end,
                     double distance, sf_view_ray *out, const char **why);

/* The same stretch, but for a viewer above the top the ray starts where it
 * enters (models/ray_geometry.h: out->r is the top's radius, out->mu the
 * cosine there, the stretch's distances from there), and *mu_s_out is the
 * sun's cosine at the ray's start (mu_s itself for a viewer inside). On the
 * viewer's own ray the points of a ray from 1e9 km are r^2 + t (t + 2 r mu)
 * with r^2 and t^2 cancelling: the reference's values there had come out
 * 0, 2e-282 or 100 for a column of 8. For the reference, and the
 * baselines (whose emitted code moves the viewer the same way). */
int sf_view_ray_make_at_entry(const sf_atmosphere *atm, double h_km, double mu, double mu_s, double nu,
                              sf_ray_end end, double distance, sf_view_ray *out, double *mu_s_out,
                              const char **why);

#endif
