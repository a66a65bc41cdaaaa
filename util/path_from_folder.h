/* A path as seen from a folder: what the report (metrics.json, report.md,
 * report.html) writes for a file outside its own tree, the emitted headers,
 * so that every path it holds has one base, the report's folder (its views
 * and plots were relative to it, the headers relative to where skyfit ran). */
#ifndef SKYFIT_UTIL_PATH_FROM_FOLDER_H
#define SKYFIT_UTIL_PATH_FROM_FOLDER_H

#include <stddef.h>

/* Writes to out (n bytes) path relative to folder when path lies in folder
 * or below it ("sky.h", "include/sky.h"), else its absolute path. A path
 * spelled as folder/rest gives rest as it stands; otherwise links are
 * resolved in folder and in path's folder, both of which must exist; the
 * file itself need not. Returns 0, or -1 (out holds path as given) when a
 * folder cannot be resolved or the result does not fit. */
int sf_path_from_folder(const char *folder, const char *path, char *out, size_t n);

#endif
