/* Segments of in-domain rays, for the report's segment errors
 * (codegen/report.h): what a renderer's aerial perspective asks of a
 * model's segment function (seed 000 eq. 43, 44).
 *
 * Each sample is a ray drawn as sf_domain_samples_make draws its rays
 * (fit/candidate_metrics.h: h, mu, mu_s uniform in the scene's box, nu from
 * a uniform azimuth), a ray that never enters the atmosphere (from a viewer
 * above the top) drawn again, and the segment's end t uniform on the ray's
 * stretch in the air [t_enter, t_exit] (models/ray_geometry.h
 * sf_ray_atmosphere_segment: to the ground or the top), so that the
 * segment's length in the air is uniform between 0 and the whole ray's.
 * t is the distance from the viewer, as the emitted segment functions take
 * it. Inputs per sample: the quantity's (sf_candidate_n_inputs), then t_km:
 * n_inputs is 3 or 5. Seeded: the same samples for the same arguments. */
#ifndef SKYFIT_FIT_SEGMENT_SAMPLES_H
#define SKYFIT_FIT_SEGMENT_SAMPLES_H

#include <stddef.h>
#include <stdint.h>

#include "fit/candidate_metrics.h"

/* A ray is drawn at most this many times per sample asked for; a domain of
 * rays that mostly miss the atmosphere gives fewer samples (out->n, maybe
 * 0: nothing to measure). */
#define SF_SEGMENT_SAMPLES_MAX_DRAWS 64

int sf_segment_samples_make(const sf_scene_domain *d, double bottom_radius_km, double top_radius_km,
                            sf_candidate_quantity q, size_t n, uint64_t seed, sf_domain_samples *out,
                            sf_error *err);

#endif
