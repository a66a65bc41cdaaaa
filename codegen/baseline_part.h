/* A baseline (codegen/baselines.h) as a part of an emitted file: its
 * summary, atmosphere, domain and measured transmittance error. */
#ifndef SKYFIT_CODEGEN_BASELINE_PART_H
#define SKYFIT_CODEGEN_BASELINE_PART_H

#include "codegen/baselines.h"
#include "codegen/codegen_file.h"
#include "models/sky_naive.h"
#include "models/sky_raymarched.h"

/* Fills part for b (which must outlive part) over domain; measures the
 * error (sf_baseline_measure, a few ms). */
int sf_baseline_part(const sf_baseline *b, const sf_scene_domain *domain, sf_codegen_part *part,
                     sf_error *err);

/* Fills part for the naive sky m (models/sky_naive.h; must outlive part)
 * over domain: the sky-radiance baseline `skyfit codegen --baselines
 * naive-sky` emits. Its error against the reference sky radiance needs
 * the tables (skyfit report measures it); part->error says so. Schuler's
 * sky (sf_sky_schuler_make) likewise: `--baselines schuler-sky`.
 * SF_ERR_INPUT where it cannot be emitted (sf_sky_naive_emittable,
 * nothing that scatters). */
int sf_sky_naive_part(const sf_sky_naive *m, const sf_scene_domain *domain, sf_codegen_part *part, sf_error *err);

/* The same for Leenman's raymarched sky m (models/sky_raymarched.h):
 * `skyfit codegen --baselines raymarched-sky`; with flat set, his flat sky
 * (m made with SF_SKY_FLAT_STEPS), `--baselines flat-sky`. SF_ERR_INPUT
 * where it cannot be emitted (sf_sky_raymarched_emittable, nothing that
 * scatters). */
int sf_sky_raymarched_part(const sf_sky_raymarched *m, int flat, const sf_scene_domain *domain,
                           sf_codegen_part *part, sf_error *err);

#endif
