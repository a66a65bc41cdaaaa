/* util/atomic_file.h: an output appears whole or not at all, with the mode
 * of any new file (0666 less the umask, read by the system, never by a
 * umask() call that would change it for every thread); the temporary sits
 * beside the target and is gone after a commit or an abort; two writers
 * of one path do not collide; a missing folder is an input error. (Stale
 * temporaries: tests/test_memory_limit.c.) */
#define _XOPEN_SOURCE 700 /* mknod, S_IFCHR */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/atomic_file.h"

/* Files in dir whose name starts with prefix. */
static int count_prefixed(const char *dir, const char *prefix) {
  DIR *d = opendir(dir);
  if (!d) return -1;
  int n = 0;
  for (struct dirent *e; (e = readdir(d)) != NULL;) n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
  closedir(d);
  return n;
}

/* Writes text to path through an atomic file; 0 on success. */
static int write_text(const char *path, const char *text) {
  sf_atomic_file f;
  sf_error err;
  sf_error_clear(&err);
  if (sf_atomic_open(&f, path, &err)) return -1;
  fputs(text, f.stream);
  return sf_atomic_commit(&f, &err);
}

static int file_is(const char *path, const char *text) {
  char buf[256] = {0};
  FILE *fp = fopen(path, "rb");
  if (!fp) return 0;
  size_t n = fread(buf, 1, sizeof buf - 1, fp);
  fclose(fp);
  return n == strlen(text) && memcmp(buf, text, n) == 0;
}

/* What is at the path is not always a file. A link is followed: the file
 * it names is replaced and the link stays (renaming over it had replaced
 * the link). A character device or a FIFO is written into in place
 * (renaming over it had replaced /dev/null itself, as root, with a
 * regular file). A folder is refused. */
static void test_other_kinds(const char *dir) {
  char target[600], link[600], dangling[600], missing[600], fifo[600], folder[600], node[600];
  snprintf(target, sizeof target, "%s/real.json", dir);
  snprintf(link, sizeof link, "%s/link.json", dir);
  snprintf(dangling, sizeof dangling, "%s/dangling.json", dir);
  snprintf(missing, sizeof missing, "%s/missing.json", dir);
  snprintf(fifo, sizeof fifo, "%s/fifo", dir);
  snprintf(folder, sizeof folder, "%s/folder", dir);
  snprintf(node, sizeof node, "%s/null", dir);
  struct stat st;

  CHECK(write_text(target, "old") == 0);
  CHECK(symlink("real.json", link) == 0);
  CHECK(write_text(link, "through the link") == 0);
  CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode));
  CHECK(file_is(target, "through the link"));
  CHECK(count_prefixed(dir, "real.json.tmp.") == 0 && count_prefixed(dir, "link.json.tmp.") == 0);
  /* a link to a file not yet there: the file is made where it points */
  CHECK(symlink("missing.json", dangling) == 0);
  CHECK(write_text(dangling, "made") == 0);
  CHECK(lstat(dangling, &st) == 0 && S_ISLNK(st.st_mode));
  CHECK(file_is(missing, "made"));

  /* a FIFO: a child reads what is written into it */
  CHECK(mkfifo(fifo, 0666) == 0);
  sf_error err;
  sf_error_clear(&err);
  CHECK(sf_atomic_check(fifo, &err) == SF_OK);   /* does not wait for a reader */
  pid_t child = fork();
  if (child == 0) {
    FILE *in = fopen(fifo, "rb");
    char buf[64] = {0};
    size_t n = in ? fread(buf, 1, sizeof buf - 1, in) : 0;
    _exit(n == 9 && memcmp(buf, "into fifo", 9) == 0 ? 0 : 1);
  }
  CHECK(write_text(fifo, "into fifo") == 0);
  int status = -1;
  CHECK(waitpid(child, &status, 0) == child && WIFEXITED(status) && WEXITSTATUS(status) == 0);
  CHECK(lstat(fifo, &st) == 0 && S_ISFIFO(st.st_mode));
  CHECK(count_prefixed(dir, "fifo.tmp.") == 0);

  /* a character device (a private /dev/null; root only) */
  if (mknod(node, S_IFCHR | 0666, makedev(1, 3)) == 0) {
    CHECK(write_text(node, "discarded") == 0);
    CHECK(lstat(node, &st) == 0 && S_ISCHR(st.st_mode));
    CHECK(count_prefixed(dir, "null.tmp.") == 0);
    unlink(node);
  } else {
    printf("skip a character device (mknod needs root)\n");
  }

  /* one of the process's descriptors (/dev/fd/N, /proc/self/fd/N; and so
   * /dev/stdout): written through a copy of it, after what the file
   * holds. Reopened, a file there had been written from its start, and a
   * pipe's link ("pipe:[N]") read as a relative path. */
  char through[600];
  snprintf(through, sizeof through, "%s/through.txt", dir);
  FILE *held = fopen(through, "w");
  CHECK(held != NULL);
  if (held) {
    fputs("PRE\n", held);
    fflush(held);
    char fd_path[64];
    snprintf(fd_path, sizeof fd_path, "/dev/fd/%d", fileno(held));
    CHECK(write_text(fd_path, "one\n") == 0);
    snprintf(fd_path, sizeof fd_path, "/proc/self/fd/%d", fileno(held));
    CHECK(write_text(fd_path, "two\n") == 0);
    fclose(held);
    CHECK(file_is(through, "PRE\none\ntwo\n"));
    CHECK(count_prefixed(dir, "through.txt.tmp.") == 0);
  }
  int ends[2];
  CHECK(pipe(ends) == 0);
  char pipe_path[64];
  snprintf(pipe_path, sizeof pipe_path, "/dev/fd/%d", ends[1]);
  sf_error_clear(&err);
  CHECK(sf_atomic_check(pipe_path, &err) == SF_OK);
  CHECK(write_text(pipe_path, "piped") == 0);
  close(ends[1]);
  char got[16] = {0};
  CHECK(read(ends[0], got, sizeof got - 1) == 5 && strcmp(got, "piped") == 0);
  close(ends[0]);
  unlink(through);

  /* a folder: refused naming it, before anything is written */
  CHECK(mkdir(folder, 0777) == 0);
  sf_atomic_file f;
  sf_error_clear(&err);
  CHECK(sf_atomic_open(&f, folder, &err) != 0 && err.status == SF_ERR_INPUT && strstr(err.message, "is a folder"));
  CHECK(count_prefixed(dir, "folder.tmp.") == 0);
  sf_error_clear(&err);
  CHECK(sf_atomic_check(folder, &err) == SF_ERR_INPUT);

  unlink(target);
  unlink(link);
  unlink(dangling);
  unlink(missing);
  unlink(fifo);
  rmdir(folder);
}

int main(void) {
  char dir[] = "/tmp/skyfit-atomic-XXXXXX";
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return 1;
  }
  char path[512];
  snprintf(path, sizeof path, "%s/out.h", dir);

  /* The mode follows the umask, whatever it is; the umask is left as set. */
  const mode_t masks[] = {022, 027, 002, 077};
  for (int k = 0; k < 4; ++k) {
    umask(masks[k]);
    CHECK(write_text(path, "first") == 0);
    struct stat st;
    CHECK(stat(path, &st) == 0);
    printf("umask %03o: mode %03o (want %03o)\n", (unsigned)masks[k], (unsigned)(st.st_mode & 0777),
           (unsigned)(0666 & ~masks[k]));
    CHECK((st.st_mode & 0777) == (0666 & ~masks[k]));
    mode_t now = umask(0);
    CHECK(now == masks[k]);
    umask(now);
    CHECK(unlink(path) == 0);
  }
  umask(022);

  /* Commit replaces; the temporary was beside the target and is gone. */
  CHECK(write_text(path, "first") == 0);
  CHECK(write_text(path, "second") == 0);
  CHECK(file_is(path, "second"));
  CHECK(count_prefixed(dir, "out.h.tmp.") == 0);

  /* Abort leaves the previous file and no temporary. */
  sf_atomic_file f;
  sf_error err;
  sf_error_clear(&err);
  CHECK(sf_atomic_open(&f, path, &err) == 0);
  fputs("half", f.stream);
  CHECK(count_prefixed(dir, "out.h.tmp.") == 1);
  sf_atomic_abort(&f);
  CHECK(file_is(path, "second"));
  CHECK(count_prefixed(dir, "out.h.tmp.") == 0);

  /* Two writers of one path in one process get two temporaries. */
  sf_atomic_file a, b;
  CHECK(sf_atomic_open(&a, path, &err) == 0);
  CHECK(sf_atomic_open(&b, path, &err) == 0);
  CHECK(strcmp(a.temp_path, b.temp_path) != 0);
  CHECK(count_prefixed(dir, "out.h.tmp.") == 2);
  fputs("from a", a.stream);
  fputs("from b", b.stream);
  CHECK(sf_atomic_commit(&a, &err) == 0);
  CHECK(sf_atomic_commit(&b, &err) == 0);
  CHECK(file_is(path, "from b"));
  CHECK(count_prefixed(dir, "out.h.tmp.") == 0);

  /* A missing folder: an input error naming the path, nothing written. */
  char missing[600];
  snprintf(missing, sizeof missing, "%s/no-such-folder/out.h", dir);
  sf_error_clear(&err);
  CHECK(sf_atomic_open(&f, missing, &err) != 0);
  CHECK(err.status == SF_ERR_INPUT);
  printf("missing folder: %s\n", err.message);
  CHECK(strstr(err.message, missing) != NULL);

  test_other_kinds(dir);
  unlink(path);
  rmdir(dir);
  return check_summary();
}
