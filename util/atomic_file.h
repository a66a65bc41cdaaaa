/* Outputs appear whole or not at all (SPEC §11): write to a temporary file in
 * the destination folder, flush and fsync it, then rename() it into place. */
#ifndef SKYFIT_UTIL_ATOMIC_FILE_H
#define SKYFIT_UTIL_ATOMIC_FILE_H

#include <stdio.h>
#include "util/error.h"

typedef struct sf_atomic_file {
  FILE *stream;          /* write here */
  char final_path[4096]; /* the path, or the file its links name */
  char temp_path[4096];
  int in_place;          /* a character device or a FIFO: written into, no temporary */
} sf_atomic_file;

/* Opens a temporary sibling of path, first removing stale temporaries of
 * path that a killed writer left behind (sf_atomic_remove_stale). The
 * output gets mode 0666 less the process's umask, like any new file. A
 * link at path is followed: the file it names is replaced, the link stays.
 * A character device or a FIFO there (/dev/null, a pipe) is written into
 * in place, and a descriptor (/dev/stdout, /dev/fd/N) through a copy of it
 * (from where its file stands); a folder, a block device or a socket is
 * refused. On failure
 * sets err (SF_ERR_INPUT: the folder is missing or unwritable, or what is
 * at path cannot take the output) and returns nonzero. */
int sf_atomic_open(sf_atomic_file *f, const char *path, sf_error *err);
/* Flushes, syncs and renames into place; the previous file stays untouched
 * until the rename. Returns nonzero (and removes the temporary) on failure. */
int sf_atomic_commit(sf_atomic_file *f, sf_error *err);
/* Abandons the temporary; the destination is left as it was. */
void sf_atomic_abort(sf_atomic_file *f);
/* Whether path can be written (its folder exists and takes a temporary;
 * path is not a folder; or path is a writable device or FIFO), checked
 * before long work whose result goes there; SF_ERR_INPUT naming the path
 * otherwise. Writes nothing. */
int sf_atomic_check(const char *path, sf_error *err);
/* The status of a failed write with this errno: a full disk or a failing
 * device (ENOSPC, EDQUOT, EIO, ENOMEM) is not bad input (SF_ERR_INTERNAL,
 * exit 1, SPEC §11); a path that cannot hold the file (missing folder, no
 * permission, a folder there) is (SF_ERR_INPUT). */
int sf_write_error_status(int errno_value);
/* 1 when no process pid exists, so what it left behind (a temporary, a
 * staging folder) can go; 0 for this process, pid <= 0, or one that may
 * exist. */
int sf_process_gone(long pid);
/* Removes temporaries of path ("PATH.tmp.PID.XXXXXX", beside the file its
 * links name, as sf_atomic_open makes them) whose writing process
 * no longer exists (killed before it could commit or abort), so an
 * interrupted run leaves nothing behind once the file is written again.
 * Temporaries of live processes, this one included, are kept. */
void sf_atomic_remove_stale(const char *path);
/* The same for every file of folder: any "NAME.tmp.PID.XXXXXX" whose
 * writing process no longer exists (an interrupted writer's, where the
 * names it wrote are not known: cli/interrupt_cleanup.h). */
void sf_atomic_remove_stale_in(const char *folder);
/* The same, of those not written for min_age_seconds: where the folder may
 * be shared (a cache on a network file system), a pid that runs nowhere
 * here may be a writer on another machine, still writing. */
void sf_atomic_remove_stale_older(const char *folder, long min_age_seconds);

#endif
