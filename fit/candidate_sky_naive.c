/* The naive sky (models/sky_naive.h) as the sky-radiance baseline of the
 * report (SPEC §7.6, §12): valid for every viewer and sun, from the
 * atmosphere alone, timed in float32 as emitted (codegen/emit_sky_naive.h).
 * Where Preetham and Hosek take a ground viewer only, it is the sky
 * models' comparison for flying and space scenes. */
#include <stdio.h>
#include <stdlib.h>

#include "codegen/emit_sky_naive.h"
#include "fit/candidate_builtin.h"

typedef struct sky_naive_ctx {
  sf_sky_naive model;
  sf_sky_naive_f model_f;
} sky_naive_ctx;

static void eval(const void *ctx, const double *in, double *out) {
  const sky_naive_ctx *c = ctx;
  sf_sky_naive_radiance(&c->model, in[0], in[1], in[2], in[3], out);
}

static void eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const sky_naive_ctx *c = ctx;
  for (size_t p = 0; p < n; ++p)
    sf_sky_naive_radiance_f(&c->model_f, in[4 * p], in[4 * p + 1], in[4 * p + 2], in[4 * p + 3],
                            out + (size_t)c->model_f.sky.n_channels * p);
}

static void emit(struct sf_code_writer *w, const void *model) { sf_emit_sky_naive(w, model); }

/* What the emitted code holds: per constituent its layers (4 numbers each,
 * and the layer's top), its scattering and extinction per channel and up
 * to 3 phase parameters; the sun per channel; the radii. */
static long constants(const sf_atmosphere *atm) {
  long n = 2 + atm->n_channels;
  for (int i = 0; i < atm->n_constituents; ++i) n += 5L * atm->constituents[i].n_layers + 2L * atm->n_channels + 3;
  return n;
}

int sf_candidate_sky_naive(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  sky_naive_ctx *c = calloc(1, sizeof *c);
  if (!c) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  c->model.atm = atm;
  c->model.view_steps = SF_SKY_NAIVE_VIEW_STEPS;
  c->model.sun_steps = SF_SKY_NAIVE_SUN_STEPS;
  int emittable = sf_sky_naive_f_make(&c->model, &c->model_f) == 0;   /* at most 4 channels */
  sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, "naive-sky", "Naive single scattering");
  snprintf(out->description, sizeof out->description,
           "Single scattering by direct numerical integration: a %d-step midpoint raymarch of the view ray, the "
           "sun's optical depth at each step by an %d-step one; no multiple scattering (seed 000 §11.2.6, "
           "Terrell 2016 with ozone).",
           SF_SKY_NAIVE_VIEW_STEPS, SF_SKY_NAIVE_SUN_STEPS);
  out->n_channels = atm->n_channels;
  out->n_params = constants(atm);
  out->constant_bytes = 4 * out->n_params;
  snprintf(out->emit_name, sizeof out->emit_name, "naive");
  if (emittable) {
    out->emit = emit;
    out->emit_model = &c->model;
    out->eval_f32 = eval_f32;
  }
  out->eval = eval;
  out->ctx = c;
  out->free_ctx = free;
  return SF_OK;
}
