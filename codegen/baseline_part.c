#include "codegen/baseline_part.h"

#include <stdio.h>
#include <string.h>

#include "codegen/emit_sky_naive.h"
#include "codegen/emit_sky_raymarched.h"
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

/* A sky-radiance baseline's part: its error against the reference sky
 * radiance needs the tables, so part->error points to the report's row. */
static int sky_part(const sf_atmosphere *atm, const char *name, const char *row, const sf_scene_domain *domain,
                    void (*emit)(sf_code_writer *w, const void *model), const void *model, sf_codegen_part *part,
                    sf_error *err) {
  if (sf_atmosphere_scattering_count(atm) == 0)
    return sf_fail(err, SF_ERR_INPUT, "%s: no constituent of %s scatters light: its sky is black", row, atm->name);
  memset(part, 0, sizeof *part);
  snprintf(part->name, sizeof part->name, "%s", name);
  snprintf(part->quantity, sizeof part->quantity, "sky_radiance");
  snprintf(part->atmosphere_name, sizeof part->atmosphere_name, "%s", atm->name);
  sf_atmosphere_hash_hex(atm, part->atmosphere_hash);
  part->domain = *domain;
  snprintf(part->error, sizeof part->error,
           "not measured here: its error against the reference sky radiance (which the tables give) is in "
           "skyfit report's %s row",
           row);
  part->emit = emit;
  part->model = model;
  return SF_OK;
}

static void emit_sky_naive(sf_code_writer *w, const void *model) { sf_emit_sky_naive(w, (const sf_sky_naive *)model); }

int sf_sky_naive_part(const sf_sky_naive *m, const sf_scene_domain *domain, sf_codegen_part *part, sf_error *err) {
  const int schuler = m->sun == SF_SKY_SUN_CHAPMAN;
  const char *why = NULL, *row = schuler ? "schuler-sky" : "naive-sky";
  if (!sf_sky_naive_emittable(m, &why)) return sf_fail(err, SF_ERR_INPUT, "%s: %s", row, why);
  if (sky_part(m->atm, schuler ? "schuler" : "naive", row, domain, emit_sky_naive, m, part, err) != SF_OK)
    return err->status;
  if (schuler)
    snprintf(part->summary, sizeof part->summary,
             "schuler sky: single scattering by a %d-step midpoint raymarch of the view ray, the sun's optical "
             "depth at each step by Schuler's Chapman approximation (seed 000 eq. 22-25, eq. 59 shells), no "
             "multiple scattering (seed 000 §11.2.7)",
             m->view_steps);
  else
    snprintf(part->summary, sizeof part->summary,
             "naive sky: single scattering by a %d-step midpoint raymarch of the view ray and another of %d steps "
             "toward the sun at each step, no multiple scattering (seed 000 §11.2.6)",
             m->view_steps, m->sun_steps);
  return SF_OK;
}

static void emit_sky_raymarched(sf_code_writer *w, const void *model) {
  sf_emit_sky_raymarched(w, (const sf_sky_raymarched *)model, "raymarched");
}

static void emit_sky_flat(sf_code_writer *w, const void *model) {
  sf_emit_sky_raymarched(w, (const sf_sky_raymarched *)model, "flat");
}

int sf_sky_raymarched_part(const sf_sky_raymarched *m, int flat, const sf_scene_domain *domain,
                           sf_codegen_part *part, sf_error *err) {
  const char *why = NULL, *row = flat ? "flat-sky" : "raymarched-sky";
  if (!sf_sky_raymarched_emittable(m, &why)) return sf_fail(err, SF_ERR_INPUT, "%s: %s", row, why);
  if (sky_part(m->atm, flat ? "flat" : "raymarched", row, domain, flat ? emit_sky_flat : emit_sky_raymarched, m,
               part, err) != SF_OK)
    return err->status;
  if (flat)
    snprintf(part->summary, sizeof part->summary,
             "flat sky: single scattering as one closed-form segment of the view ray (seed 000 eq. 52 looking "
             "up, eq. 55 toward the ground) with the flat model's optical depths, the planet's shadow split off; "
             "no multiple scattering (seed 000 §10.1-10.4, §11.2.9)");
  else
    snprintf(part->summary, sizeof part->summary,
             "raymarched sky: single scattering in %d steps of the view ray, each integrated in closed form with "
             "the flat model's optical depths, the planet's shadow split off; no multiple scattering (seed 000 "
             "§10.4, §11.2.10)",
             m->steps);
  return SF_OK;
}
