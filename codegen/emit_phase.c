#include "codegen/emit_phase.h"

#include "util/constants.h"

void sf_emit_phase(sf_code_writer *w, int k, const sf_phase *p) {
  const double pi = SF_PI;
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH:
      sf_cw_emit(w, "  float p%d = %F * (1.0f + nu * nu);  /* rayleigh */\n", k, 3.0 / (16.0 * pi));
      return;
    case SF_PHASE_HENYEY_GREENSTEIN: {
      double g = p->g;
      sf_cw_emit(w, "  float q%d = %F - %F * nu;\n  float p%d = %F / (q%d * @sqrt(q%d));  /* henyey_greenstein */\n",
                 k, 1.0 + g * g, 2.0 * g, k, (1.0 - g * g) / (4.0 * pi), k, k);
      return;
    }
    case SF_PHASE_CORNETTE_SHANKS: {
      double g = p->g;
      sf_cw_emit(w,
                 "  float q%d = %F - %F * nu;\n"
                 "  float p%d = %F * (1.0f + nu * nu) / (q%d * @sqrt(q%d));  /* cornette_shanks */\n",
                 k, 1.0 + g * g, 2.0 * g, k, 3.0 / (8.0 * pi) * (1.0 - g * g) / (2.0 + g * g), k, k);
      return;
    }
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
      double g1 = p->g1, g2 = p->g2, f = p->f;
      sf_cw_emit(w,
                 "  float q%d = %F - %F * nu, r%d = %F - %F * nu;\n"
                 "  float p%d = %F / (q%d * @sqrt(q%d)) + %F / (r%d * @sqrt(r%d));  /* double HG */\n",
                 k, 1.0 + g1 * g1, 2.0 * g1, k, 1.0 + g2 * g2, 2.0 * g2, k,
                 (1.0 - f) * (1.0 - g1 * g1) / (4.0 * pi), k, k, f * (1.0 - g2 * g2) / (4.0 * pi), k, k);
      return;
    }
    case SF_PHASE_ISOTROPIC:
      sf_cw_emit(w, "  float p%d = %F;  /* isotropic */\n", k, 1.0 / (4.0 * pi));
      return;
    case SF_PHASE_NONE: break;
  }
  sf_cw_emit(w, "  float p%d = 0.0f;\n", k);
}
