#define _XOPEN_SOURCE 700 /* realpath */
#include "cli/output_file_check.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "util/atomic_file.h"

/* path with its folder resolved (realpath) and its last name kept: one
 * spelling for a file that does not exist yet ("d.csv", "./d.csv"); the
 * path itself where the folder does not resolve. */
static void resolved_path(const char *path, char *out, size_t n) {
  char folder[PATH_MAX], resolved[PATH_MAX];
  const char *slash = strrchr(path, '/');
  const char *name = slash ? slash + 1 : path;
  if (slash == path) snprintf(folder, sizeof folder, "/");
  else if (slash) snprintf(folder, sizeof folder, "%.*s", (int)(slash - path), path);
  else snprintf(folder, sizeof folder, ".");
  if (realpath(folder, resolved)) snprintf(out, n, "%s/%s", strcmp(resolved, "/") ? resolved : "", name);
  else snprintf(out, n, "%s", path);
}

int sf_cli_same_file(const char *a, const char *b) {
  if (strcmp(a, b) == 0) return 1;
  struct stat sa, sb;
  int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
  if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (ea != eb) return 0;   /* one exists, the other not */
  char ra[PATH_MAX + 256], rb[PATH_MAX + 256];
  resolved_path(a, ra, sizeof ra);
  resolved_path(b, rb, sizeof rb);
  return strcmp(ra, rb) == 0;
}

void sf_cli_scene_files(const char *scene_path, const char *atmosphere_path, const sf_scene *scene,
                        const char *files[3]) {
  files[0] = scene_path;
  files[1] = scene_path && scene->atmosphere_path[0] ? scene->atmosphere_path : NULL;
  files[2] = atmosphere_path;
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
