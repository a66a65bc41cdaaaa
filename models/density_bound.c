#include "models/density_bound.h"

#include <math.h>

/* Limit of the layer's value as h -> +infinity. */
static double layer_limit_at_infinity(const sf_density_layer *l) {
  double e = l->exp_term, s = l->exp_scale_per_km, lin = l->linear_per_km;
  if (e != 0.0 && s > 0.0) return e > 0.0 ? INFINITY : -INFINITY;   /* exp dominates */
  if (lin != 0.0) return lin > 0.0 ? INFINITY : -INFINITY;
  return l->constant + (s == 0.0 ? e : 0.0);
}

/* Max of one layer's unclamped value over [a, b], a finite, b finite or
 * +infinity. */
static double layer_max(const sf_density_layer *l, double a, double b) {
  double best = sf_density_layer_value(l, a);
  double end = isfinite(b) ? sf_density_layer_value(l, b) : layer_limit_at_infinity(l);
  if (end > best) best = end;
  double e = l->exp_term, s = l->exp_scale_per_km, lin = l->linear_per_km;
  if (e != 0.0 && s != 0.0) {            /* stationary point: e s exp(s h) + lin = 0 */
    double arg = -lin / (e * s);
    if (arg > 0.0) {
      double h = log(arg) / s;
      if (h > a && h < b) {
        double v = sf_density_layer_value(l, h);
        if (v > best) best = v;
      }
    }
  }
  return best;
}

double sf_constituent_max_density(const sf_constituent *c, double h_lo, double h_hi) {
  if (c->n_layers <= 0 || !(h_hi >= h_lo) || !isfinite(h_lo)) return 0.0;
  /* Layer j holds on [sum of widths before j, sum through j), the first from
   * -infinity, the last to +infinity (sf_constituent_density); the closed
   * ranges used here can only raise the bound. */
  double best = -INFINITY, layer_lo = -INFINITY, cumulative = 0.0;
  for (int j = 0; j < c->n_layers && layer_lo <= h_hi; ++j) {
    double layer_hi = INFINITY;
    if (j < c->n_layers - 1) {
      cumulative += c->layers[j].width_km;
      layer_hi = cumulative;
    }
    double a = h_lo > layer_lo ? h_lo : layer_lo;
    double b = h_hi < layer_hi ? h_hi : layer_hi;
    if (a <= b) {
      double v = layer_max(&c->layers[j], a, b);
      if (v > best) best = v;
    }
    layer_lo = layer_hi;
  }
  return best < 0.0 ? 0.0 : (best > 1.0 ? 1.0 : best);
}
