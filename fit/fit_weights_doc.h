/* The weights file (SPEC §8) of a fitted sigmoid, Perez or Hosek model, one
 * writer for both of its users (`skyfit fit MODEL` and the build's
 * candidates), so a file says the same whichever made it: parameters, the
 * metrics of the fit's report, and how it was fitted. */
#ifndef SKYFIT_FIT_FIT_WEIGHTS_DOC_H
#define SKYFIT_FIT_FIT_WEIGHTS_DOC_H

#include "fit/fit_sigmoid.h"
#include "fit/fit_sky_elevation.h"
#include "models/hosek_sky_model.h"
#include "util/error.h"

/* Writes the sigmoid model fitted over domain with options o (its report
 * rep) to path, atomically. */
int sf_sigmoid_weights_write(const sf_atmosphere *atm, const sf_scene_domain *domain,
                             const sf_sigmoid_fit_options *o, const sf_sigmoid_model *m,
                             const sf_sigmoid_fit_report *rep, const char *path, sf_error *err);

/* Writes the Perez or Hosek model (m->form) fitted with options o on tables
 * of the given parameterisation ("bruneton", "leenman") to path,
 * atomically; domain: where it holds (a ground viewer, the sky above the
 * horizon, its sun range). */
int sf_sky_form_weights_write(const sf_atmosphere *atm, const sf_scene_domain *domain,
                              const sf_sky_elevation_options *o, const char *tables_kind, const sf_elevation_sky_model *m,
                              const sf_sky_elevation_report *rep, const char *path, sf_error *err);

#endif
