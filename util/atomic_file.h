/* Outputs appear whole or not at all (SPEC §11): write to a temporary file in
 * the destination folder, flush and fsync it, then rename() it into place. */
#ifndef SKYFIT_UTIL_ATOMIC_FILE_H
#define SKYFIT_UTIL_ATOMIC_FILE_H

#include <stdio.h>
#include "util/error.h"

typedef struct sf_atomic_file {
  FILE *stream;          /* write here */
  char final_path[4096];
  char temp_path[4096];
} sf_atomic_file;

/* Opens a temporary sibling of path, first removing stale temporaries of
 * path that a killed writer left behind (sf_atomic_remove_stale). On failure sets err (SF_ERR_INPUT: the
 * folder is missing or unwritable) and returns nonzero. */
int sf_atomic_open(sf_atomic_file *f, const char *path, sf_error *err);
/* Flushes, syncs and renames into place; the previous file stays untouched
 * until the rename. Returns nonzero (and removes the temporary) on failure. */
int sf_atomic_commit(sf_atomic_file *f, sf_error *err);
/* Abandons the temporary; the destination is left as it was. */
void sf_atomic_abort(sf_atomic_file *f);
/* Temporary name for writers that need a path rather than a FILE* (e.g. the
 * OpenEXR writer): fills temp (size n) with a unique sibling of path. */
int sf_atomic_temp_name(const char *path, char *temp, size_t n);
/* Removes temporaries of path ("PATH.tmp.PID.XXXXXX") whose writing process
 * no longer exists (killed before it could commit or abort), so an
 * interrupted run leaves nothing behind once the file is written again.
 * Temporaries of live processes, this one included, are kept. */
void sf_atomic_remove_stale(const char *path);

#endif
