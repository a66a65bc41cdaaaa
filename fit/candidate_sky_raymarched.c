/* Leenman's raymarched and flat skies (models/sky_raymarched.h) as
 * sky-radiance baselines of the report (SPEC §7.6 "Leenman's flat and
 * raymarched models", §12): the seed's analytic single-scattering models,
 * 5 steps or one, each integrated in closed form with the flat model's
 * optical depths, valid for every viewer and sun; the report's
 * counterparts of seed 000 App. B's "Raymarched" and "Flat" columns.
 * Emitted by codegen/emit_sky_raymarched.h and timed in float32 as
 * emitted. */
#include <stdio.h>
#include <stdlib.h>

#include "codegen/emit_sky_raymarched.h"
#include "fit/candidate_builtin.h"
#include "models/sky_raymarched.h"

typedef struct sky_raymarched_ctx {
  sf_sky_raymarched model;
  sf_sky_raymarched_f model_f;
} sky_raymarched_ctx;

static void emit_raymarched(struct sf_code_writer *w, const void *model) {
  sf_emit_sky_raymarched(w, model, "raymarched");
}

static void emit_flat(struct sf_code_writer *w, const void *model) { sf_emit_sky_raymarched(w, model, "flat"); }

static void eval(const void *ctx, const double *in, double *out) {
  sf_sky_raymarched_radiance(&((const sky_raymarched_ctx *)ctx)->model, in[0], in[1], in[2], in[3], out);
}

static void eval_f32(const void *ctx, size_t n, const float *in, float *out) {
  const sky_raymarched_ctx *c = ctx;
  for (size_t p = 0; p < n; ++p)
    sf_sky_raymarched_radiance_f(&c->model_f, in[4 * p], in[4 * p + 1], in[4 * p + 2], in[4 * p + 3],
                                 out + (size_t)c->model_f.sky.n_channels * p);
}

/* What the model holds: per constituent its profile (scale height and
 * density, or the shell's two radii), its scattering and extinction per
 * channel and up to 3 phase parameters; the sun per channel; the radii. */
static long constants(const sf_atmosphere *atm) {
  return 2 + atm->n_channels + (long)atm->n_constituents * (2 + 2L * atm->n_channels + 3);
}

/* flat: Leenman's flat sky (one step, SF_SKY_FLAT_STEPS), else his raymarched sky. */
static int make(const sf_atmosphere *atm, int flat, sf_candidate *out, sf_error *err) {
  sky_raymarched_ctx *c = calloc(1, sizeof *c);
  if (!c) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_sky_raymarched *m = &c->model;
  sf_sky_raymarched_make(atm, flat ? SF_SKY_FLAT_STEPS : SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, m);
  if (flat) {
    sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, "flat-sky", "Flat (Leenman)");
    snprintf(out->description, sizeof out->description,
             "Leenman's flat single scattering: the view ray as one segment integrated in closed form (seed 000 "
             "eq. 52 looking up, eq. 55 toward the ground) with the flat model's optical depths (seed 000 "
             "§10.1-10.5), the planet's shadow split off; no multiple scattering (seed 000 §11.2.9).");
  } else {
    sf_candidate_init(out, SF_CANDIDATE_SKY_RADIANCE, SF_ROLE_BASELINE, "raymarched-sky", "Raymarched (Leenman)");
    snprintf(out->description, sizeof out->description,
             "Leenman's raymarched single scattering: %d steps of the view ray, each integrated in closed form "
             "(seed 000 eq. 55) with the flat model's optical depths (seed 000 §10.1-10.5), the planet's shadow "
             "split off; no multiple scattering (seed 000 §11.2.10).",
             SF_SKY_RAYMARCHED_STEPS);
  }
  const char *why = NULL;
  int emittable = sf_sky_raymarched_emittable(m, &why) && sf_sky_raymarched_f_make(m, &c->model_f) == 0;
  sf_candidate_sky_baseline_set(out, atm, constants(atm), flat ? "flat" : "raymarched",
                                !emittable ? NULL : flat ? emit_flat : emit_raymarched, m, eval, eval_f32, c);
  return SF_OK;
}

int sf_candidate_sky_raymarched(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  return make(atm, 0, out, err);
}

int sf_candidate_sky_flat(const sf_atmosphere *atm, sf_candidate *out, sf_error *err) {
  return make(atm, 1, out, err);
}
