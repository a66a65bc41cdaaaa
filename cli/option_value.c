#include "cli/option_value.h"

#include <stdio.h>
#include <string.h>

const char *sf_cli_value_after(int argc, char **argv, int i) {
  if (i + 1 >= argc) return NULL;
  const char *v = argv[i + 1];
  return strncmp(v, "--", 2) == 0 ? NULL : v;
}

int sf_cli_valued(const char *a, const char *name, const char *v, const char **missing) {
  if (strcmp(a, name) != 0) return 0;
  if (!v) *missing = name;
  return v != NULL;
}

int sf_cli_bad_option(const char *command, const char *a, const char *missing) {
  if (missing)
    fprintf(stderr, "%s: %s needs a value; see --help\n", command, missing);
  else
    fprintf(stderr, "%s: unknown option '%s'; see --help\n", command, a);
  return 2;
}
