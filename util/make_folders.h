/* mkdir -p with messages that name what the folder is for. */
#ifndef SKYFIT_UTIL_MAKE_FOLDERS_H
#define SKYFIT_UTIL_MAKE_FOLDERS_H

#include "util/error.h"

/* Creates each missing component of dir. Errors (SF_ERR_INPUT) start with
 * "<role>: ", e.g. "--out: cannot create folder ...". */
int sf_make_folders(const char *dir, const char *role, sf_error *err);

#endif
