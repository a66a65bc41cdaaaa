#include "codegen/baseline_part.h"

#include <stdio.h>
#include <string.h>

#include "models/atmosphere_file.h"

static void emit_baseline(sf_code_writer *w, const void *model) {
  sf_emit_baseline(w, (const sf_baseline *)model);
}

int sf_baseline_part(const sf_baseline *b, const sf_scene_domain *domain, sf_codegen_part *part,
                     sf_error *err) {
  if (sf_baseline_check(b, err) != SF_OK) return err->status;
  memset(part, 0, sizeof *part);
  snprintf(part->name, sizeof part->name, "%s", sf_baseline_kind_name(b->kind));
  snprintf(part->quantity, sizeof part->quantity, "transmittance");
  sf_baseline_describe(b, part->summary, sizeof part->summary);
  snprintf(part->atmosphere_name, sizeof part->atmosphere_name, "%s", b->atmosphere->name);
  sf_atmosphere_hash_hex(b->atmosphere, part->atmosphere_hash);
  part->domain = *domain;
  double rmse, max_abs;
  sf_baseline_measure(b, domain, &rmse, &max_abs);
  snprintf(part->error, sizeof part->error,
           "transmittance against the reference (double): rmse %.3g over a 64 x 384 (h, mu) grid "
           "over the domain, max abs %.3g over it and the rays grazing the ground and shells",
           rmse, max_abs);
  part->emit = emit_baseline;
  part->model = b;
  return SF_OK;
}
