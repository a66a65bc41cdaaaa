/* A phase function in emitted code: the statements
 *   float p<k> = <phase p at the float variable nu>;
 * (models/phase.c's formulas, its constants folded), for the scattering
 * network's constituents (codegen/emit_mlp.h) and the naive sky
 * (codegen/emit_sky_naive.h); p<k> = 0 for SF_PHASE_NONE. */
#ifndef SKYFIT_CODEGEN_EMIT_PHASE_H
#define SKYFIT_CODEGEN_EMIT_PHASE_H

#include "codegen/code_writer.h"
#include "models/atmosphere.h"

void sf_emit_phase(sf_code_writer *w, int k, const sf_phase *p);

#endif
