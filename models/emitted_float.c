#include "models/emitted_float.h"

#include <math.h>
#include <string.h>

int sf_emitted_ray_enter_f(float R, float h_top, float *h, float *mu, float *mu_s, float nu) {
  if (*h <= h_top) return 1;
  float r = R + *h, Rt = R + h_top, disc;
  if (r > 2.0f * Rt) {   /* from the closest approach: (h_top - h)(Rt + r) + (r mu)^2 cancels far out */
    float p = r * sqrtf(fmaxf((1.0f - *mu) * (1.0f + *mu), 0.0f));
    disc = (Rt - p) * (Rt + p);
  } else {
    disc = (h_top - *h) * (Rt + r) + (r * *mu) * (r * *mu);
  }
  if (!(*mu < 0.0f) || !(disc > 0.0f)) return 0;
  float root = sqrtf(disc);
  if (mu_s) *mu_s = fminf(fmaxf((r * (*mu_s - *mu * nu) - root * nu) / Rt, -1.0f), 1.0f);
  *mu = fminf(fmaxf(-root / Rt, -1.0f), 1.0f);
  *h = h_top;
  return 1;
}

void sf_emitted_sphere_hits_f(float r, float mu, float R, float R_minus_r, float *near, float *far) {
  float disc = R_minus_r * (R + r) + (r * mu) * (r * mu);
  if (disc < 0.0f) {
    *near = 1.0f;
    *far = -1.0f;
    return;
  }
  float root = sqrtf(disc);
  float q = -(r * mu + (mu >= 0.0f ? root : -root));
  float b = q != 0.0f ? -R_minus_r * (r + R) / q : 0.0f;
  *near = q < b ? q : b;
  *far = q < b ? b : q;
}

void sf_emitted_air_clip_f(float bottom, float thickness, float h, float mu, float *a, float *b) {
  float r = bottom + h, s0, s1, g0, g1;
  *a = *b = 0.0f;
  sf_emitted_sphere_hits_f(r, mu, bottom + thickness, thickness - h, &s0, &s1);
  if (s0 > s1) return;
  float lo = 0.0f, hi = 3.4e38f;
  if (s0 > lo) lo = s0;
  if (s1 < hi) hi = s1;
  sf_emitted_sphere_hits_f(r, mu, bottom, -h, &g0, &g1);
  if (g0 < g1) {
    if (lo <= g0) {
      if (g0 < hi) hi = g0;
    } else if (lo < g1) {
      lo = g1;
    }
  }
  *a = lo;
  *b = hi > lo ? hi : lo;
}

void sf_density_f_make(const sf_constituent *c, sf_density_f *out) {
  memset(out, 0, sizeof *out);
  out->n_layers = c->n_layers;
  double top = 0.0;
  for (int l = 0; l < c->n_layers; ++l) {
    top += c->layers[l].width_km;
    out->layer_top[l] = (float)top;
    out->linear[l] = (float)c->layers[l].linear_per_km;
    out->constant[l] = (float)c->layers[l].constant;
    out->exp_term[l] = (float)c->layers[l].exp_term;
    out->exp_scale[l] = (float)c->layers[l].exp_scale_per_km;
  }
}

float sf_density_f_at(const sf_density_f *d, float h) {
  if (d->n_layers < 1) return 0.0f;
  int l = 0;
  while (l + 1 < d->n_layers && !(h < d->layer_top[l])) ++l;
  /* the emitted sum, left to right, its zero terms left out (as the
   * emitter leaves them out: 0 e^(large) would be NaN) */
  float v = 0.0f;
  if (d->linear[l] != 0.0f) v += d->linear[l] * h;
  if (d->constant[l] != 0.0f) v += d->constant[l];
  if (d->exp_term[l] != 0.0f) v += d->exp_term[l] * expf(d->exp_scale[l] * h);
  return fminf(fmaxf(v, 0.0f), 1.0f);
}
