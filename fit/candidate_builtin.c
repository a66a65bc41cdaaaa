#include "fit/candidate_builtin.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/baselines.h"
#include "data/table.h"
#include "models/baseline_float.h"
#include "models/optical_depth.h"
#include "models/optical_depth_chapman.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_raymarch.h"
#include "models/optical_depth_spline.h"
#include "models/optical_depth_taylor.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

/* ---- reference transmittance: exact optical depth ---- */

static void reference_transmittance_eval(const void *ctx, const double *in, double *out) {
  const sf_atmosphere *atm = ctx;
  double depth[SF_MAX_CONSTITUENTS];
  sf_optical_depth_ray(atm, in[0], in[1], SF_RAY_END_NEAREST, depth);
  sf_transmittance_from_depth(atm, depth, out);
}

/* The segment from the viewer to distance in[2] (models/view_ray.h: a
 * viewer above the top from where its ray enters), the reference of the
 * models' segment functions: exp(-extinction x the exact optical depth of
 * the segment). NaN where the segment would pass below the ground. */
static void reference_transmittance_segment(const void *ctx, const double *in, double *out) {
  const sf_atmosphere *atm = ctx;
  double depth[SF_MAX_CONSTITUENTS] = {0}, mu_s;
  sf_view_ray ray;
  const char *why = NULL;
  if (sf_view_ray_make_at_entry(atm, in[0], in[1], 1.0, in[1], SF_RAY_END_NEAREST, fmax(in[2], 0.0), &ray, &mu_s,
                                &why) != 0) {
    for (int k = 0; k < atm->n_channels; ++k) out[k] = NAN;
    return;
  }
  if (ray.t1 > ray.t0) sf_optical_depth_segment(atm, ray.r, ray.mu, ray.t0, ray.t1, depth);
  sf_transmittance_from_depth(atm, depth, out);
}

int sf_candidate_reference_transmittance(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  (void)err;
  sf_candidate_init(out, SF_CANDIDATE_TRANSMITTANCE, SF_ROLE_REFERENCE, "reference",
                    "Reference (exact optical depth)");
  snprintf(out->description, sizeof out->description,
           "Optical depth by adaptive Gauss-Kronrod quadrature split at the closest approach and "
           "the density kinks (models/optical_depth.h), T = exp(-sum beta_e tau).");
  out->n_channels = atm->n_channels;
  out->eval = reference_transmittance_eval;
  out->eval_segment = reference_transmittance_segment;
  out->ctx = (void *)atm;
  return SF_OK;
}

/* ---- table lookups ---- */

static void table_transmittance_eval(const void *ctx, const double *in, double *out) {
  sf_sky_transmittance(ctx, in[0], in[1], out);
}

static void table_radiance_eval(const void *ctx, const double *in, double *out) {
  const sf_sky_tables *sky = ctx;
  sf_sky_sample s;
  sf_sky_lookup(sky, in[0], in[1], in[2], in[3], &s);
  memcpy(out, s.radiance, sizeof(double) * (size_t)sky->atm->n_channels);
}

/* The sky's segment from the viewer to distance in[4], eq. 44 from the
 * tables: L(viewer) - T(viewer -> end) L(end), with T from the exact optical
 * depth of the segment and L(end) the tables' at the end looking on along
 * the ray (the same ray: its sun cosine moved with it); a segment that
 * reaches the ray's end (the ground or the top) is the whole ray, L(end)
 * being 0 there. The reference of the sky models' segment functions.
 * Not clamped at 0: the tables' own eq. 44. */
static void table_radiance_segment(const void *ctx, const double *in, double *out) {
  const sf_sky_tables *sky = ctx;
  const sf_atmosphere *atm = sky->atm;
  int n = atm->n_channels;
  double mu = fmax(-1.0, fmin(1.0, in[1])), mu_s = fmax(-1.0, fmin(1.0, in[2]));
  double nu = sf_clamp_nu(mu, mu_s, in[3]), d = fmax(in[4], 0.0);
  sf_sky_sample whole;
  sf_sky_lookup(sky, in[0], mu, mu_s, nu, &whole);
  for (int k = 0; k < n; ++k) out[k] = 0.0;
  sf_view_ray ray, full;
  double mu_s_e;
  const char *why = NULL;
  if (sf_view_ray_make_at_entry(atm, in[0], mu, mu_s, nu, SF_RAY_END_NEAREST, d, &ray, &mu_s_e, &why) != 0 ||
      sf_view_ray_make_at_entry(atm, in[0], mu, mu_s, nu, SF_RAY_END_NEAREST, -1.0, &full, &mu_s_e, &why) != 0) {
    for (int k = 0; k < n; ++k) out[k] = NAN;
    return;
  }
  if (!(ray.t1 > ray.t0)) return;   /* no air on the segment */
  if (ray.t1 >= full.t1) {          /* the whole ray */
    memcpy(out, whole.radiance, sizeof(double) * (size_t)n);
    return;
  }
  double depth[SF_MAX_CONSTITUENTS] = {0}, T[SF_MAX_CHANNELS];
  sf_optical_depth_segment(atm, ray.r, ray.mu, ray.t0, ray.t1, depth);
  sf_transmittance_from_depth(atm, depth, T);
  double r_d = sf_ray_radius_at(ray.r, ray.mu, ray.t1);
  double h_d = fmax(sf_ray_altitude_at(atm->bottom_radius_km, ray.r - atm->bottom_radius_km, ray.mu, ray.t1), 0.0);
  double mu_d = fmax(-1.0, fmin(1.0, (ray.r * ray.mu + ray.t1) / r_d));
  double mu_s_d = fmax(-1.0, fmin(1.0, (ray.r * mu_s_e + ray.t1 * nu) / r_d));
  sf_sky_sample end;
  sf_sky_lookup(sky, h_d, mu_d, mu_s_d, nu, &end);
  for (int k = 0; k < n; ++k) out[k] = whole.radiance[k] - T[k] * end.radiance[k];
}

static long table_floats(const sf_table *t) {
  return t ? (long)sf_table_desc_points(&t->desc) * t->desc.n_channels : 0;
}

int sf_candidate_table_transmittance(const sf_sky_tables *sky, sf_candidate *out, sf_error *err) {
  if (!sky->transmittance) return sf_fail(err, SF_ERR_INTERNAL, "no transmittance table");
  sf_candidate_init(out, SF_CANDIDATE_TRANSMITTANCE, SF_ROLE_LOOKUP, "table",
                    "Transmittance table lookup");
  snprintf(out->description, sizeof out->description,
           "The reference transmittance table (%s parameterisation, %dx%d), interpolated "
           "bilinearly; rays to the ground are a ratio of two lookups (Bruneton 2017).",
           sf_parameterization_name(sky->params.kind), sky->params.res.transmittance_mu,
           sky->params.res.transmittance_h);
  out->n_channels = sky->atm->n_channels;
  out->n_params = table_floats(sky->transmittance);
  out->constant_bytes = out->n_params * 4;
  out->eval = table_transmittance_eval;
  out->ctx = (void *)sky;
  return SF_OK;
}

int sf_candidate_table_sky_radiance(const sf_sky_tables *sky, sf_candidate *out, sf_error *err) {
  if (!sky->transmittance || !sky->multiple) return sf_fail(err, SF_ERR_INTERNAL, "no scattering tables");
  sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_REFERENCE, "reference",
                    "Reference (precomputed tables)");
  snprintf(out->description, sizeof out->description,
           "Single scattering per constituent with its phase function plus all multiple-scattering "
           "orders, from the %s-parameterised tables (%dx%dx%dx%d), interpolated multilinearly (under a "
           "low sun the single scattering divided by the ray's sunlit air, interpolated and multiplied back).",
           sf_parameterization_name(sky->params.kind), sky->params.res.scattering_h,
           sky->params.res.scattering_mu, sky->params.res.scattering_mu_s,
           sky->params.res.scattering_nu);
  out->n_channels = sky->atm->n_channels;
  long floats = table_floats(sky->transmittance) + table_floats(sky->multiple);
  for (int i = 0; i < sky->n_single; ++i) floats += table_floats(sky->single[i]);
  out->n_params = floats;
  out->constant_bytes = floats * 4;
  out->eval = table_radiance_eval;
  out->eval_segment = table_radiance_segment;
  out->ctx = (void *)sky;
  return SF_OK;
}

/* ---- analytic baselines ---- */

typedef struct baseline_ctx {
  const sf_atmosphere *atm;
  sf_transmittance_baseline kind;
  int steps;
  sf_flat_model flat;
  sf_spline_model spline;   /* SF_TB_SPLINE: its meshes */
  sf_baseline emitted;      /* codegen/baselines.h form */
  /* float32 copy for the timed naive raymarch */
  float bottom_f, top_f;
  int n_constituents, n_channels;
  int n_layers[SF_MAX_CONSTITUENTS];
  float layer_top_f[SF_MAX_CONSTITUENTS][SF_MAX_LAYERS];
  float layer_f[SF_MAX_CONSTITUENTS][SF_MAX_LAYERS][4];   /* exp_term, exp_scale, linear, constant */
  float extinction_f[SF_MAX_CONSTITUENTS][4];
  /* Chapman, Taylor, flat: their emitted code in float32 (what is timed) */
  sf_baseline_f analytic_f;
} baseline_ctx;

static void baseline_depth(const baseline_ctx *b, const sf_view_ray *ray, double *depth) {
  const sf_atmosphere *atm = b->atm;
  switch (b->kind) {
    case SF_TB_NAIVE:
      sf_optical_depth_raymarch_segment(atm, ray->r, ray->mu, ray->t0, ray->t1, b->steps,
                                        SF_RAYMARCH_MIDPOINT, depth);
      return;
    case SF_TB_FLAT:
      sf_optical_depth_flat_segment(atm, ray->r, ray->mu, ray->t0, ray->t1, &b->flat, depth);
      return;
    case SF_TB_SPLINE:   /* the eq. 59 shells included */
      sf_optical_depth_spline_segment(&b->spline, ray->r, ray->mu, ray->t0, ray->t1, depth);
      return;
    case SF_TB_CHAPMAN:
      sf_optical_depth_chapman_segment(atm, ray->r, ray->mu, ray->t0, ray->t1, depth);
      break;
    case SF_TB_TAYLOR:
      sf_optical_depth_taylor_segment(atm, ray->r, ray->mu, ray->t0, ray->t1, SF_TAYLOR_A,
                                      SF_TAYLOR_B, depth);
      break;
  }
  /* Chapman and Taylor: non-exponential constituents become the flat
   * model's constant shell (seed 000 §10.5, eq. 59). */
  for (int i = 0; i < atm->n_constituents; ++i)
    if (b->flat.is_shell[i])
      depth[i] = sf_flat_shell_chord(atm->bottom_radius_km + b->flat.shell_bottom_km[i],
                                     atm->bottom_radius_km + b->flat.shell_top_km[i], ray->r,
                                     ray->mu, ray->t0, ray->t1);
}

/* The ray to distance (< 0: its end). */
static void baseline_between(const baseline_ctx *b, double h_km, double mu, double distance, double *out) {
  sf_view_ray ray;
  const char *why = NULL;
  double depth[SF_MAX_CONSTITUENTS] = {0}, mu_s_entry;
  /* a viewer above the top from where its ray enters, as the emitted code
   * (codegen/baselines.c) */
  if (sf_view_ray_make_at_entry(b->atm, h_km, mu, 1.0, mu, SF_RAY_END_NEAREST, distance, &ray, &mu_s_entry,
                                &why) == 0 &&
      ray.t1 > ray.t0)
    baseline_depth(b, &ray, depth);
  sf_transmittance_from_depth(b->atm, depth, out);
}

static void baseline_eval(const void *ctx, const double *in, double *out) {
  baseline_between(ctx, in[0], in[1], -1.0, out);
}

/* skyfit_<name>_transmittance_segment: the same model on [0, t_km]. */
static void baseline_segment(const void *ctx, const double *in, double *out) {
  baseline_between(ctx, in[0], in[1], fmax(in[2], 0.0), out);
}

/* Not models/emitted_float.h's sf_density_f_at: this is the report's cost
 * unit (SPEC §12), and its arithmetic stays as every earlier report timed
 * it (the emitted sum's order and fminf/fmaxf made it 37 % slower). */
static float density_f(const baseline_ctx *b, int c, float h) {
  if (h > b->top_f - b->bottom_f) return 0.0f;
  int l = 0;
  while (l + 1 < b->n_layers[c] && h >= b->layer_top_f[c][l]) ++l;
  const float *p = b->layer_f[c][l];
  float v = p[0] * expf(p[1] * h) + p[2] * h + p[3];
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

/* The naive raymarch in float32, as a shader would run it: what the cost
 * unit of SPEC §12 times. */
static void naive_eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const baseline_ctx *b = ctx;
  const int nc = b->n_channels;
  for (size_t p = 0; p < n; ++p) {
    float r = b->bottom_f + in[2 * p], mu = in[2 * p + 1];
    float t0, t1;
    int ground;
    float depth[SF_MAX_CONSTITUENTS] = {0};
    if (sf_ray_atmosphere_segment_f(r, mu, b->bottom_f, b->top_f, &t0, &t1, &ground) && t1 > t0) {
      float dt = (t1 - t0) / (float)b->steps;
      for (int k = 0; k < b->steps; ++k) {
        float t = t0 + ((float)k + 0.5f) * dt;
        float h = sqrtf(fmaxf(r * r + 2.0f * r * mu * t + t * t, 0.0f)) - b->bottom_f;
        for (int c = 0; c < b->n_constituents; ++c) depth[c] += density_f(b, c, h) * dt;
      }
    }
    for (int ch = 0; ch < nc; ++ch) {
      float tau = 0.0f;
      for (int c = 0; c < b->n_constituents; ++c) tau += b->extinction_f[c][ch] * depth[c];
      out[(size_t)nc * p + (size_t)ch] = expf(-tau);
    }
  }
}

/* Chapman, Taylor, flat and the spline in float32 as emitted (models/baseline_float.h). */
static void analytic_eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const baseline_ctx *b = ctx;
  for (size_t p = 0; p < n; ++p)
    sf_baseline_transmittance_f(&b->analytic_f, in[2 * p], in[2 * p + 1], out + (size_t)b->n_channels * p);
}

static void fill_float_copy(baseline_ctx *b) {
  const sf_atmosphere *atm = b->atm;
  b->bottom_f = (float)atm->bottom_radius_km;
  b->top_f = (float)atm->top_radius_km;
  b->n_constituents = atm->n_constituents;
  b->n_channels = atm->n_channels;
  for (int c = 0; c < atm->n_constituents; ++c) {
    const sf_constituent *k = &atm->constituents[c];
    b->n_layers[c] = k->n_layers;
    double top = 0.0;
    for (int l = 0; l < k->n_layers; ++l) {
      top += k->layers[l].width_km;
      b->layer_top_f[c][l] = (float)top;
      b->layer_f[c][l][0] = (float)k->layers[l].exp_term;
      b->layer_f[c][l][1] = (float)k->layers[l].exp_scale_per_km;
      b->layer_f[c][l][2] = (float)k->layers[l].linear_per_km;
      b->layer_f[c][l][3] = (float)k->layers[l].constant;
    }
    for (int ch = 0; ch < atm->n_channels && ch < 4; ++ch)
      b->extinction_f[c][ch] = (float)sf_extinction(atm, c, ch);
  }
}

/* name, label and description, in sf_transmittance_baseline's order */
static const char *const baseline_texts[][3] = {
    {"naive", "Naive raymarch",
     "Midpoint rule with equal steps along the ray for every constituent (seed 000 §11.2.6); the cost unit of "
     "the report."},
    {"chapman", "Schuler's Chapman approximation",
     "Schuler 2012 Chapman-function approximation per exponential constituent (seed 000 eq. 22-25); other "
     "constituents as a constant shell (seed 000 eq. 59)."},
    {"taylor", "Galaj's Taylor transmittance",
     "Taylor expansion of the altitude along the ray, a = b = 0.45 (seed 002 eq. 12-17); other constituents as "
     "a constant shell (seed 000 eq. 59)."},
    {"flat", "Leenman's flat model",
     "Homogeneous shell of one scale height above each point (seed 000 eq. 48-53), a descending ray's about its "
     "closest point (Fig. 11); ozone as a constant-density shell (eq. 59)."},
    {"spline", "Galaj's spline transmittance",
     "Tensor-product cubic Hermite meshes of the optical-depth integrand, 50 x 20 points per region (seed 002 "
     "IV.E, Table 3); other constituents as a constant shell (seed 000 eq. 59)."},
};

static void emit_baseline(struct sf_code_writer *w, const void *model) { sf_emit_baseline(w, model); }

static long baseline_constants(const sf_atmosphere *atm, const baseline_ctx *b) {
  long n = 2;
  for (int c = 0; c < atm->n_constituents; ++c) {
    n += atm->n_channels;
    if (b->kind == SF_TB_NAIVE) n += 5L * atm->constituents[c].n_layers;
    else n += 2;
    /* the spline's meshes: value and three derivatives per node */
    if (b->kind == SF_TB_SPLINE && b->spline.is_exponential[c]) {
      const sf_spline_grid *miss = &b->spline.miss[c], *hit = &b->spline.hit[c];
      n += 4L * ((long)miss->n_x * miss->n_d + (long)hit->n_x * hit->n_d);
    }
  }
  return n;
}

static void free_baseline(void *ctx) {
  baseline_ctx *b = ctx;
  sf_spline_model_free(&b->spline);
  sf_baseline_f_free(&b->analytic_f);
  free(b);
}

int sf_candidate_transmittance_baseline(const sf_atmosphere *atm, sf_transmittance_baseline kind,
                                        int steps, sf_candidate *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  if (kind == SF_TB_NAIVE && steps < 1) return sf_fail(err, SF_ERR_INPUT, "naive raymarch: steps must be >= 1");
  if (kind != SF_TB_NAIVE && sf_atmosphere_exponential_count(atm) == 0)
    return sf_fail(err, SF_ERR_INPUT, "%s (%s): the analytic optical depths need an exponential constituent; %s has none",
                   baseline_texts[kind][0], baseline_texts[kind][1], atm->name);
  baseline_ctx *b = calloc(1, sizeof *b);
  if (!b) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  b->atm = atm;
  b->kind = kind;
  b->steps = steps;
  sf_flat_model_make(atm, SF_FLAT_DESCENT_CLOSEST, &b->flat);
  if (kind == SF_TB_SPLINE &&
      sf_spline_model_make(atm, SF_SPLINE_HEIGHT_POINTS, SF_SPLINE_DISTANCE_POINTS, &b->spline) != 0) {
    free(b);
    return sf_fail(err, SF_ERR_INTERNAL, "spline baseline: out of memory");
  }
  fill_float_copy(b);
  char name[48], label[96];
  if (kind == SF_TB_NAIVE) {
    snprintf(name, sizeof name, "naive%d", steps);
    snprintf(label, sizeof label, "Naive raymarch, %d steps", steps);
  } else {
    snprintf(name, sizeof name, "%s", baseline_texts[kind][0]);
    snprintf(label, sizeof label, "%s", baseline_texts[kind][1]);
  }
  const char *what = baseline_texts[kind][2];
  sf_candidate_init(out, SF_CANDIDATE_TRANSMITTANCE, SF_ROLE_BASELINE, name, label);
  snprintf(out->description, sizeof out->description, "%s", what);
  static const sf_baseline_kind emitted_kind[] = {SF_BASELINE_NAIVE, SF_BASELINE_CHAPMAN, SF_BASELINE_TAYLOR,
                                                  SF_BASELINE_FLAT, SF_BASELINE_SPLINE};
  snprintf(out->emit_name, sizeof out->emit_name, "%s", sf_baseline_kind_name(emitted_kind[kind]));
  if (atm->n_channels <= 4) {
    b->emitted.kind = emitted_kind[kind];
    b->emitted.steps = steps;
    b->emitted.atmosphere = atm;
    b->emitted.spline = kind == SF_TB_SPLINE ? &b->spline : NULL;
    out->emit = emit_baseline;
    out->emit_model = &b->emitted;
  }
  out->n_channels = atm->n_channels;
  out->n_params = baseline_constants(atm, b);
  out->constant_bytes = 4 * out->n_params;
  out->eval = baseline_eval;
  out->eval_segment = baseline_segment;
  out->eval_f32 = NULL;
  if (atm->n_channels <= 4 && kind == SF_TB_NAIVE) out->eval_f32 = naive_eval_f32;
  static const int analytic_kind[] = {-1, SF_BASELINE_F_CHAPMAN, SF_BASELINE_F_TAYLOR, SF_BASELINE_F_FLAT, -1};
  if (analytic_kind[kind] >= 0 &&
      sf_baseline_f_make(atm, (sf_baseline_f_kind)analytic_kind[kind], &b->analytic_f) == 0)
    out->eval_f32 = analytic_eval_f32;
  if (kind == SF_TB_SPLINE && sf_baseline_f_make_spline(atm, &b->spline, &b->analytic_f) == 0)
    out->eval_f32 = analytic_eval_f32;   /* its meshes as the emitted float arrays */
  out->ctx = b;
  out->free_ctx = free_baseline;
  return SF_OK;
}

void sf_candidate_sky_baseline_set(sf_candidate *out, const sf_atmosphere *atm, long n_params, const char *emit_name,
                                   void (*emit)(struct sf_code_writer *w, const void *model), const void *emit_model,
                                   sf_candidate_eval_fn eval, sf_candidate_eval_f32_fn eval_f32, void *ctx) {
  out->n_channels = atm->n_channels;
  out->n_params = n_params;
  out->constant_bytes = 4 * n_params;
  snprintf(out->emit_name, sizeof out->emit_name, "%s", emit_name);
  if (emit) {
    out->emit = emit;
    out->emit_model = emit_model;
    out->eval_f32 = eval_f32;
  }
  out->eval = eval;
  out->ctx = ctx;
  out->free_ctx = free;
}
