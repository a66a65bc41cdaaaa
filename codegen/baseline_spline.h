/* The float32 form of Gałaj's spline transmittance (seed 002 §IV.E;
 * models/optical_depth_spline.h) for the "spline" baseline of
 * codegen/baselines.h: the meshes as constant float arrays (per node: value,
 * x slope, d slope, mixed slope) and, per exponential constituent i, the
 * exact integrals of the 1-D Hermite spline for a line at distance d:
 *   float skyfit_spline_miss_<i>(float d, float t0, float t1)   region I
 *   float skyfit_spline_hit_<i>(float d, float h0, float h1)    region II
 * (region II takes the factored integrand s / sqrt(h + r - d) as the double
 * model does). */
#ifndef SKYFIT_CODEGEN_BASELINE_SPLINE_H
#define SKYFIT_CODEGEN_BASELINE_SPLINE_H

#include "codegen/code_writer.h"
#include "models/optical_depth_spline.h"

/* The arrays and functions above, at file scope (before the transmittance
 * function that calls them). */
void sf_emit_spline_tables(sf_code_writer *w, const sf_spline_model *model);

/* Statements for the body of skyfit_spline_transmittance_between, after
 * the segment's ends (codegen/baselines.c emit_segment_ends: r, s0, s1, d,
 * dd_bb, shape; seg.z, seg.w the ends' altitudes): d<i> for each
 * exponential constituent i. */
void sf_emit_spline_depths(sf_code_writer *w, const sf_atmosphere *atm,
                           const sf_spline_model *model);

#endif
