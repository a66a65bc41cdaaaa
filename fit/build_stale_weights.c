#include "fit/build_stale_weights.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/candidate_registry.h"

int sf_build_weights_name(const char *file) {
  size_t len = strlen(file);
  if (len <= 5 || strcmp(file + len - 5, ".json") != 0) return 0;
  size_t stem_len = len - 5;
  if (stem_len == strlen("spectral4") && strncmp(file, "spectral4", stem_len) == 0) return 1;
  const sf_candidate_factory *f;
  int n = sf_candidate_factories(&f);
  for (int i = 0; i < n; ++i)
    if (stem_len == strlen(f[i].name) && strncmp(file, f[i].name, stem_len) == 0) return 1;
  return sf_candidate_network_name(file, stem_len);
}

static int was_written(const char *path, const char *const *written, int n_written) {
  for (int k = 0; k < n_written; ++k)
    if (written[k] && strcmp(written[k], path) == 0) return 1;
  return 0;
}

int sf_build_remove_stale_weights(const char *work_dir, const char *const *written, int n_written,
                                  int *n_removed, sf_error *err) {
  *n_removed = 0;
  DIR *dir = opendir(work_dir);
  if (!dir && errno == ENOENT) return SF_OK;   /* a build that wrote no weights: none stale */
  if (!dir) return sf_fail(err, SF_ERR_INPUT, "%s: cannot list the weights folder: %s", work_dir, strerror(errno));
  /* The stale paths first, then removed: what readdir returns after an
   * entry is removed is unspecified (POSIX). */
  char (*stale)[4200] = NULL;
  int n_stale = 0, cap = 0, status = SF_OK;
  struct dirent *e;
  while ((e = readdir(dir)) != NULL && status == SF_OK) {
    if (!sf_build_weights_name(e->d_name)) continue;
    char path[4200];
    int w = snprintf(path, sizeof path, "%s/%s", work_dir, e->d_name);
    if (w < 0 || (size_t)w >= sizeof path || was_written(path, written, n_written)) continue;
    if (n_stale == cap) {
      int grown = cap ? 2 * cap : 8;
      void *p = realloc(stale, (size_t)grown * sizeof *stale);
      if (!p) {
        status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
        break;
      }
      stale = p;
      cap = grown;
    }
    memcpy(stale[n_stale++], path, (size_t)w + 1);
  }
  closedir(dir);
  int listed = status == SF_OK;
  for (int k = 0; listed && k < n_stale; ++k) {   /* all tried; err keeps the first failure */
    if (remove(stale[k]) == 0) ++*n_removed;
    else status = sf_fail(err, SF_ERR_INPUT, "%s: cannot remove this weights file of an earlier run: %s", stale[k],
                          strerror(errno));
  }
  free(stale);
  return status;
}
