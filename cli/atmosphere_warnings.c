/* An atmosphere file's unit warnings on stderr (cli/atmosphere_warnings.h). */
#include "cli/atmosphere_warnings.h"

#include <stdio.h>
#include <stdlib.h>

#include "models/atmosphere_units.h"

void sf_cli_warn_atmosphere_units(const char *command, const char *source, const sf_atmosphere *atm) {
  if (!source || !source[0]) return;
  sf_unit_warnings *w = malloc(sizeof *w);   /* 8 KB of text */
  if (!w) return;   /* a warning is not worth failing the command for */
  sf_atmosphere_unit_warnings(atm, source, w);
  for (int i = 0; i < w->count; ++i) fprintf(stderr, "%s: warning: %s\n", command, w->text[i]);
  if (w->dropped > 0)
    fprintf(stderr, "%s: warning: %s: %d more warning(s) of the same kind\n", command, source, w->dropped);
  free(w);
}
