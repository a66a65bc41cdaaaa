/* What `skyfit fit preetham` and `skyfit fit hosek` share (SPEC §7.2, §11):
 * the table fit over a scene's sun range (--out W.json), the one-sky fit of
 * sampled radiance (--samples SKY.csv, JSON on stdout) and --check of a
 * weights file. */
#ifndef SKYFIT_CLI_FIT_SKY_COMMAND_H
#define SKYFIT_CLI_FIT_SKY_COMMAND_H

#include "models/hosek_sky_model.h"

int sf_fit_sky_command(sf_sky_form form, int argc, char **argv);

#endif
