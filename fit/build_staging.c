#include "fit/build_staging.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/atomic_file.h"
#include "util/make_folders.h"

#define STAGING_PREFIX ".staging."

/* The previous outputs a publish replaces, kept until it has succeeded. */
#define KEEP_DIR ".previous"

/* Folders nest at most this deep in a staging folder (views/, weights/). */
#define MAX_DEPTH 4

/* Everything under path, then path itself; symbolic links removed, never
 * followed. */
static void remove_tree(const char *path, int depth) {
  struct stat st;
  if (lstat(path, &st) != 0) return;
  if (!S_ISDIR(st.st_mode)) {
    unlink(path);
    return;
  }
  DIR *d = depth < MAX_DEPTH ? opendir(path) : NULL;
  if (d) {
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      char child[4096];
      int w = snprintf(child, sizeof child, "%s/%s", path, e->d_name);
      if (w > 0 && (size_t)w < sizeof child) remove_tree(child, depth + 1);
    }
    closedir(d);
  }
  rmdir(path);
}

/* Staging folders of processes that no longer exist. */
void sf_build_staging_remove_stale(const char *out_dir) {
  DIR *d = opendir(out_dir);
  if (!d) return;
  size_t prefix = strlen(STAGING_PREFIX);
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    if (strncmp(e->d_name, STAGING_PREFIX, prefix) != 0) continue;
    char *end = NULL;
    errno = 0;
    long pid = strtol(e->d_name + prefix, &end, 10);
    if (errno || !end || *end || !sf_process_gone(pid)) continue;
    char path[4096];
    int w = snprintf(path, sizeof path, "%s/%s", out_dir, e->d_name);
    if (w > 0 && (size_t)w < sizeof path) remove_tree(path, 0);
  }
  closedir(d);
}

const char *const sf_build_out_files[SF_BUILD_OUT_FILES] = {"report.html", "report.md", "metrics.json"};
const char *const sf_build_out_folders[SF_BUILD_OUT_FOLDERS] = {"views", "weights", "plots"};

int sf_build_staging_check_out(const char *out_dir, sf_error *err) {
  for (int i = 0; i < SF_BUILD_OUT_FILES + SF_BUILD_OUT_FOLDERS; ++i) {
    int folder = i >= SF_BUILD_OUT_FILES;
    const char *name = folder ? sf_build_out_folders[i - SF_BUILD_OUT_FILES] : sf_build_out_files[i];
    char path[4096];
    struct stat st;
    int w = snprintf(path, sizeof path, "%s/%s", out_dir, name);
    if (w < 0 || (size_t)w >= sizeof path) return sf_fail(err, SF_ERR_INPUT, "%s: output folder path too long", out_dir);
    if (lstat(path, &st) != 0) continue;
    if (folder && !S_ISDIR(st.st_mode))
      return sf_fail(err, SF_ERR_INPUT, "%s: is in the way of the output folder %s/", path, name);
    if (!folder && S_ISDIR(st.st_mode))
      return sf_fail(err, SF_ERR_INPUT, "%s: is a folder, not a file: the report cannot be written there", path);
  }
  return SF_OK;
}

int sf_build_staging_open(sf_build_staging *s, const char *out_dir, sf_error *err) {
  memset(s, 0, sizeof *s);
  int w1 = snprintf(s->out_dir, sizeof s->out_dir, "%s", out_dir);
  int w2 = snprintf(s->dir, sizeof s->dir, "%s/" STAGING_PREFIX "%ld", out_dir, (long)getpid());
  if (w1 < 0 || (size_t)w1 >= sizeof s->out_dir || w2 < 0 || (size_t)w2 >= sizeof s->dir)
    return sf_fail(err, SF_ERR_INPUT, "%s: output folder path too long", out_dir);
  sf_build_staging_remove_stale(out_dir);
  remove_tree(s->dir, 0);   /* a folder of this PID's earlier life */
  if (mkdir(s->dir, 0777) != 0)
    return sf_fail(err, SF_ERR_INPUT, "%s: cannot create the staging folder: %s", s->dir, strerror(errno));
  return SF_OK;
}

void sf_build_staging_final_path(const sf_build_staging *s, const char *staged, char *out, size_t n) {
  size_t len = strlen(s->dir);
  if (strncmp(staged, s->dir, len) == 0 && (staged[len] == '/' || staged[len] == '\0'))
    snprintf(out, n, "%s%s", s->out_dir, staged + len);
  else
    snprintf(out, n, "%s", staged);
}

/* The paths of entry name in staged/ and in final/ (4096 bytes each). */
static int entry_paths(const char *staged, const char *final, const char *name, char *from, char *to, sf_error *err) {
  int w1 = snprintf(from, 4096, "%s/%s", staged, name);
  int w2 = snprintf(to, 4096, "%s/%s", final, name);
  if (w1 < 0 || w1 >= 4096 || w2 < 0 || w2 >= 4096)
    return sf_fail(err, SF_ERR_INPUT, "%s/%s: output path too long", final, name);
  return SF_OK;
}

/* Every move checked before any is made: a folder where a file goes, or a
 * file where a folder goes, fails the publish with nothing moved (a
 * report.md made a folder had left the run half published). */
static int check_tree(const char *staged, const char *final, int depth, sf_error *err) {
  DIR *d = opendir(staged);
  if (!d) return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot list the staging folder: %s", staged, strerror(errno));
  int status = SF_OK;
  for (struct dirent *e; status == SF_OK && (e = readdir(d)) != NULL;) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char from[4096], to[4096];
    if ((status = entry_paths(staged, final, e->d_name, from, to, err)) != SF_OK) break;
    struct stat st, there;
    if (lstat(from, &st) != 0) continue;
    int exists = lstat(to, &there) == 0;
    if (S_ISDIR(st.st_mode)) {
      if (exists && !S_ISDIR(there.st_mode))
        status = sf_fail(err, SF_ERR_INPUT, "%s: is in the way of the output folder; nothing was replaced", to);
      else if (depth + 1 < MAX_DEPTH)
        status = check_tree(from, to, depth + 1, err);
    } else if (exists && S_ISDIR(there.st_mode)) {
      status = sf_fail(err, SF_ERR_INPUT, "%s: is a folder, not a file; nothing was replaced", to);
    }
  }
  closedir(d);
  return status;
}

/* What the moves did, to undo them if one fails: each destination's
 * previous file kept under the staging folder (a hard link, or the file
 * itself moved there where links are not supported), and the folders the
 * publish created. */
typedef struct move_log {
  char (*to)[4096];
  char (*kept)[4096];   /* "" where there was no previous file */
  int *is_folder;
  int n, capacity;
  const char *keep_dir;
} move_log;

static int log_add(move_log *log, const char *to, const char *kept, int is_folder) {
  if (log->n == log->capacity) {
    int cap = log->capacity ? 2 * log->capacity : 64;
    char(*t)[4096] = realloc(log->to, sizeof *t * (size_t)cap);
    if (t) log->to = t;
    char(*k)[4096] = realloc(log->kept, sizeof *k * (size_t)cap);
    if (k) log->kept = k;
    int *f = realloc(log->is_folder, sizeof *f * (size_t)cap);
    if (f) log->is_folder = f;
    if (!t || !k || !f) return -1;
    log->capacity = cap;
  }
  snprintf(log->to[log->n], sizeof log->to[log->n], "%s", to);
  snprintf(log->kept[log->n], sizeof log->kept[log->n], "%s", kept);
  log->is_folder[log->n++] = is_folder;
  return 0;
}

static void log_undo(move_log *log) {
  for (int i = log->n - 1; i >= 0; --i) {
    if (log->is_folder[i]) rmdir(log->to[i]);
    else if (log->kept[i][0]) rename(log->kept[i], log->to[i]);
    else unlink(log->to[i]);
  }
}

static int move_file(move_log *log, const char *from, const char *to, sf_error *err) {
  char kept[4096] = "";
  struct stat there;
  if (lstat(to, &there) == 0) {
    snprintf(kept, sizeof kept, "%s/%d", log->keep_dir, log->n);
    if (link(to, kept) != 0 && rename(to, kept) != 0)
      return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot keep the previous file: %s", to, strerror(errno));
  }
  /* logged before the move, so that the undo covers every moved file */
  if (log_add(log, to, kept, 0) != 0) {
    if (kept[0]) rename(kept, to);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory publishing %s", to);
  }
  if (rename(from, to) != 0) {
    int e = errno;
    --log->n;
    if (kept[0]) rename(kept, to);
    return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot move into place: %s", to, strerror(e));
  }
  return SF_OK;
}

/* The files of staged/ into final/: the folders first, then the files, so
 * the report (top level) lands after the weights and views it names. */
static int publish_tree(move_log *log, const char *staged, const char *final, int depth, sf_error *err) {
  struct stat there;
  if (lstat(final, &there) != 0) {
    if (sf_make_folders(final, "--out", err) != SF_OK) return err->status;
    if (log_add(log, final, "", 1) != 0) return sf_fail(err, SF_ERR_INTERNAL, "out of memory publishing %s", final);
  }
  for (int pass = 0; pass < 2; ++pass) {
    DIR *d = opendir(staged);
    if (!d) return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot list the staging folder: %s", staged, strerror(errno));
    int status = SF_OK;
    for (struct dirent *e; status == SF_OK && (e = readdir(d)) != NULL;) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      if (depth == 0 && strcmp(e->d_name, KEEP_DIR) == 0) continue;
      char from[4096], to[4096];
      if ((status = entry_paths(staged, final, e->d_name, from, to, err)) != SF_OK) break;
      struct stat st;
      if (lstat(from, &st) != 0) continue;
      int is_dir = S_ISDIR(st.st_mode);
      if (pass == 0 && is_dir && depth + 1 < MAX_DEPTH) status = publish_tree(log, from, to, depth + 1, err);
      if (pass == 1 && !is_dir) status = move_file(log, from, to, err);
    }
    closedir(d);
    if (status != SF_OK) return status;
  }
  return SF_OK;
}

int sf_build_staging_check(const sf_build_staging *s, sf_error *err) { return check_tree(s->dir, s->out_dir, 0, err); }

int sf_build_staging_publish(sf_build_staging *s, sf_error *err) {
  int status = sf_build_staging_check(s, err);
  if (status != SF_OK) return status;
  char keep_dir[4096 + 16];
  snprintf(keep_dir, sizeof keep_dir, "%s/" KEEP_DIR, s->dir);
  if (mkdir(keep_dir, 0777) != 0)
    return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot create: %s", keep_dir, strerror(errno));
  move_log log = {NULL, NULL, NULL, 0, 0, keep_dir};
  status = publish_tree(&log, s->dir, s->out_dir, 0, err);
  if (status != SF_OK) log_undo(&log);
  free(log.to);
  free(log.kept);
  free(log.is_folder);
  if (status == SF_OK) remove_tree(s->dir, 0);
  return status;
}

void sf_build_staging_discard(sf_build_staging *s) {
  if (s->dir[0]) remove_tree(s->dir, 0);
}
