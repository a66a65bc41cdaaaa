#include "models/view_ray.h"

#include "models/ray_geometry.h"

int sf_view_ray_make(const sf_atmosphere *atm, double h_km, double mu, sf_ray_end end,
                     double distance, sf_view_ray *out, const char **why) {
  out->r = atm->bottom_radius_km + h_km;
  out->mu = mu;
  out->t0 = out->t1 = 0.0;
  out->hits_ground = 0;
  double t_enter, t_exit;
  int hits_ground;
  int enters = sf_ray_atmosphere_segment(out->r, mu, atm->bottom_radius_km,
                                         atm->top_radius_km, &t_enter, &t_exit, &hits_ground);
  if (distance >= 0.0) {
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
