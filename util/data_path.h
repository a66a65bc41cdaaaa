/* Where the project's shipped data files live (data/physical/: CIE colour
 * matching functions, solar spectrum, published sky-model coefficients...).
 * Looked up, in order: the folder named by the environment variable
 * SKYFIT_DATA_DIR; share/skyfit/physical beside the running executable's
 * bin/ (an installed copy, wherever its prefix was moved: the paths below
 * are fixed when skyfit is built); the source tree's data/physical
 * (SKYFIT_SHARED_DATA_DIR, set by the build); the installed
 * share/skyfit/physical (SKYFIT_INSTALLED_DATA_DIR, when the build defines
 * it). */
#ifndef SKYFIT_UTIL_DATA_PATH_H
#define SKYFIT_UTIL_DATA_PATH_H

#include <stddef.h>

#include "util/error.h"

/* The path of data file `name` (e.g. "hosek2012_rgb.json") in the first
 * folder above that holds it. SF_ERR_INPUT naming the folders searched
 * when none does. */
int sf_data_file_path(const char *name, char *out, size_t out_size, sf_error *err);

#endif
