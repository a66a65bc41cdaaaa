/* A baseline (codegen/baselines.h) as a part of an emitted file: its
 * summary, atmosphere, domain and measured transmittance error. */
#ifndef SKYFIT_CODEGEN_BASELINE_PART_H
#define SKYFIT_CODEGEN_BASELINE_PART_H

#include "codegen/baselines.h"
#include "codegen/codegen_file.h"

/* Fills part for b (which must outlive part) over domain; measures the
 * error (sf_baseline_measure, a few ms). */
int sf_baseline_part(const sf_baseline *b, const sf_scene_domain *domain, sf_codegen_part *part,
                     sf_error *err);

#endif
