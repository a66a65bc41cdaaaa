#include "util/make_folders.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

int sf_make_folders(const char *dir, const char *role, sf_error *err) {
  char path[4096];
  size_t n = strlen(dir);
  if (n == 0 || n + 32 >= sizeof path)
    return sf_fail(err, SF_ERR_INPUT, "%s: folder name '%s' is not usable", role, dir);
  memcpy(path, dir, n + 1);
  for (size_t i = 1; i <= n; ++i) {
    if (path[i] != '/' && path[i] != '\0') continue;
    char saved = path[i];
    path[i] = '\0';
    struct stat st;
    if (stat(path, &st) != 0) {
      if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return sf_fail(err, SF_ERR_INPUT, "%s: cannot create folder %s: %s", role, path, strerror(errno));
    } else if (!S_ISDIR(st.st_mode)) {
      return sf_fail(err, SF_ERR_INPUT, "%s: %s is not a folder", role, path);
    }
    path[i] = saved;
  }
  return SF_OK;
}
