#include "util/atomic_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* Creates "PATH.tmp.PID.XXXXXX" (6 characters tried until the name is new)
 * beside path, so that rename() never crosses a file system; the pid keeps
 * concurrent writers apart and tells stale temporaries. Mode 0666, which
 * the system reduces by the process's umask as for any file: mkstemp's
 * 0600 would need the umask to be read, and reading it means setting it,
 * for the whole process at once (a race with every other thread creating
 * a file). Returns the descriptor, or -1 with errno set. */
static int create_temp(const char *path, char *temp, size_t n) {
  static const char alphabet[] = "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
  /* A name taken can only be a leftover of an earlier process with this
   * pid (or a writer of the same path in this one): the next is tried. */
  struct timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  uint64_t start = (uint64_t)now.tv_nsec ^ ((uint64_t)now.tv_sec << 30);
  for (int attempt = 0; attempt < 100; ++attempt) {
    uint64_t bits = start + (uint64_t)attempt;
    char suffix[7];
    for (int k = 0; k < 6; ++k, bits /= 62) suffix[k] = alphabet[bits % 62];
    suffix[6] = '\0';
    int len = snprintf(temp, n, "%s.tmp.%ld.%s", path, (long)getpid(), suffix);
    if (len < 0 || (size_t)len >= n) {
      errno = ENAMETOOLONG;
      return -1;
    }
    int fd = open(temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  errno = EEXIST;
  return -1;
}

/* Linux: pid is a zombie (state Z in /proc/PID/stat: it has exited and
 * writes nothing more, but its parent has not reaped it yet). */
static int is_zombie(long pid) {
  char path[64], line[512];
  snprintf(path, sizeof path, "/proc/%ld/stat", pid);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  size_t n = fread(line, 1, sizeof line - 1, f);
  fclose(f);
  line[n] = '\0';
  const char *paren = strrchr(line, ')');   /* the name may hold spaces and parentheses */
  return paren && paren[1] == ' ' && paren[2] == 'Z';
}

int sf_process_gone(long pid) {
  if (pid <= 0 || pid == (long)getpid()) return 0;
  /* kill(pid, 0) fails with ESRCH only when no such process exists; EPERM
   * (another user's live process) counts as alive. A zombie counts as
   * gone: a build's worker killed with its supervisor (SIGKILL, through
   * PR_SET_PDEATHSIG: cli/interrupt_cleanup.h) stays one until init reaps
   * it, and its staging folder had been kept by the next build. */
  if (kill((pid_t)pid, 0) != 0) return errno == ESRCH;
  return is_zombie(pid);
}

/* "PID.XXXXXX" after the "PATH.tmp." prefix: the writer's pid, or 0. */
static long temp_writer_pid(const char *suffix) {
  char *end;
  errno = 0;
  long pid = strtol(suffix, &end, 10);
  if (errno != 0 || end == suffix || pid <= 0 || *end != '.' || strlen(end + 1) != 6) return 0;
  return pid;
}

void sf_atomic_remove_stale(const char *path) {
  char dir[4096], prefix[1024];
  const char *slash = strrchr(path, '/');
  if (slash) snprintf(dir, sizeof dir, "%.*s", (int)(slash - path + 1), path);
  else snprintf(dir, sizeof dir, "./");
  int len = snprintf(prefix, sizeof prefix, "%s.tmp.", slash ? slash + 1 : path);
  if (len < 0 || (size_t)len >= sizeof prefix || strlen(dir) + 256 >= sizeof dir) return;
  DIR *d = opendir(dir);
  if (!d) return;
  size_t dir_len = strlen(dir);
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    if (strncmp(e->d_name, prefix, (size_t)len) != 0) continue;
    if (!sf_process_gone(temp_writer_pid(e->d_name + len))) continue;
    char stale[4096 + 256];
    snprintf(stale, sizeof stale, "%.*s%s", (int)dir_len, dir, e->d_name);
    unlink(stale);
  }
  closedir(d);
}

void sf_atomic_remove_stale_in(const char *folder) {
  DIR *d = opendir(folder);
  if (!d) return;
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    const char *tmp = strstr(e->d_name, ".tmp.");
    if (!tmp || tmp == e->d_name) continue;
    for (const char *next; (next = strstr(tmp + 1, ".tmp.")) != NULL;) tmp = next;   /* the last one */
    if (!sf_process_gone(temp_writer_pid(tmp + 5))) continue;
    char stale[4096 + 256];
    int w = snprintf(stale, sizeof stale, "%s/%s", folder, e->d_name);
    if (w > 0 && (size_t)w < sizeof stale) unlink(stale);
  }
  closedir(d);
}

/* sample, fit and build had exited 2 on ENOSPC, codegen 1. */
int sf_write_error_status(int errno_value) {
  switch (errno_value) {
    case ENOSPC:
    case EIO:
#ifdef EDQUOT
    case EDQUOT:
#endif
    case ENOMEM:
      return SF_ERR_INTERNAL;
    default:
      return SF_ERR_INPUT;
  }
}

int sf_atomic_open(sf_atomic_file *f, const char *path, sf_error *err) {
  memset(f, 0, sizeof *f);
  sf_atomic_remove_stale(path);
  if (strlen(path) + 1 > sizeof f->final_path)
    return sf_fail(err, SF_ERR_INPUT, "%s: output path is too long", path);
  strcpy(f->final_path, path);
  int fd = create_temp(path, f->temp_path, sizeof f->temp_path);
  if (fd < 0) {
    int saved = errno;
    f->temp_path[0] = '\0';
    if (saved == ENAMETOOLONG) return sf_fail(err, SF_ERR_INPUT, "%s: output path is too long", path);
    return sf_fail(err, sf_write_error_status(saved), "%s: cannot write here: %s", path, strerror(saved));
  }
  f->stream = fdopen(fd, "wb");
  if (!f->stream) {
    close(fd);
    unlink(f->temp_path);
    return sf_fail(err, SF_ERR_INTERNAL, "%s: fdopen failed: %s", path, strerror(errno));
  }
  return 0;
}

int sf_atomic_commit(sf_atomic_file *f, sf_error *err) {
  int failed = ferror(f->stream) || fflush(f->stream) != 0 || fsync(fileno(f->stream)) != 0;
  int saved = errno;
  if (fclose(f->stream) != 0) failed = 1;
  f->stream = NULL;
  if (!failed) {
    if (rename(f->temp_path, f->final_path) == 0) return 0;
    saved = errno;
  }
  unlink(f->temp_path);
  return sf_fail(err, sf_write_error_status(saved), "%s: writing failed: %s", f->final_path, strerror(saved));
}

void sf_atomic_abort(sf_atomic_file *f) {
  if (f->stream) fclose(f->stream);
  f->stream = NULL;
  if (f->temp_path[0]) unlink(f->temp_path);
}

int sf_atomic_check(const char *path, sf_error *err) {
  struct stat st;
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return sf_fail(err, SF_ERR_INPUT, "%s: is a folder", path);
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  sf_atomic_abort(&f);
  return SF_OK;
}
