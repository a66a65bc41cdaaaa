#include "models/atmosphere.h"

#include <math.h>
#include <string.h>

#include "util/sort_doubles.h"

static int layer_index(const sf_constituent *c, double h_km) {
  double top_of_layer = 0.0;
  for (int i = 0; i < c->n_layers - 1; ++i) {
    top_of_layer += c->layers[i].width_km;
    if (h_km < top_of_layer) return i;
  }
  return c->n_layers - 1;
}

double sf_density_layer_value(const sf_density_layer *l, double h_km) {
  double v = l->linear_per_km * h_km + l->constant;
  if (l->exp_term != 0.0) v += l->exp_term * exp(l->exp_scale_per_km * h_km);
  return v;
}

double sf_constituent_density(const sf_constituent *c, double h_km) {
  if (c->n_layers <= 0) return 0.0;
  double v = sf_density_layer_value(&c->layers[layer_index(c, h_km)], h_km);
  return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
}

double sf_atmosphere_thickness_km(const sf_atmosphere *atm) {
  return atm->top_radius_km - atm->bottom_radius_km;
}

int sf_constituent_scatters(const sf_constituent *c, int n_channels) {
  for (int ch = 0; ch < n_channels; ++ch)
    if (c->scattering[ch] > 0.0) return 1;
  return 0;
}

int sf_atmosphere_scattering_count(const sf_atmosphere *atm) {
  int n = 0;
  for (int i = 0; i < atm->n_constituents; ++i) n += sf_constituent_scatters(&atm->constituents[i], atm->n_channels);
  return n;
}

int sf_atmosphere_find(const sf_atmosphere *atm, const char *name) {
  for (int i = 0; i < atm->n_constituents; ++i)
    if (strcmp(atm->constituents[i].name, name) == 0) return i;
  return -1;
}

int sf_constituent_exponential(const sf_constituent *c, double *scale_height_km,
                               double *surface_density) {
  if (c->n_layers != 1) return 0;
  const sf_density_layer *l = &c->layers[0];
  if (l->linear_per_km != 0.0 || l->constant != 0.0) return 0;
  if (!(l->exp_term > 0.0 && l->exp_term <= 1.0 && l->exp_scale_per_km < 0.0)) return 0;
  *scale_height_km = -1.0 / l->exp_scale_per_km;
  *surface_density = l->exp_term;
  return 1;
}

int sf_atmosphere_exponential_count(const sf_atmosphere *atm) {
  int n = 0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    n += sf_constituent_exponential(&atm->constituents[i], &H, &d0);
  }
  return n;
}

/* ---- kinks: where a density profile has a corner ---------------------- */

static void add_kink(double *k, int *n, double h, double thickness) {
  if (!(h > 0.0 && h < thickness) || *n >= SF_MAX_KINKS) return;
  k[(*n)++] = h;
}

/* Root of sf_density_layer_value(l, h) - level on [a, b], where the function is
 * monotone and changes sign: bisection to full double precision. */
static double bisect_level(const sf_density_layer *l, double level, double a, double b) {
  double fa = sf_density_layer_value(l, a) - level;
  for (int it = 0; it < 200 && b - a > 0.0; ++it) {
    double m = 0.5 * (a + b);
    if (m <= a || m >= b) break;
    double fm = sf_density_layer_value(l, m) - level;
    if ((fm < 0.0) == (fa < 0.0)) { a = m; fa = fm; } else { b = m; }
  }
  return 0.5 * (a + b);
}

/* The clamp to [0, 1] makes a corner where the layer's raw value crosses 0
 * or 1. exp_term*exp(s h) + linear*h is convex or concave, so it is monotone
 * on each side of its one stationary point: one crossing per side at most. */
static void add_clamp_kinks(const sf_density_layer *l, double lo, double hi,
                            double thickness, double *k, int *n) {
  double cuts[3] = {lo, hi, hi};
  int n_cuts = 2;
  if (l->exp_term != 0.0 && l->exp_scale_per_km != 0.0 && l->linear_per_km != 0.0) {
    double arg = -l->linear_per_km / (l->exp_term * l->exp_scale_per_km);
    if (arg > 0.0) {
      double stationary = log(arg) / l->exp_scale_per_km;
      if (stationary > lo && stationary < hi) {
        cuts[1] = stationary;
        cuts[2] = hi;
        n_cuts = 3;
      }
    }
  }
  for (int piece = 0; piece + 1 < n_cuts; ++piece) {
    double a = cuts[piece], b = cuts[piece + 1];
    for (int level = 0; level <= 1; ++level) {
      double fa = sf_density_layer_value(l, a) - level, fb = sf_density_layer_value(l, b) - level;
      if (fa == 0.0) add_kink(k, n, a, thickness);
      else if (fa * fb < 0.0) add_kink(k, n, bisect_level(l, level, a, b), thickness);
    }
  }
}

void sf_atmosphere_finalize(sf_atmosphere *atm) {
  double thickness = sf_atmosphere_thickness_km(atm);
  double k[SF_MAX_KINKS];
  int n = 0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    double lo = 0.0;
    for (int j = 0; j < c->n_layers; ++j) {
      int last = j == c->n_layers - 1;
      double hi = last ? thickness : lo + c->layers[j].width_km;
      if (hi > thickness) hi = thickness;
      if (!last) add_kink(k, &n, lo + c->layers[j].width_km, thickness);
      if (hi > lo) add_clamp_kinks(&c->layers[j], lo, hi, thickness, k, &n);
      lo += c->layers[j].width_km;
      if (lo >= thickness) break;
    }
  }
  sf_sort_doubles(k, (size_t)n);
  /* Corners closer than SF_KINK_MERGE_KM are one corner for quadrature: the
   * default ozone tent, written with 7 digits, is clamped at 1 over the
   * 2.5 mm around 25 km. Smoothing over a plateau of width w with a slope
   * change s misplaces at most s w^2 of the integral: 0.07/km * (1e-5 km)^2
   * = 7e-12 km of ozone, 5e-13 of its column. */
  atm->n_kinks = 0;
  for (int i = 0; i < n; ++i)
    if (atm->n_kinks == 0 || k[i] - atm->kink_altitudes_km[atm->n_kinks - 1] > SF_KINK_MERGE_KM)
      atm->kink_altitudes_km[atm->n_kinks++] = k[i];
}
