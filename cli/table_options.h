/* The options that `skyfit sample` and `skyfit eval multiple_scattering |
 * sky_radiance` share: which atmosphere and which reference tables. */
#ifndef SKYFIT_CLI_TABLE_OPTIONS_H
#define SKYFIT_CLI_TABLE_OPTIONS_H

#include <stdio.h>

#include "data/table_set.h"
#include "models/atmosphere.h"
#include "models/scene_file.h"

typedef struct sf_table_cli {
  const char *atmosphere_path;     /* NULL: the built-in default */
  const char *scene_path;          /* NULL: no scene (the full domain) */
  sf_scene_domain scene_domain;    /* with scene_path, after sf_table_cli_atmosphere */
  sf_table_set_options set;
  int quiet;
} sf_table_cli;

void sf_table_cli_default(sf_table_cli *o);

/* If argv[*i] is one of the shared options, consumes it (and its value),
 * advancing *i, and returns 1; returns 0 if it is not one; returns -1 after
 * printing "<command>: <problem>" for a bad value. */
int sf_table_cli_option(sf_table_cli *o, const char *command, int argc, char **argv, int *i);

/* The lines of --help that describe the shared options. */
void sf_table_cli_help(FILE *out);

/* Loads the atmosphere (or the default). With --scene (SPEC §5), the atmosphere
 * is the scene's, and o->set gets the scene's domain (models/scene_file.h
 * sf_scene_get_domain: viewer altitudes, view cosines, sun cosines; view
 * "above_horizon" keeps Bruneton's sky half only) and, for a scene that asks
 * for transmittance alone, transmittance_only. --scene with --atmosphere is
 * rejected: the scene names its atmosphere. Prints the error and returns its
 * exit code (2 for bad input) on failure. */
int sf_table_cli_atmosphere(sf_table_cli *o, const char *command, sf_atmosphere *atm);

#endif
