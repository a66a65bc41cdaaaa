/* skyfit fit hosek: the Hosek-Wilkie 2012 sky fitted to the reference
 * (SPEC §7.2); the work is in cli/fit_sky_command.c. */
#include "cli/fit_commands.h"
#include "cli/fit_sky_command.h"

int sf_cmd_fit_hosek(int argc, char **argv) { return sf_fit_sky_command(SF_SKY_FORM_HOSEK, argc, argv); }
