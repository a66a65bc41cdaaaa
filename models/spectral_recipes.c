#include "models/spectral_recipes.h"

#include <math.h>
#include <stdlib.h>

#include "models/quadrature.h"
#include "models/spectral_data.h"
#include "util/constants.h"

double sf_rayleigh_lambda4_per_km(double lambda_nm, double reference_nm, double reference_per_km) {
  double r = reference_nm / lambda_nm;
  return reference_per_km * (r * r) * (r * r);
}

double sf_rayleigh_formula_per_km(double lambda_nm, double n, double number_density_per_m3) {
  double n2m1 = n * n - 1.0;
  double l = lambda_nm * 1e-9;
  double per_m = 8.0 * SF_PI * SF_PI * SF_PI * n2m1 * n2m1 / (3.0 * number_density_per_m3 * l * l * l * l);
  return per_m * 1e3;
}

double sf_angstrom_per_km(double lambda_nm, double reference_nm, double reference_per_km, double exponent) {
  return reference_per_km * pow(lambda_nm / reference_nm, -exponent);
}

static void density_at(void *ctx, double h_km, double *value) { *value = sf_constituent_density(ctx, h_km); }

double sf_density_column_km(const sf_constituent *c, double thickness_km) {
  /* Adaptive Gauss-Kronrod per layer, split where a linear layer's clamp to
   * [0, 1] bends it and 64 scale heights up a decaying exponential. A trapezoid of
   * 2^18 steps over the whole thickness had missed a 30 km ozone tent in a
   * 1e8 km atmosphere ("integrates to 0") and been 1.2e-4 high for a scale
   * height of 10 m. */
  double column = 0.0, lo = 0.0, layer_top = 0.0;
  for (int l = 0; l < c->n_layers && lo < thickness_km; ++l) {
    layer_top += c->layers[l].width_km;
    double hi = l < c->n_layers - 1 ? fmin(layer_top, thickness_km) : thickness_km;
    /* the layer's ends, and where a linear layer meets 0 or 1 between them */
    double cuts[4] = {lo};
    int n = 1;
    const sf_density_layer *layer = &c->layers[l];
    for (int bound = 0; bound <= 1 && layer->exp_term == 0.0 && layer->linear_per_km != 0.0; ++bound) {
      double at = (bound - layer->constant) / layer->linear_per_km;
      if (at > lo && at < hi) cuts[n++] = at;
    }
    /* a decaying exponential's mass within 64 scale heights of the layer's
     * foot: over 3e6 km at once, every node saw 0 and so did the error */
    if (layer->exp_term != 0.0 && layer->exp_scale_per_km < 0.0 && lo - 64.0 / layer->exp_scale_per_km < hi)
      cuts[n++] = lo - 64.0 / layer->exp_scale_per_km;
    if (n == 3 && cuts[1] > cuts[2]) {
      double swap = cuts[1];
      cuts[1] = cuts[2];
      cuts[2] = swap;
    }
    cuts[n++] = hi;
    for (int k = 0; k + 1 < n; ++k)
      if (cuts[k + 1] > cuts[k]) sf_integrate_adaptive(density_at, (void *)c, cuts[k], cuts[k + 1], 1, 1e-13, NULL, &column);
    lo = hi;
  }
  return column;
}

double sf_ozone_peak_number_density(double column_du, double profile_column_km) {
  return column_du * SF_DOBSON_UNIT_PER_M2 / (profile_column_km * 1e3);
}

static int table_recipe(const char *file, const char *column, int n, const double *lambda_nm, int loglog,
                        double scale, double *out, sf_error *err) {
  sf_spectrum *s = malloc(sizeof *s);
  if (!s) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int rc = sf_spectrum_load(file, column, s, err);
  for (int i = 0; rc == 0 && i < n; ++i) {
    if (!sf_spectrum_covers(s, lambda_nm[i])) {
      rc = sf_fail(err, SF_ERR_INPUT, "wavelength %g nm is outside %s (%g to %g nm)", lambda_nm[i], file,
                   s->lambda_nm[0], s->lambda_nm[s->n - 1]);
      break;
    }
    out[i] = scale * (loglog ? sf_spectrum_loglog(s, lambda_nm[i]) : sf_spectrum_linear(s, lambda_nm[i]));
  }
  free(s);
  return rc;
}

int sf_recipe_rayleigh_bucholtz(int n, const double *lambda_nm, double scale, double *out, sf_error *err) {
  return table_recipe("rayleigh_bucholtz.csv", "beta_s_per_km", n, lambda_nm, 1, scale, out, err);
}

int sf_recipe_ozone_cross_section(int n, const double *lambda_nm, double peak_number_density_per_m3,
                                  double *out, sf_error *err) {
  /* sigma (m²) * N (1/m³) = 1/m; * 1e3 = 1/km */
  return table_recipe("ozone_cross_section.csv", "cross_section_m2", n, lambda_nm, 0,
                      peak_number_density_per_m3 * 1e3, out, err);
}

int sf_recipe_solar_astm_g173(int n, const double *lambda_nm, double bin_nm, double scale, double *out,
                              sf_error *err) {
  sf_spectrum *s = malloc(sizeof *s);
  if (!s) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int rc = sf_spectrum_load("astm_g173.csv", "etr", s, err);
  for (int i = 0; rc == 0 && i < n; ++i) {
    double lo = lambda_nm[i] - 0.5 * bin_nm, hi = lambda_nm[i] + 0.5 * bin_nm;
    if (!sf_spectrum_covers(s, lo) || !sf_spectrum_covers(s, hi)) {
      rc = sf_fail(err, SF_ERR_INPUT, "wavelength bin %g..%g nm is outside astm_g173.csv (%g to %g nm)", lo, hi,
                   s->lambda_nm[0], s->lambda_nm[s->n - 1]);
      break;
    }
    out[i] = scale * sf_spectrum_window_mean(s, lo, hi);
  }
  free(s);
  return rc;
}
