/* A build's outputs inside OUT (weights/, views/, plots/, report.html,
 * report.md, metrics.json) are written under a staging folder, OUT/.staging.PID, and
 * moved into place together once the run has succeeded: a failed or
 * interrupted run never touches the previous outputs (SPEC §11). The
 * moves are renames within OUT's file system, one per file, in a burst at
 * the end. A run killed before it leaves its staging folder behind; the
 * next build into OUT removes the staging folders of processes that no
 * longer exist (as util/atomic_file.h does for temporaries). */
#ifndef SKYFIT_FIT_BUILD_STAGING_H
#define SKYFIT_FIT_BUILD_STAGING_H

#include <stddef.h>

#include "util/error.h"

/* What a build publishes in OUT from its staging folder: these files and
 * folders (besides them OUT holds the cache/ and, by default, the headers). */
#define SF_BUILD_OUT_FILES 3
#define SF_BUILD_OUT_FOLDERS 3
extern const char *const sf_build_out_files[SF_BUILD_OUT_FILES];     /* report.html, report.md, metrics.json */
extern const char *const sf_build_out_folders[SF_BUILD_OUT_FOLDERS]; /* views, weights, plots */

typedef struct sf_build_staging {
  char out_dir[4096];
  char dir[4096];   /* OUT/.staging.PID */
} sf_build_staging;

/* Whether a build's outputs can be published into out_dir (which exists):
 * report.html, report.md and metrics.json not folders, views/, weights/
 * and plots/ not files (SF_ERR_INPUT naming the path). For a check before
 * the work; the publish checks every path again. */
int sf_build_staging_check_out(const char *out_dir, sf_error *err);

/* Removes the staging folders in out_dir of processes that no longer
 * exist (cli/interrupt_cleanup.h calls it for an interrupted build). */
void sf_build_staging_remove_stale(const char *out_dir);

/* Removes stale staging folders in out_dir (which exists) and creates this
 * process's. */
int sf_build_staging_open(sf_build_staging *s, const char *out_dir, sf_error *err);

/* The final path of a path under the staging folder (out, n bytes): the
 * same path under OUT. Paths elsewhere are copied as they are. */
void sf_build_staging_final_path(const sf_build_staging *s, const char *staged, char *out, size_t n);

/* Whether every file of the staging folder can be moved into place: no
 * folder where a file goes, no file where a folder goes (SF_ERR_INPUT
 * naming the path). The publish checks this itself; a caller with other
 * files to move first (the headers) checks before moving them. */
int sf_build_staging_check(const sf_build_staging *s, sf_error *err);

/* Moves every file of the staging folder to the same place under OUT
 * (creating folders there as needed), then removes the staging folder.
 * Every move is checked first (a folder where a file goes, or a file
 * where a folder goes: SF_ERR_INPUT, nothing moved), and a move that
 * still fails undoes the ones before it: the previous files are kept
 * under the staging folder until the last move has succeeded. */
int sf_build_staging_publish(sf_build_staging *s, sf_error *err);

/* Removes the staging folder and everything in it (a failed run). */
void sf_build_staging_discard(sf_build_staging *s);

#endif
