#include "fit/published_sky.h"

#include <math.h>
#include <string.h>

#include "models/preetham.h"
#include "util/constants.h"

/* The model's three channels at one sun elevation: the state that depends
 * on the sun alone, then any view direction. */
typedef struct sun_state {
  sf_preetham_sky preetham;
  double coeffs[SF_HOSEK_DATASET_CHANNELS][SF_HOSEK_N_COEFFS], radiance[SF_HOSEK_DATASET_CHANNELS];
} sun_state;

static void state_at(const sf_published_sky *p, double elevation_rad, sun_state *s) {
  double e = fmin(fmax(elevation_rad, 0.0), 0.5 * SF_PI);
  if (p->preetham) {
    sf_preetham_sky_init(&s->preetham, p->turbidity, 0.5 * SF_PI - e);
    return;
  }
  for (int k = 0; k < SF_HOSEK_DATASET_CHANNELS; ++k) {
    sf_error err = {0};   /* in range: T in [1, 10], albedo and e clamped */
    sf_hosek_dataset_state(p->dataset, k, p->turbidity, p->albedo[k], e, s->coeffs[k], &s->radiance[k], &err);
  }
}

static void rgb_at(const sf_published_sky *p, const sun_state *s, double theta, double cos_theta, double gamma,
                   double rgb[3]) {
  if (p->preetham) {
    sf_preetham_sky_rgb(&s->preetham, theta, gamma, rgb);
    return;
  }
  for (int k = 0; k < 3; ++k) rgb[k] = s->radiance[k] * sf_hosek_f(s->coeffs[k], cos_theta, gamma);
}

static int channel_of(int n_channels, int k) { return n_channels == 3 ? k : 1; }

int sf_published_sky_fit(const sf_sky_samples *samples, int n_e, const sf_atmosphere *atm,
                         const sf_hosek_dataset *dataset, int preetham, sf_published_sky *out, double *rmse,
                         sf_error *err) {
  const int nk = atm->n_channels;
  memset(out, 0, sizeof *out);
  out->turbidity = NAN;
  for (int k = 0; k < SF_MAX_CHANNELS; ++k) out->scale[k] = NAN;
  *rmse = NAN;
  if (preetham && nk != 3)
    return sf_fail(err, SF_ERR_INPUT, "published Preetham: gives 3 channels (linear sRGB), the atmosphere has %d", nk);
  if (!preetham && !dataset) return sf_fail(err, SF_ERR_INPUT, "published Hosek: no dataset");
  sf_published_sky p = *out;
  p.preetham = preetham;
  p.dataset = dataset;
  p.n_channels = nk;
  for (int k = 0; k < SF_HOSEK_DATASET_CHANNELS; ++k)
    p.albedo[k] = fmin(fmax(atm->ground_albedo[nk == 3 ? k : 0], 0.0), 1.0);
  double best_sse = INFINITY;
  long n_total = 0;
  for (int e = 0; e < n_e; ++e) n_total += samples[e].n;
  for (double T = preetham ? 2.0 : 1.0; T <= 10.0 + 1e-9; T += 0.25) {
    p.turbidity = T;
    double md[SF_MAX_CHANNELS] = {0}, mm[SF_MAX_CHANNELS] = {0}, dd[SF_MAX_CHANNELS] = {0};
    for (int e = 0; e < n_e; ++e) {
      const sf_sky_samples *s = &samples[e];
      sun_state state;
      state_at(&p, s->elevation_rad, &state);
      for (int i = 0; i < s->n; ++i) {
        double m[3];
        rgb_at(&p, &state, s->theta[i], s->cos_theta[i], s->gamma[i], m);
        for (int k = 0; k < nk; ++k) {
          double model = m[channel_of(nk, k)], data = s->radiance[(size_t)i * nk + k];
          md[k] += model * data;
          mm[k] += model * model;
          dd[k] += data * data;
        }
      }
    }
    /* SSE after the best per-channel factor md / mm: dd - md^2 / mm */
    double sse = 0;
    for (int k = 0; k < nk; ++k) sse += dd[k] - (mm[k] > 0 ? md[k] * md[k] / mm[k] : 0.0);
    if (sse < best_sse) {
      best_sse = sse;
      *out = p;
      for (int k = 0; k < nk; ++k) out->scale[k] = mm[k] > 0 ? md[k] / mm[k] : 0.0;
    }
  }
  *rmse = sqrt(fmax(best_sse, 0.0) / (double)(n_total * nk));
  return SF_OK;
}

void sf_published_sky_radiance(const sf_published_sky *p, double theta, double gamma, double elevation_rad,
                               double *out) {
  sun_state state;
  state_at(p, elevation_rad, &state);
  double m[3];
  rgb_at(p, &state, theta, cos(theta), gamma, m);
  for (int k = 0; k < p->n_channels; ++k) out[k] = p->scale[k] * m[channel_of(p->n_channels, k)];
}
