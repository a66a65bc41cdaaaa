#include "util/data_path.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int try_folder(const char *dir, const char *name, char *out, size_t out_size) {
  if (!dir || !*dir) return 0;
  int n = snprintf(out, out_size, "%s/%s", dir, name);
  if (n < 0 || (size_t)n >= out_size) return 0;
  return access(out, R_OK) == 0;
}

/* PREFIX/share/skyfit/physical for the running PREFIX/bin/skyfit (Linux's
 * /proc/self/exe); "" when it cannot be read. */
static void beside_executable(char *dir, size_t n) {
  dir[0] = '\0';
  char exe[4096];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len <= 0) return;
  exe[len] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash) return;
  *slash = '\0';   /* PREFIX/bin */
  int w = snprintf(dir, n, "%s/../share/skyfit/physical", exe);
  if (w < 0 || (size_t)w >= n) dir[0] = '\0';
}

int sf_data_file_path(const char *name, char *out, size_t out_size, sf_error *err) {
  const char *from_env = getenv("SKYFIT_DATA_DIR");
  if (try_folder(from_env, name, out, out_size)) return SF_OK;
  char installed_here[4200];
  beside_executable(installed_here, sizeof installed_here);
  if (try_folder(installed_here, name, out, out_size)) return SF_OK;
#ifdef SKYFIT_SHARED_DATA_DIR
  if (try_folder(SKYFIT_SHARED_DATA_DIR "/physical", name, out, out_size)) return SF_OK;
#endif
#ifdef SKYFIT_INSTALLED_DATA_DIR
  if (try_folder(SKYFIT_INSTALLED_DATA_DIR, name, out, out_size)) return SF_OK;
#endif
  return sf_fail(err, SF_ERR_INPUT,
                 "data file %s not found (searched $SKYFIT_DATA_DIR=%s, %s"
#ifdef SKYFIT_SHARED_DATA_DIR
                 ", " SKYFIT_SHARED_DATA_DIR "/physical"
#endif
#ifdef SKYFIT_INSTALLED_DATA_DIR
                 ", " SKYFIT_INSTALLED_DATA_DIR
#endif
                 ")",
                 name, from_env ? from_env : "(unset)", installed_here[0] ? installed_here : "(no executable path)");
}
