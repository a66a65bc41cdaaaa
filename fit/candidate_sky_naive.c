/* The naive sky (models/sky_naive.h) as the sky-radiance baseline of the
 * report (SPEC §7.6, §12): valid for every viewer and sun, from the
 * atmosphere alone, timed in float32 as emitted (codegen/emit_sky_naive.h).
 * Where Preetham and Hosek take a ground viewer only, it is the sky
 * models' comparison for flying and space scenes. And Schuler's sky, the
 * same with the sun's depths from his Chapman approximation: the report's
 * counterpart of seed 000 App. B's "Schuler" column. */
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
 * to 3 phase parameters; the sun per channel; the radii. Schuler's sky:
 * an exponential constituent's H and H d0 besides, a shell's two radii. */
static long constants(const sf_atmosphere *atm, int schuler) {
  long n = 2 + atm->n_channels;
  for (int i = 0; i < atm->n_constituents; ++i) n += 5L * atm->constituents[i].n_layers + 2L * atm->n_channels + 3;
  return n + (schuler ? 2L * atm->n_constituents : 0);
}

static int make(const sf_atmosphere *atm, int schuler, sf_candidate *out, sf_error *err) {
  sky_naive_ctx *c = calloc(1, sizeof *c);
  if (!c) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  if (schuler) {
    sf_sky_schuler_make(atm, &c->model);
  } else {
    c->model.atm = atm;
    c->model.view_steps = SF_SKY_NAIVE_VIEW_STEPS;
    c->model.sun_steps = SF_SKY_NAIVE_SUN_STEPS;
  }
  const char *why = NULL;
  int emittable = sf_sky_naive_emittable(&c->model, &why) && sf_sky_naive_f_make(&c->model, &c->model_f) == 0;
  if (schuler) {
    sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, "schuler-sky", "Schuler (Chapman sun)");
    snprintf(out->description, sizeof out->description,
             "Single scattering by a %d-step midpoint raymarch of the view ray, the sun's optical depth at each "
             "step by Schuler's Chapman approximation (seed 000 eq. 22-25; non-exponential constituents as eq. 59 "
             "shells, which the seed leaves out); no multiple scattering (seed 000 §11.2.7).",
             SF_SKY_SCHULER_VIEW_STEPS);
  } else {
    sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, "naive-sky", "Naive single scattering");
    snprintf(out->description, sizeof out->description,
             "Single scattering by direct numerical integration: a %d-step midpoint raymarch of the view ray, the "
             "sun's optical depth at each step by an %d-step one; no multiple scattering (seed 000 §11.2.6, "
             "Terrell 2016 with ozone).",
             SF_SKY_NAIVE_VIEW_STEPS, SF_SKY_NAIVE_SUN_STEPS);
  }
  sf_candidate_sky_baseline_set(out, atm, constants(atm, schuler), schuler ? "schuler" : "naive",
                                emittable ? emit : NULL, &c->model, eval, eval_f32, c);
  return SF_OK;
}

int sf_candidate_sky_naive(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  return make(atm, 0, out, err);
}

int sf_candidate_sky_schuler(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  return make(atm, 1, out, err);
}
