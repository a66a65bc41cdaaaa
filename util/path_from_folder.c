#define _XOPEN_SOURCE 700 /* realpath */
#include "util/path_from_folder.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sf_path_from_folder(const char *folder, const char *path, char *out, size_t n) {
  int w = snprintf(out, n, "%s", path);
  if (w < 0 || (size_t)w >= n) return -1;
  /* Spelled below the folder ("out/weights/x.json" from "out"): the rest,
   * whether or not its folders exist yet (a build's report names weights
   * files still in its staging folder). Every slash after the folder goes:
   * "--out out/" spells its files "out//sky.h", whose rest is not "/sky.h". */
  size_t nf = strlen(folder);
  while (nf > 1 && folder[nf - 1] == '/') --nf;
  if (nf > 0 && strncmp(path, folder, nf) == 0 && path[nf] == '/') {
    const char *rest = path + nf;
    while (*rest == '/') ++rest;
    if (*rest != '\0' && strstr(path + nf, "/../") == NULL) {
      snprintf(out, n, "%s", rest);
      return 0;
    }
  }
  char base[PATH_MAX], dir[PATH_MAX], parent[PATH_MAX];
  const char *slash = strrchr(path, '/');
  const char *name = slash ? slash + 1 : path;
  if (slash == path) snprintf(parent, sizeof parent, "/");
  else if (slash) snprintf(parent, sizeof parent, "%.*s", (int)(slash - path), path);
  else snprintf(parent, sizeof parent, ".");
  if (*name == '\0' || !realpath(folder, base) || !realpath(parent, dir)) return -1;
  size_t nb = strlen(base);
  const char *rest = NULL;
  if (strcmp(dir, base) == 0) rest = "";
  else if (strncmp(dir, base, nb) == 0 && (dir[nb] == '/' || nb == 1)) rest = dir + nb + (nb == 1 ? 0 : 1);
  char joined[2 * PATH_MAX + 2];
  if (rest) snprintf(joined, sizeof joined, "%s%s%s", rest, *rest ? "/" : "", name);
  else snprintf(joined, sizeof joined, "%s%s%s", dir, strcmp(dir, "/") ? "/" : "", name);
  w = snprintf(out, n, "%s", joined);
  if (w < 0 || (size_t)w >= n) {
    snprintf(out, n, "%s", path);
    return -1;
  }
  return 0;
}
