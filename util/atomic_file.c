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

/* The temporaries of the file at path (links already followed). */
static void remove_stale_beside(const char *path) {
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

void sf_atomic_remove_stale_in(const char *folder) { sf_atomic_remove_stale_older(folder, 0); }

void sf_atomic_remove_stale_older(const char *folder, long min_age_seconds) {
  DIR *d = opendir(folder);
  if (!d) return;
  time_t now = time(NULL);
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    const char *tmp = strstr(e->d_name, ".tmp.");
    if (!tmp || tmp == e->d_name) continue;
    for (const char *next; (next = strstr(tmp + 1, ".tmp.")) != NULL;) tmp = next;   /* the last one */
    if (!sf_process_gone(temp_writer_pid(tmp + 5))) continue;
    char stale[4096 + 256];
    int w = snprintf(stale, sizeof stale, "%s/%s", folder, e->d_name);
    struct stat st;
    if (w <= 0 || (size_t)w >= sizeof stale) continue;
    if (min_age_seconds > 0 && (lstat(stale, &st) != 0 || now - st.st_mtime < min_age_seconds)) continue;
    unlink(stale);
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
    case EINTR:   /* a stop signal while waiting (a FIFO's reader): not bad input */
      return SF_ERR_INTERNAL;
    default:
      return SF_ERR_INPUT;
  }
}

/* What an output at path replaces. Links are followed (up to 40), so that
 * the file a link names is replaced and the link stays: renaming over the
 * link had replaced it with a file of its own. */
typedef enum output_kind {
  OUTPUT_NEW,         /* nothing there yet */
  OUTPUT_FILE,        /* a regular file: written beside and renamed over */
  OUTPUT_STREAM,      /* a character device or a FIFO (/dev/null, a pipe): written into */
  OUTPUT_DESCRIPTOR,  /* one of this process's open files (/dev/stdout, /dev/fd/N): written through it */
  OUTPUT_FOLDER,
  OUTPUT_OTHER        /* a block device or a socket */
} output_kind;

/* The descriptor a path names (/dev/stdout, /dev/stderr, /dev/fd/N,
 * /proc/self/fd/N), or -1. The kernel's links there are not paths (a
 * pipe's reads "pipe:[N]"), and a file opened anew through them would be
 * written from its start: `--out /dev/stdout >> log` had replaced log. */
static int descriptor_named(const char *path) {
  if (strcmp(path, "/dev/stdout") == 0) return 1;
  if (strcmp(path, "/dev/stderr") == 0) return 2;
  const char *number = NULL;
  if (strncmp(path, "/dev/fd/", 8) == 0) number = path + 8;
  else if (strncmp(path, "/proc/self/fd/", 14) == 0) number = path + 14;
  if (!number || *number < '0' || *number > '9') return -1;
  char *end;
  long fd = strtol(number, &end, 10);
  return *end == '\0' && fd <= 1 << 20 ? (int)fd : -1;
}

static int resolve_output(const char *path, char *target, size_t n, output_kind *kind, int *fd, sf_error *err) {
  char current[4096], link[4096];
  if (snprintf(current, sizeof current, "%s", path) >= (int)sizeof current || strlen(path) + 1 > n)
    return sf_fail(err, SF_ERR_INPUT, "%s: output path is too long", path);
  *fd = -1;
  for (int hops = 0; hops <= 40; ++hops) {
    struct stat st;
    if ((*fd = descriptor_named(current)) >= 0) {
      *kind = OUTPUT_DESCRIPTOR;
    } else if (lstat(current, &st) != 0) {
      *kind = OUTPUT_NEW;   /* a missing folder is found when the temporary is made */
    } else if (S_ISLNK(st.st_mode)) {
      ssize_t len = readlink(current, link, sizeof link - 1);
      if (len < 0) return sf_fail(err, SF_ERR_INPUT, "%s: cannot read the link: %s", path, strerror(errno));
      link[len] = '\0';
      const char *slash = strrchr(current, '/');
      char next[8192];
      if (link[0] == '/' || !slash) snprintf(next, sizeof next, "%s", link);
      else snprintf(next, sizeof next, "%.*s%s", (int)(slash - current + 1), current, link);
      if (strlen(next) + 1 > sizeof current || strlen(next) + 1 > n)
        return sf_fail(err, SF_ERR_INPUT, "%s: output path is too long (through its link)", path);
      strcpy(current, next);
      continue;
    } else if (S_ISREG(st.st_mode)) {
      *kind = OUTPUT_FILE;
    } else if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      *kind = OUTPUT_STREAM;
    } else {
      *kind = S_ISDIR(st.st_mode) ? OUTPUT_FOLDER : OUTPUT_OTHER;
    }
    strcpy(target, current);
    return SF_OK;
  }
  return sf_fail(err, SF_ERR_INPUT, "%s: too many links", path);
}

/* The errors of an output that is neither a file nor a stream. */
static int refuse_kind(const char *path, output_kind kind, sf_error *err) {
  if (kind == OUTPUT_FOLDER) return sf_fail(err, SF_ERR_INPUT, "%s: is a folder", path);
  return sf_fail(err, SF_ERR_INPUT,
                 "%s: is a block device or a socket: outputs go to files, character devices (/dev/null) or FIFOs",
                 path);
}

void sf_atomic_remove_stale(const char *path) {
  /* a temporary sits beside the file the path's links name */
  char target[4096];
  output_kind kind;
  int fd;
  sf_error ignored = {0};
  remove_stale_beside(resolve_output(path, target, sizeof target, &kind, &fd, &ignored) == SF_OK ? target : path);
}

int sf_atomic_open(sf_atomic_file *f, const char *path, sf_error *err) {
  memset(f, 0, sizeof *f);
  output_kind kind;
  int descriptor;
  if (resolve_output(path, f->final_path, sizeof f->final_path, &kind, &descriptor, err) != SF_OK)
    return err->status;
  if (kind == OUTPUT_FOLDER || kind == OUTPUT_OTHER) return refuse_kind(path, kind, err);
  if (kind == OUTPUT_STREAM || kind == OUTPUT_DESCRIPTOR) {
    /* a device or a pipe is written into, in place: renaming a file over
     * it had replaced /dev/null itself (as root) with a regular file */
    int fd = kind == OUTPUT_DESCRIPTOR ? fcntl(descriptor, F_DUPFD_CLOEXEC, 3)
                                       : open(f->final_path, O_WRONLY | O_CLOEXEC);
    if (fd < 0) {
      int saved = errno;
      return sf_fail(err, sf_write_error_status(saved), "%s: cannot write here: %s", path, strerror(saved));
    }
    f->stream = fdopen(fd, "wb");
    if (!f->stream) {
      close(fd);
      return sf_fail(err, SF_ERR_INTERNAL, "%s: fdopen failed: %s", path, strerror(errno));
    }
    f->in_place = 1;
    return 0;
  }
  remove_stale_beside(f->final_path);
  int fd = create_temp(f->final_path, f->temp_path, sizeof f->temp_path);
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
  if (f->in_place) {   /* nothing to sync or rename on a device or a pipe */
    int failed = ferror(f->stream) || fflush(f->stream) != 0;
    int saved = failed && errno ? errno : EIO;
    if (fclose(f->stream) != 0 && !failed) {
      failed = 1;
      saved = errno;
    }
    f->stream = NULL;
    if (!failed) return 0;
    return sf_fail(err, sf_write_error_status(saved), "%s: writing failed: %s", f->final_path, strerror(saved));
  }
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
  char target[4096];
  output_kind kind;
  int descriptor;
  if (resolve_output(path, target, sizeof target, &kind, &descriptor, err) != SF_OK) return err->status;
  if (kind == OUTPUT_FOLDER || kind == OUTPUT_OTHER) return refuse_kind(path, kind, err);
  if (kind == OUTPUT_DESCRIPTOR) {
    int flags = fcntl(descriptor, F_GETFL);
    if (flags >= 0 && (flags & O_ACCMODE) != O_RDONLY) return SF_OK;
    return sf_fail(err, SF_ERR_INPUT, "%s: cannot write here: %s", path,
                   flags < 0 ? strerror(errno) : "open for reading only");
  }
  if (kind == OUTPUT_STREAM) {   /* opening a FIFO to check it would wait for its reader */
    if (access(target, W_OK) == 0) return SF_OK;
    int saved = errno;
    return sf_fail(err, SF_ERR_INPUT, "%s: cannot write here: %s", path, strerror(saved));
  }
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  sf_atomic_abort(&f);
  return SF_OK;
}
