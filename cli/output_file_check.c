#define _XOPEN_SOURCE 700 /* realpath */
#include "cli/output_file_check.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/atomic_file.h"

/* path made absolute (from the working folder) without its "." and ".."
 * components and repeated slashes: "./o//sky.h" and "/cwd/o/../o/sky.h"
 * are "/cwd/o/sky.h". */
static void absolute_lexical_path(const char *path, char *out, size_t n) {
  char joined[2 * PATH_MAX];
  char cwd[PATH_MAX];
  if (path[0] != '/' && getcwd(cwd, sizeof cwd)) snprintf(joined, sizeof joined, "%s/%s", cwd, path);
  else snprintf(joined, sizeof joined, "%s", path);
  size_t len = 0;
  out[len++] = '/';
  for (const char *p = joined; *p;) {
    while (*p == '/') ++p;
    size_t part = strcspn(p, "/");
    if (part == 2 && p[0] == '.' && p[1] == '.') {
      while (len > 1 && out[len - 1] != '/') --len;   /* back over the last name */
      if (len > 1) --len;                               /* and its slash */
    } else if (part > 0 && !(part == 1 && p[0] == '.') && len + part + 2 < n) {
      if (out[len - 1] != '/') out[len++] = '/';
      memcpy(out + len, p, part);
      len += part;
    }
    p += part;
  }
  out[len] = '\0';
}

/* path with its folder resolved: the deepest existing folder on it through
 * realpath (links), the rest as written (absolute_lexical_path): one
 * spelling for a file that does not exist yet ("d.csv", "./d.csv",
 * "/cwd/out/d.csv" before out/ exists). */
static void resolved_path(const char *path, char *out, size_t n) {
  char lexical[2 * PATH_MAX], folder[2 * PATH_MAX], resolved[PATH_MAX];
  absolute_lexical_path(path, lexical, sizeof lexical);
  for (size_t cut = strlen(lexical); cut-- > 0;) {   /* each folder on it, deepest first */
    if (lexical[cut] != '/') continue;
    snprintf(folder, sizeof folder, "%.*s", cut ? (int)cut : 1, lexical);
    if (realpath(folder, resolved)) {
      snprintf(out, n, "%s%s", strcmp(resolved, "/") ? resolved : "", lexical + cut);
      return;
    }
  }
  snprintf(out, n, "%s", lexical);
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

const char *sf_cli_same_as_any(const char *path, const char *const *files, int n) {
  for (int i = 0; i < n; ++i)
    if (files[i] && sf_cli_same_file(path, files[i])) return files[i];
  return NULL;
}

const char *sf_cli_inside_any(const char *path, const char *const *folders, int n) {
  char lexical[2 * PATH_MAX];
  absolute_lexical_path(path, lexical, sizeof lexical);
  for (size_t cut = strlen(lexical); cut-- > 0;) {   /* each folder on it, deepest first */
    if (lexical[cut] != '/') continue;
    lexical[cut ? cut : 1] = '\0';
    const char *inside = sf_cli_same_as_any(lexical, folders, n);
    if (inside) return inside;
  }
  return NULL;
}

int sf_cli_output_problem(const char *option, const char *path, const char *const *inputs, int n_inputs,
                          sf_error *err) {
  const char *clash = sf_cli_same_as_any(path, inputs, n_inputs);
  if (clash)
    return sf_fail(err, SF_ERR_INPUT, "%s %s: the same file as another of the run's files (%s), which it would "
                                      "overwrite", option, path, clash);
  return sf_atomic_check(path, err);
}

int sf_cli_check_output(const char *command, const char *option, const char *path, const char *const *inputs,
                        int n_inputs) {
  sf_error err = {0};
  if (sf_cli_output_problem(option, path, inputs, n_inputs, &err) == SF_OK) return 0;
  fprintf(stderr, "%s: %s\n", command, err.message);
  return 2;
}

int sf_cli_stdout_written(const char *command) {
  if (fflush(stdout) == 0 && !ferror(stdout)) return 0;
  fprintf(stderr, "%s: writing to stdout failed\n", command);
  return 1;
}
