#include "util/data_path.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static int try_folder(const char *dir, const char *name, char *out, size_t out_size) {
  if (!dir || !*dir) return 0;
  int n = snprintf(out, out_size, "%s/%s", dir, name);
  if (n < 0 || (size_t)n >= out_size) return 0;
  return access(out, R_OK) == 0;
}

int sf_data_file_path(const char *name, char *out, size_t out_size, sf_error *err) {
  const char *from_env = getenv("SKYFIT_DATA_DIR");
  if (try_folder(from_env, name, out, out_size)) return SF_OK;
#ifdef SKYFIT_SHARED_DATA_DIR
  if (try_folder(SKYFIT_SHARED_DATA_DIR "/physical", name, out, out_size)) return SF_OK;
#endif
#ifdef SKYFIT_INSTALLED_DATA_DIR
  if (try_folder(SKYFIT_INSTALLED_DATA_DIR, name, out, out_size)) return SF_OK;
#endif
  return sf_fail(err, SF_ERR_INPUT,
                 "data file %s not found (searched $SKYFIT_DATA_DIR=%s"
#ifdef SKYFIT_SHARED_DATA_DIR
                 ", " SKYFIT_SHARED_DATA_DIR "/physical"
#endif
#ifdef SKYFIT_INSTALLED_DATA_DIR
                 ", " SKYFIT_INSTALLED_DATA_DIR
#endif
                 ")",
                 name, from_env ? from_env : "(unset)");
}
