/* The double-precision models that emitted headers (codegen/) approximate,
 * as callbacks of one signature for the tests that run those headers in
 * float32: out = the model in double at the float inputs p exactly as the
 * header gets them (p[0..] in the header function's argument order).
 *   baselines:  codegen/baselines.h sf_baseline_transmittance (full ray,
 *               first t km, [t0, t1]);
 *   sigmoid:    the model's own full ray (sf_sigmoid_model_eval); segments
 *               as models/sigmoid_transmittance.h states them, with double
 *               ray geometry, the whole ray from the ray's end on;
 *   hosek, preetham: sf_sky_radiance_clamped (codegen/emit_sky.h);
 *   mlp:        models/mlp_sky.h in double;
 *   naive and raymarched skies: models/sky_naive.h, models/sky_raymarched.h;
 *   spectral4:  the 3x4 matrices and constants of the weights file.
 * Shared by tests/test_float32_sweep.c and tests/test_codegen_headers.c. */
#ifndef SKYFIT_TESTS_EMITTED_DOUBLE_MODELS_H
#define SKYFIT_TESTS_EMITTED_DOUBLE_MODELS_H

#include <math.h>
#include <string.h>

#include "codegen/baselines.h"
#include "codegen/fitted_part.h"
#include "models/ray_geometry.h"
#include "models/sky_naive.h"
#include "models/sky_raymarched.h"

typedef void (*emitted_double_fn)(const void *ctx, const float *p, double *out);

/* ---- baselines: ctx = const sf_baseline * ---- */
static inline void emitted_baseline_full(const void *ctx, const float *p, double *out) {
  sf_baseline_transmittance(ctx, p[0], p[1], 0.0, INFINITY, out);
}
static inline void emitted_baseline_segment(const void *ctx, const float *p, double *out) {
  sf_baseline_transmittance(ctx, p[0], p[1], 0.0, p[2], out);
}
static inline void emitted_baseline_between(const void *ctx, const float *p, double *out) {
  sf_baseline_transmittance(ctx, p[0], p[1], p[2], p[3], out);
}

/* ---- sigmoid: ctx = const sf_sigmoid_emit * ---- */
static inline double emitted_sigmoid_log_top(const sf_sigmoid_model *m, int k, double h, double mu) {
  double s = 0.0;
  for (int c = 0; c < m->n_constituents; ++c) s += sf_sigmoid_log_transmittance(m->a[c][k], h, mu);
  return s;
}
static inline void emitted_sigmoid_full(const void *ctx, const float *p, double *out) {
  sf_sigmoid_model_eval(&((const sf_sigmoid_emit *)ctx)->model, p[0], p[1], out);
}
static inline void emitted_sigmoid_segment(const void *ctx, const float *p, double *out) {
  const sf_sigmoid_model *m = &((const sf_sigmoid_emit *)ctx)->model;
  double R = m->bottom_radius_km, Rt = m->top_radius_km;
  double h = fmax(p[0], 0.0), mu = fmin(fmax(p[1], -1.0), 1.0), d = p[2];
  int n = m->n_channels;
  for (int k = 0; k < n; ++k) out[k] = 1.0;
  double r = R + h, t0, t1;
  int ground;
  if (!sf_ray_atmosphere_segment(r, mu, R, Rt, &t0, &t1, &ground)) return;
  if (r > Rt) {   /* a viewer in space starts where the ray enters */
    mu = fmin(fmax((r * mu + t0) / Rt, -1.0), 1.0);
    h = Rt - R;
    r = Rt;
    d -= t0;
    t1 -= t0;
  }
  if (!(d > 0.0)) return;
  double a[SF_MAX_CHANNELS], b[SF_MAX_CHANNELS];
  sf_sigmoid_model_eval(m, h, mu, a);
  if (d >= t1) {   /* the whole ray */
    for (int k = 0; k < n; ++k) out[k] = a[k];
    return;
  }
  double r_d = sf_ray_radius_at(r, mu, d);
  double mu_d = fmin(fmax((r * mu + d) / r_d, -1.0), 1.0), h_d = fmin(fmax(r_d - R, 0.0), Rt - R);
  sf_sigmoid_model_eval(m, h_d, mu_d, b);
  for (int k = 0; k < n; ++k) {
    /* ground hit: eq. 43 with reversed rays (seed 000 §9.6.3) */
    double la = ground ? emitted_sigmoid_log_top(m, k, h_d, -mu_d) : log(a[k]);
    double lb = ground ? emitted_sigmoid_log_top(m, k, h, -mu) : log(b[k]);
    out[k] = exp(fmin(la - lb, 0.0));
  }
}

/* ---- hosek / preetham: ctx = const sf_elevation_sky_model * ---- */
static inline void emitted_sky(const void *ctx, const float *p, double *out) {
  sf_sky_radiance_clamped(ctx, p[0], p[1], p[2], out);
}

/* ---- MLP: transmittance ctx = const sf_mlp_sky *, scattering ctx = const sf_fitted_model * ---- */
static inline void emitted_mlp_t(const void *ctx, const float *p, double *out) {
  sf_mlp_transmittance(ctx, p[0], p[1], out);
}
static inline void emitted_mlp_t_top(const void *ctx, const float *p, double *out) {
  sf_mlp_transmittance_top(ctx, p[0], p[1], out);
}
static inline void emitted_mlp_t_segment(const void *ctx, const float *p, double *out) {
  sf_mlp_transmittance_segment(ctx, p[0], p[1], p[2], out);
}
static inline void emitted_mlp_s(const void *ctx, const float *p, double *out) {
  sf_mlp_scattering(&((const sf_fitted_model *)ctx)->mlp, p[0], p[1], p[2], p[3], out);
}
static inline void emitted_mlp_s_segment(const void *ctx, const float *p, double *out) {
  const sf_fitted_model *m = ctx;
  sf_mlp_scattering_segment(&m->mlp, m->transmittance, p[0], p[1], p[2], p[3], p[4], out);
}

/* ---- the sky-radiance baselines: ctx = the model ---- */
static inline void emitted_naive_sky(const void *ctx, const float *p, double *out) {
  sf_sky_naive_radiance(ctx, p[0], p[1], p[2], p[3], out);
}
static inline void emitted_raymarched_sky(const void *ctx, const float *p, double *out) {
  sf_sky_raymarched_radiance(ctx, p[0], p[1], p[2], p[3], out);
}

/* ---- spectral4: ctx = const sf_spectral4_emit *, p = the vec4 or the index ---- */
static inline void emitted_spectral_matrix(const double m[3][4], const float *p, int absolute, double *out) {
  for (int i = 0; i < 3; ++i) {
    out[i] = 0.0;
    for (int j = 0; j < 4; ++j) out[i] += absolute ? fabs(m[i][j] * p[j]) : m[i][j] * p[j];
  }
}
static inline void emitted_spectral_srgb(const void *ctx, const float *p, double *out) {
  emitted_spectral_matrix(((const sf_spectral4_emit *)ctx)->to_linear_srgb, p, 0, out);
}
/* sum_j |M_ij L_j|: what the float sum may cancel */
static inline void emitted_spectral_srgb_abs(const void *ctx, const float *p, double *out) {
  emitted_spectral_matrix(((const sf_spectral4_emit *)ctx)->to_linear_srgb, p, 1, out);
}
static inline void emitted_spectral_xyz(const void *ctx, const float *p, double *out) {
  emitted_spectral_matrix(((const sf_spectral4_emit *)ctx)->to_xyz, p, 0, out);
}
static inline void emitted_spectral_xyz_abs(const void *ctx, const float *p, double *out) {
  emitted_spectral_matrix(((const sf_spectral4_emit *)ctx)->to_xyz, p, 1, out);
}
static inline void emitted_spectral_per_constituent(const sf_spectral4_emit *s, const double (*v)[4], float index,
                                                     double *out) {
  int c = (int)index;
  for (int j = 0; j < 4; ++j) out[j] = c >= 0 && c < s->n_constituents ? v[c][j] : 0.0;
}
static inline void emitted_spectral_scattering(const void *ctx, const float *p, double *out) {
  const sf_spectral4_emit *s = ctx;
  emitted_spectral_per_constituent(s, s->scattering, p[0], out);
}
static inline void emitted_spectral_absorption(const void *ctx, const float *p, double *out) {
  const sf_spectral4_emit *s = ctx;
  emitted_spectral_per_constituent(s, s->absorption, p[0], out);
}
static inline void emitted_spectral_wavelengths(const void *ctx, const float *p, double *out) {
  (void)p;
  memcpy(out, ((const sf_spectral4_emit *)ctx)->wavelengths_nm, 4 * sizeof(double));
}
static inline void emitted_spectral_sun(const void *ctx, const float *p, double *out) {
  (void)p;
  memcpy(out, ((const sf_spectral4_emit *)ctx)->sun_irradiance, 4 * sizeof(double));
}
static inline void emitted_spectral_albedo(const void *ctx, const float *p, double *out) {
  (void)p;
  memcpy(out, ((const sf_spectral4_emit *)ctx)->ground_albedo, 4 * sizeof(double));
}

#endif
