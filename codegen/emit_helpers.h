/* The helper functions emitted code shares (ray geometry, the segment of a
 * ray inside the air, expm1, the Chapman and Taylor pieces), written in
 * float32 with the same cancellation-free formulas as the double reference
 * (models/ray_geometry_impl.inc, models/air_segment.c, SPEC §10). Each is
 * emitted at most once per file, behind its own #ifndef guard, so several
 * emitted files can be included by one shader or translation unit. They
 * take every atmosphere-dependent number as an argument. */
#ifndef SKYFIT_CODEGEN_EMIT_HELPERS_H
#define SKYFIT_CODEGEN_EMIT_HELPERS_H

#include "codegen/code_writer.h"

/* The helpers `needed` asks for (SF_HELPER_*) and those they call. */
unsigned sf_helpers_closure(unsigned needed);

/* Writes the helpers of `needed` (closed under sf_helpers_closure) in
 * dependency order. */
void sf_emit_helpers(sf_code_writer *w, unsigned needed);

#endif
