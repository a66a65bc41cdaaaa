#include "cli/output_file_check.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "util/atomic_file.h"

int sf_cli_same_file(const char *a, const char *b) {
  if (strcmp(a, b) == 0) return 1;
  struct stat sa, sb;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int sf_cli_output_problem(const char *option, const char *path, const char *const *inputs, int n_inputs,
                          sf_error *err) {
  for (int i = 0; i < n_inputs; ++i)
    if (inputs[i] && sf_cli_same_file(path, inputs[i]))
      return sf_fail(err, SF_ERR_INPUT, "%s %s: the same file as another of the run's files (%s), which it would "
                                        "overwrite", option, path, inputs[i]);
  return sf_atomic_check(path, err);
}

int sf_cli_check_output(const char *command, const char *option, const char *path, const char *const *inputs,
                        int n_inputs) {
  sf_error err = {0};
  if (sf_cli_output_problem(option, path, inputs, n_inputs, &err) == SF_OK) return 0;
  fprintf(stderr, "%s: %s\n", command, err.message);
  return 2;
}
