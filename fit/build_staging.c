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
static void remove_stale(const char *out_dir) {
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

int sf_build_staging_open(sf_build_staging *s, const char *out_dir, sf_error *err) {
  memset(s, 0, sizeof *s);
  int w1 = snprintf(s->out_dir, sizeof s->out_dir, "%s", out_dir);
  int w2 = snprintf(s->dir, sizeof s->dir, "%s/" STAGING_PREFIX "%ld", out_dir, (long)getpid());
  if (w1 < 0 || (size_t)w1 >= sizeof s->out_dir || w2 < 0 || (size_t)w2 >= sizeof s->dir)
    return sf_fail(err, SF_ERR_INPUT, "%s: output folder path too long", out_dir);
  remove_stale(out_dir);
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

/* The files of staged/ into final/: the folders first, then the files, so
 * the report (top level) lands after the weights and views it names. */
static int publish_tree(const char *staged, const char *final, int depth, sf_error *err) {
  if (sf_make_folders(final, "--out", err) != SF_OK) return err->status;
  for (int pass = 0; pass < 2; ++pass) {
    DIR *d = opendir(staged);
    if (!d) return sf_fail(err, SF_ERR_INTERNAL, "%s: cannot list the staging folder: %s", staged, strerror(errno));
    int status = SF_OK;
    for (struct dirent *e; status == SF_OK && (e = readdir(d)) != NULL;) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      char from[4096], to[4096];
      int w1 = snprintf(from, sizeof from, "%s/%s", staged, e->d_name);
      int w2 = snprintf(to, sizeof to, "%s/%s", final, e->d_name);
      if (w1 < 0 || (size_t)w1 >= sizeof from || w2 < 0 || (size_t)w2 >= sizeof to) {
        status = sf_fail(err, SF_ERR_INPUT, "%s/%s: output path too long", final, e->d_name);
        break;
      }
      struct stat st;
      if (lstat(from, &st) != 0) continue;
      int is_dir = S_ISDIR(st.st_mode);
      if (pass == 0 && is_dir && depth + 1 < MAX_DEPTH) status = publish_tree(from, to, depth + 1, err);
      if (pass == 1 && !is_dir && rename(from, to) != 0)
        status = sf_fail(err, SF_ERR_INTERNAL, "%s: cannot move into place: %s", to, strerror(errno));
    }
    closedir(d);
    if (status != SF_OK) return status;
  }
  return SF_OK;
}

int sf_build_staging_publish(sf_build_staging *s, sf_error *err) {
  int status = publish_tree(s->dir, s->out_dir, 0, err);
  if (status == SF_OK) remove_tree(s->dir, 0);
  return status;
}

void sf_build_staging_discard(sf_build_staging *s) {
  if (s->dir[0]) remove_tree(s->dir, 0);
}
