#include "models/optical_depth_chapman.h"

#include <math.h>

#include "models/air_segment.h"

double sf_chapman_tau_up(double bottom_radius, double scale_height_km, double radius,
                         double cos_up) {
  /* seed 000 eq. 25: c = sqrt((r + h) / h0); eq. 24: exp(-h/h0) c / (1 + c cos) */
  double c = sqrt(radius / scale_height_km);
  return exp(-(radius - bottom_radius) / scale_height_km) * c / (1.0 + c * cos_up);
}

/* tau_Ch of a clipped segment, in units of H; the three shapes share eq. 24. */
static double chapman_segment_tau(const sf_air_segment *seg, double bottom_radius,
                                  double scale_height_km) {
  double H = scale_height_km;
  switch (seg->shape) {
    case SF_AIR_SEGMENT_RISING:
      return sf_chapman_tau_up(bottom_radius, H, seg->r0, seg->mu0) -
             sf_chapman_tau_up(bottom_radius, H, seg->r1, seg->mu1);
    case SF_AIR_SEGMENT_FALLING:
      /* Reversed, b looks up through a: no term passes through the planet, so
       * rays that hit the ground need no huge, cancelling eq. 23 terms. */
      return sf_chapman_tau_up(bottom_radius, H, seg->r1, -seg->mu1) -
             sf_chapman_tau_up(bottom_radius, H, seg->r0, -seg->mu0);
    case SF_AIR_SEGMENT_THROUGH_P:
    default: {
      /* seed 000 eq. 24 second case: x0 = sqrt(1 - cos^2) (r + h) / h0 is the
       * closest approach d / H, and exp(r/h0 - x0) its density, written as
       * exp(-(d - r)/H) so nothing large cancels. */
      double x0 = seg->closest_radius / H;
      double through = 2.0 * sqrt(x0) * exp(-(seg->closest_radius - bottom_radius) / H);
      return through - sf_chapman_tau_up(bottom_radius, H, seg->r0, -seg->mu0) -
             sf_chapman_tau_up(bottom_radius, H, seg->r1, seg->mu1);
    }
  }
}

double sf_chapman_exponential_segment(double bottom_radius, double top_radius,
                                      double scale_height_km, double r, double mu,
                                      double t0, double t1) {
  sf_air_segment seg;
  if (!sf_air_segment_make(bottom_radius, top_radius, r, mu, t0, t1, &seg)) return 0.0;
  double tau = chapman_segment_tau(&seg, bottom_radius, scale_height_km);
  /* A difference of approximations of nearly equal columns can round below 0. */
  return tau > 0.0 ? scale_height_km * tau : 0.0;
}

int sf_optical_depth_chapman_segment(const sf_atmosphere *atm, double r, double mu,
                                     double t0, double t1, double *out) {
  sf_air_segment seg;
  int inside = sf_air_segment_make(atm->bottom_radius_km, atm->top_radius_km, r, mu,
                                   t0, t1, &seg);
  int handled = 0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      out[i] = NAN;
      continue;
    }
    ++handled;
    double tau = inside ? chapman_segment_tau(&seg, atm->bottom_radius_km, H) : 0.0;
    out[i] = tau > 0.0 ? H * d0 * tau : 0.0;
  }
  return handled;
}
