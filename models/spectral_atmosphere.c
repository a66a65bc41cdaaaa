#include "models/spectral_atmosphere.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/color_space.h"
#include "models/spectral_recipes.h"

int sf_spectral_grid(double min_nm, double max_nm, double step_nm, double *lambda_nm) {
  int n = (int)floor((max_nm - min_nm) / step_nm + 1e-9) + 1;
  if (n > SF_MAX_CHANNELS) n = SF_MAX_CHANNELS;
  for (int i = 0; i < n; ++i) lambda_nm[i] = min_nm + step_nm * i;
  return n;
}

/* Linear in wavelength through (x[k], y[k]) (increasing x), constant beyond. */
static double piecewise_linear(int m, const double *x, const double *y, double at) {
  if (at <= x[0]) return y[0];
  if (at >= x[m - 1]) return y[m - 1];
  int k = 0;
  while (at > x[k + 1]) ++k;
  double t = (at - x[k]) / (x[k + 1] - x[k]);
  return y[k] + t * (y[k + 1] - y[k]);
}

/* RGB value triplet (r, g, b) -> spectrum at n wavelengths. */
static void rgb_power_law_or_linear(const double rgb[3], int n, const double *nm, double *out) {
  const double lam[3] = {SF_RGB_LAMBDA_B_NM, SF_RGB_LAMBDA_G_NM, SF_RGB_LAMBDA_R_NM};
  const double val[3] = {rgb[2], rgb[1], rgb[0]};
  if (val[0] > 0.0 && val[1] > 0.0 && val[2] > 0.0) {
    /* least squares: log v = a - alpha log lambda */
    double mx = 0.0, my = 0.0;
    for (int k = 0; k < 3; ++k) mx += log(lam[k]) / 3.0, my += log(val[k]) / 3.0;
    double sxy = 0.0, sxx = 0.0;
    for (int k = 0; k < 3; ++k) {
      sxy += (log(lam[k]) - mx) * (log(val[k]) - my);
      sxx += (log(lam[k]) - mx) * (log(lam[k]) - mx);
    }
    double slope = sxy / sxx;
    for (int i = 0; i < n; ++i) out[i] = exp(my + slope * (log(nm[i]) - mx));
    return;
  }
  for (int i = 0; i < n; ++i) out[i] = piecewise_linear(3, lam, val, nm[i]);
}

static int from_rgb(const sf_atmosphere *src, int n, const double *nm, sf_atmosphere *out, sf_error *err) {
  const double rgb_nm[3] = {SF_RGB_LAMBDA_R_NM, SF_RGB_LAMBDA_G_NM, SF_RGB_LAMBDA_B_NM};
  double sigma_rgb[3], sigma[SF_MAX_CHANNELS];
  if (sf_recipe_ozone_cross_section(3, rgb_nm, 1e-3, sigma_rgb, err) ||   /* sigma in m² * 1e-3 * 1e3 */
      sf_recipe_ozone_cross_section(n, nm, 1e-3, sigma, err))
    return SF_ERR_INPUT;
  for (int i = 0; i < src->n_constituents; ++i) {
    const sf_constituent *c = &src->constituents[i];
    sf_constituent *o = &out->constituents[i];
    rgb_power_law_or_linear(c->scattering, n, nm, o->scattering);
    double num = 0.0, den = 0.0, norm = 0.0, misfit = 0.0;
    for (int k = 0; k < 3; ++k) {
      num += sigma_rgb[k] * c->absorption[k];
      den += sigma_rgb[k] * sigma_rgb[k];
      norm += c->absorption[k] * c->absorption[k];
    }
    double scale = num / den;
    for (int k = 0; k < 3; ++k) misfit += (c->absorption[k] - scale * sigma_rgb[k]) * (c->absorption[k] - scale * sigma_rgb[k]);
    /* Ozone's spectrum only for a triplet of ozone's shape (the default's
     * misses it by 4e-4): a grey absorber given ozone's Chappuis band had
     * missed its own values at 440 nm by 94 %. */
    if (!sf_constituent_scatters(c, 3) && norm > 0.0 && misfit <= SF_OZONE_SHAPE_TOLERANCE * SF_OZONE_SHAPE_TOLERANCE * norm) {
      for (int ch = 0; ch < n; ++ch) o->absorption[ch] = scale * sigma[ch];
    } else {
      rgb_power_law_or_linear(c->absorption, n, nm, o->absorption);
    }
  }
  const double lam[3] = {SF_RGB_LAMBDA_B_NM, SF_RGB_LAMBDA_G_NM, SF_RGB_LAMBDA_R_NM};
  const double albedo[3] = {src->ground_albedo[2], src->ground_albedo[1], src->ground_albedo[0]};
  for (int ch = 0; ch < n; ++ch) out->ground_albedo[ch] = piecewise_linear(3, lam, albedo, nm[ch]);
  /* the sun: ASTM G173 in 5 nm bins, scaled to the RGB sun's luminance */
  if (sf_recipe_solar_astm_g173(n, nm, SF_SPECTRAL_STEP_NM, 1.0, out->sun_irradiance, err)) return SF_ERR_INPUT;
  sf_cmf *cmf = malloc(sizeof *cmf);
  if (!cmf) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int rc = sf_cmf_load(cmf, err);
  if (rc == 0) {
    double xyz[3];
    sf_linear_srgb_to_xyz(src->sun_irradiance, xyz);
    double y = 0.0, step = n > 1 ? (nm[n - 1] - nm[0]) / (n - 1) : 1.0;
    for (int ch = 0; ch < n; ++ch) {
      double bar[3];
      sf_cmf_at(cmf, nm[ch], bar);
      y += bar[1] * out->sun_irradiance[ch] * step;
    }
    for (int ch = 0; ch < n; ++ch) out->sun_irradiance[ch] *= xyz[1] / y;
  }
  free(cmf);
  return rc;
}

static int from_spectral(const sf_atmosphere *src, int n, const double *nm, sf_atmosphere *out, sf_error *err) {
  int m = src->n_channels;
  const double *x = src->wavelengths_nm;
  if (nm[0] < x[0] || nm[n - 1] > x[m - 1])
    return sf_fail(err, SF_ERR_INPUT,
                   "atmosphere \"%s\": channels.wavelengths_nm cover %g-%g nm; the spectral reference needs "
                   "coefficients over %g-%g nm", src->name, x[0], x[m - 1], nm[0], nm[n - 1]);
  for (int ch = 0; ch < n; ++ch) {
    out->ground_albedo[ch] = piecewise_linear(m, x, src->ground_albedo, nm[ch]);
    out->sun_irradiance[ch] = piecewise_linear(m, x, src->sun_irradiance, nm[ch]);
    for (int i = 0; i < src->n_constituents; ++i) {
      out->constituents[i].scattering[ch] = piecewise_linear(m, x, src->constituents[i].scattering, nm[ch]);
      out->constituents[i].absorption[ch] = piecewise_linear(m, x, src->constituents[i].absorption, nm[ch]);
    }
  }
  return 0;
}

int sf_spectral_atmosphere(const sf_atmosphere *src, int n, const double *lambda_nm, sf_atmosphere *out,
                           sf_error *err) {
  if (n < 1 || n > SF_MAX_CHANNELS)
    return sf_fail(err, SF_ERR_INPUT, "spectral reference: %d wavelengths (1 to %d allowed)", n, SF_MAX_CHANNELS);
  *out = *src;
  for (int i = 0; i < out->n_constituents; ++i) {
    memset(out->constituents[i].scattering, 0, sizeof out->constituents[i].scattering);
    memset(out->constituents[i].absorption, 0, sizeof out->constituents[i].absorption);
  }
  memset(out->ground_albedo, 0, sizeof out->ground_albedo);
  memset(out->sun_irradiance, 0, sizeof out->sun_irradiance);
  memset(out->channel_names, 0, sizeof out->channel_names);
  memset(out->wavelengths_nm, 0, sizeof out->wavelengths_nm);
  int rc = src->spectral ? from_spectral(src, n, lambda_nm, out, err) : from_rgb(src, n, lambda_nm, out, err);
  if (rc) return rc;
  out->spectral = 1;
  out->n_channels = n;
  for (int ch = 0; ch < n; ++ch) {
    out->wavelengths_nm[ch] = lambda_nm[ch];
    snprintf(out->channel_names[ch], sizeof out->channel_names[ch], "%g", lambda_nm[ch]);
  }
  sf_atmosphere_finalize(out);
  return 0;
}

int sf_constituent_is_aerosol(const sf_constituent *c, int n_channels) {
  return sf_constituent_scatters(c, n_channels) && c->phase.kind != SF_PHASE_RAYLEIGH;
}

int sf_atmosphere_without_aerosols(const sf_atmosphere *in, sf_atmosphere *out) {
  *out = *in;
  int kept = 0, removed = 0;
  for (int i = 0; i < in->n_constituents; ++i) {
    if (sf_constituent_is_aerosol(&in->constituents[i], in->n_channels)) {
      ++removed;
      continue;
    }
    out->constituents[kept++] = in->constituents[i];
  }
  for (int i = kept; i < SF_MAX_CONSTITUENTS; ++i) memset(&out->constituents[i], 0, sizeof out->constituents[i]);
  out->n_constituents = kept;
  sf_atmosphere_finalize(out);
  return removed;
}

double sf_spectral_sun_luminance(const sf_atmosphere *spectral, const sf_cmf *cmf) {
  int n = spectral->n_channels;
  double step = n > 1 ? (spectral->wavelengths_nm[n - 1] - spectral->wavelengths_nm[0]) / (n - 1) : 1.0;
  double y = 0.0;
  for (int ch = 0; ch < n; ++ch) {
    double bar[3];
    sf_cmf_at(cmf, spectral->wavelengths_nm[ch], bar);
    y += bar[1] * spectral->sun_irradiance[ch] * step;
  }
  return y;
}
