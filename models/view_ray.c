#include "models/view_ray.h"

#include "models/ray_geometry.h"

/* A segment may end this far past the ground point, relative to its
 * length, and still end on it: a caller's own ground distance differs from
 * ours by rounding (an orbit viewer's exact ground distance, less the entry
 * distance, was 1.25e-12 km past it and refused). 1e-12 of 1000 km is a
 * micrometre. */
#define GROUND_SLACK 1e-12

/* sf_view_ray_make, a segment ending up to slack_km past the ground point
 * ending on it. */
static int make_with_slack(const sf_atmosphere *atm, double h_km, double mu, sf_ray_end end, double distance,
                           double slack_km, sf_view_ray *out, const char **why) {
  out->r = atm->bottom_radius_km + h_km;
  out->mu = mu;
  out->t0 = out->t1 = 0.0;
  out->hits_ground = 0;
  double t_enter, t_exit;
  int hits_ground;
  int enters = sf_ray_atmosphere_segment(out->r, mu, atm->bottom_radius_km,
                                         atm->top_radius_km, &t_enter, &t_exit, &hits_ground);
  if (distance >= 0.0) {
    if (enters && hits_ground && distance > t_exit && distance - t_exit <= slack_km) distance = t_exit;
    if (enters && hits_ground && distance > t_exit) {
      *why = "the segment passes below the ground";
      return -1;
    }
    if (!enters || distance <= t_enter) return 0;
    out->t0 = t_enter;
    out->t1 = distance < t_exit ? distance : t_exit;
    out->hits_ground = hits_ground && distance >= t_exit;
    return 0;
  }
  if (!enters) return 0;
  if (hits_ground && end == SF_RAY_END_TOP) {
    *why = "the ray hits the ground before the top of the atmosphere";
    return -1;
  }
  out->t0 = t_enter;
  out->t1 = t_exit;
  out->hits_ground = hits_ground;
  return 0;
}

int sf_view_ray_make(const sf_atmosphere *atm, double h_km, double mu, sf_ray_end end,
                     double distance, sf_view_ray *out, const char **why) {
  return make_with_slack(atm, h_km, mu, end, distance, GROUND_SLACK * distance, out, why);
}

int sf_view_ray_make_at_entry(const sf_atmosphere *atm, double h_km, double mu, double mu_s, double nu,
                              sf_ray_end end, double distance, sf_view_ray *out, double *mu_s_out,
                              const char **why) {
  *mu_s_out = mu_s;
  double r = atm->bottom_radius_km + h_km, t_enter, mu_e, mu_s_e;
  if (!(r > atm->top_radius_km)) return sf_view_ray_make(atm, h_km, mu, end, distance, out, why);
  if (!sf_ray_enter_from_above(r, mu, mu_s, nu, atm->top_radius_km, &t_enter, &mu_e, &mu_s_e)) {
    /* never enters: an empty stretch at the viewer */
    out->r = r;
    out->mu = mu;
    out->t0 = out->t1 = 0.0;
    out->hits_ground = 0;
    return 0;
  }
  *mu_s_out = mu_s_e;
  if (distance >= 0.0 && !(distance > t_enter)) {   /* the segment ends before the atmosphere */
    out->r = atm->top_radius_km;
    out->mu = mu_e;
    out->t0 = out->t1 = 0.0;
    out->hits_ground = 0;
    return 0;
  }
  /* the slack relative to the viewer's distance, whose rounding distance - t_enter keeps */
  return make_with_slack(atm, atm->top_radius_km - atm->bottom_radius_km, mu_e, end,
                         distance >= 0.0 ? distance - t_enter : distance, GROUND_SLACK * distance, out, why);
}
