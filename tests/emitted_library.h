/* An emitted header in a shared library the test loads with dlopen: a
 * driver C file that includes it, compiled with the flags the project
 * holds its emitted code to (C99, -Wall -Wextra -Werror -pedantic: a
 * warning fails the test). Used by the tests that compare emitted
 * functions with their double models. */
#ifndef SKYFIT_TESTS_EMITTED_LIBRARY_H
#define SKYFIT_TESTS_EMITTED_LIBRARY_H

#include <stdio.h>
#include <stdlib.h>

/* Compiles the driver at driver_path into so_path; 0, or -1. */
static inline int emitted_library_compile(const char *driver_path, const char *so_path) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "cc -std=c99 -O2 -fPIC -shared -Wall -Wextra -Werror -pedantic %s -o %s -lm",
           driver_path, so_path);
  fflush(stdout);
  int status = system(cmd);
  if (status != 0) printf("command failed (%d): %s\n", status, cmd);
  return status == 0 ? 0 : -1;
}

/* Writes driver_text to driver_path and compiles it; 0, or -1. */
static inline int emitted_library_build(const char *driver_path, const char *driver_text, const char *so_path) {
  FILE *f = fopen(driver_path, "w");
  if (!f) return -1;
  int ok = fputs(driver_text, f) >= 0;
  if (fclose(f) != 0 || !ok) return -1;
  return emitted_library_compile(driver_path, so_path);
}

#endif
