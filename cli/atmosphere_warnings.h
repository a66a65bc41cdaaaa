/* Prints an atmosphere file's likely unit mistakes (models/atmosphere_units.h)
 * on stderr, once per command: each command calls it where it has loaded
 * the atmosphere it will use (a scene's, or --atmosphere's), never in the
 * library's loaders, which commands and tests call many times. */
#ifndef SKYFIT_CLI_ATMOSPHERE_WARNINGS_H
#define SKYFIT_CLI_ATMOSPHERE_WARNINGS_H

#include "models/atmosphere.h"

/* "<command>: warning: <source>: <key> = <value>: ..." per warning.
 * source NULL or "": the built-in default, which has none. */
void sf_cli_warn_atmosphere_units(const char *command, const char *source, const sf_atmosphere *atm);

#endif
