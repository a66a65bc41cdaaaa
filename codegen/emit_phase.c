#include "codegen/emit_phase.h"

#include "util/constants.h"

/* Emits "float NAMEk = 1 + g^2 - 2 g nu" (the Henyey-Greenstein
 * denominator's base, seed 004 eq. 4) in float32 without cancellation at
 * the peak: (1 - g)^2 + 2g (1 - nu) for g >= 0, (1 + g)^2 - 2g (1 + nu)
 * for g < 0, two terms >= 0 and 1 -+ nu exact near the peak. The direct
 * form's rounded 1 + g^2 and 2g had cancelled to 0 (inf) at g = 0.9999
 * and nu = 1, and were 7 % off at g = 0.999. */
static void emit_hg_base(sf_code_writer *w, const char *name, int k, double g) {
  if (g >= 0.0)
    sf_cw_emit(w, "float %s%d = %F + %F * (1.0f - nu)", name, k, (1.0 - g) * (1.0 - g), 2.0 * g);
  else
    sf_cw_emit(w, "float %s%d = %F + %F * (1.0f + nu)", name, k, (1.0 + g) * (1.0 + g), -2.0 * g);
}

void sf_emit_phase(sf_code_writer *w, int k, const sf_phase *p) {
  const double pi = SF_PI;
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH:
      sf_cw_emit(w, "  float p%d = %F * (1.0f + nu * nu);  /* rayleigh */\n", k, 3.0 / (16.0 * pi));
      return;
    case SF_PHASE_HENYEY_GREENSTEIN: {
      double g = p->g;
      sf_cw_emit(w, "  ");
      emit_hg_base(w, "q", k, g);
      sf_cw_emit(w, ";\n  float p%d = %F / (q%d * @sqrt(q%d));  /* henyey_greenstein */\n", k,
                 (1.0 - g * g) / (4.0 * pi), k, k);
      return;
    }
    case SF_PHASE_CORNETTE_SHANKS: {
      double g = p->g;
      sf_cw_emit(w, "  ");
      emit_hg_base(w, "q", k, g);
      sf_cw_emit(w, ";\n  float p%d = %F * (1.0f + nu * nu) / (q%d * @sqrt(q%d));  /* cornette_shanks */\n", k,
                 3.0 / (8.0 * pi) * (1.0 - g * g) / (2.0 + g * g), k, k);
      return;
    }
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
      double g1 = p->g1, g2 = p->g2, f = p->f;
      sf_cw_emit(w, "  ");
      emit_hg_base(w, "q", k, g1);
      sf_cw_emit(w, ";\n  ");
      emit_hg_base(w, "r", k, g2);
      sf_cw_emit(w, ";\n  float p%d = %F / (q%d * @sqrt(q%d)) + %F / (r%d * @sqrt(r%d));  /* double HG */\n", k,
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
