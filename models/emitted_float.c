#include "models/emitted_float.h"

#include <math.h>
#include <string.h>

#include "models/ray_geometry.h"

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

void sf_emitted_air_clip_between_f(float bottom, float thickness, float h, float mu, float t0, float t1,
                                   float seg[4]) {
  float r = bottom + h, s0, s1, g0, g1;
  sf_emitted_sphere_hits_f(r, mu, bottom + thickness, thickness - h, &s0, &s1);
  seg[0] = seg[1] = t0;
  seg[2] = seg[3] = h;
  if (!(t1 > t0) || s0 > s1) return;
  float a = t0, b = t1, ha = -1.0f, hb = -1.0f;
  if (s0 > a) a = s0, ha = thickness;
  if (s1 < b) b = s1, hb = thickness;
  sf_emitted_sphere_hits_f(r, mu, bottom, -h, &g0, &g1);
  if (g0 < g1) {
    if (a <= g0) {
      if (g0 < b) b = g0, hb = 0.0f;
    } else if (a < g1) {
      a = g1;
      ha = 0.0f;
    }
  }
  seg[0] = seg[1] = a;
  if (!(b > a)) return;
  seg[1] = b;
  seg[2] = ha < 0.0f ? sf_ray_altitude_at_f(bottom, h, mu, a) : ha;
  seg[3] = hb < 0.0f ? sf_ray_altitude_at_f(bottom, h, mu, b) : hb;
}

float sf_emitted_shell_chord_f(float bottom, float lo, float hi, float h, float mu, float t0, float t1) {
  float r = bottom + h, o0, o1, i0, i1;
  sf_emitted_sphere_hits_f(r, mu, bottom + hi, hi - h, &o0, &o1);
  sf_emitted_sphere_hits_f(r, mu, bottom + lo, lo - h, &i0, &i1);
  float a = fmaxf(t0, o0), b = fminf(t1, o1);
  float chord = o0 <= o1 && b > a ? b - a : 0.0f;
  a = fmaxf(t0, i0);
  b = fminf(t1, i1);
  if (i0 <= i1 && b > a) chord -= b - a;
  return chord > 0.0f ? chord : 0.0f;
}

float sf_emitted_expm1_f(float x) {
  if (fabsf(x) < 0.1f)
    return x * (1.0f + x * (0.5f + x * ((float)(1.0 / 6.0) +
                                        x * ((float)(1.0 / 24.0) + x * ((float)(1.0 / 120.0) +
                                                                        x * (float)(1.0 / 720.0))))));
  return expf(x) - 1.0f;
}

float sf_emitted_flat_up_diff_f(float H, float h_a, float r_a, float s_a, float dh, float ds) {
  float r_b = r_a + dh, s_b = s_a + ds;
  float A_a = H * (2.0f * r_a + H), A_b = H * (2.0f * r_b + H);
  float q_a = sqrtf(A_a + s_a * s_a), q_b = sqrtf(A_b + s_b * s_b);
  float g_a = A_a / (q_a + s_a), g_b = A_b / (q_b + s_b);
  float dg = (ds * (g_a + g_b) - 2.0f * H * dh) / (q_a + q_b);
  return expf(-h_a / H) * (dg - g_b * sf_emitted_expm1_f(-dh / H));
}

int sf_sky_constants_f_make(const sf_atmosphere *atm, sf_sky_constants_f *out) {
  memset(out, 0, sizeof *out);
  if (atm->n_channels > 4) return -1;
  out->n_constituents = atm->n_constituents;
  out->n_channels = atm->n_channels;
  out->bottom = (float)atm->bottom_radius_km;
  out->thickness = (float)(atm->top_radius_km - atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    for (int k = 0; k < atm->n_channels; ++k) {
      out->scattering[i][k] = (float)atm->constituents[i].scattering[k];
      out->extinction[i][k] = (float)sf_extinction(atm, i, k);
    }
    out->phase[i] = atm->constituents[i].phase;
  }
  for (int k = 0; k < atm->n_channels; ++k) out->sun[k] = (float)atm->sun_irradiance[k];
  return 0;
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
