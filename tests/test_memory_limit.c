/* util/memory_limit.h against the kernel itself: the limit never exceeds
 * physical memory; under RLIMIT_AS it names RLIMIT_AS, and it is right in
 * both directions — an allocation 64 MiB over the stated limit is refused
 * by the kernel, one of 3/4 of it succeeds and can be touched. A stale
 * temporary of a dead writer is removed by util/atomic_file.h, a live
 * one's is kept. */
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/atomic_file.h"
#include "util/memory_limit.h"

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif
#ifndef UNDER_ASAN
#define UNDER_ASAN 0
#endif

#define MIB (1024.0 * 1024.0)

static double status_kib(const char *key) {
  FILE *f = fopen("/proc/self/status", "r");
  if (!f) return -1.0;
  char line[256];
  double v = -1.0;
  while (fgets(line, sizeof line, f))
    if (strncmp(line, key, strlen(key)) == 0) sscanf(line + strlen(key), "%lf", &v);
  fclose(f);
  return v;
}

static void test_under_physical_memory(void) {
  char source[512];
  size_t limit = sf_memory_limit_bytes(source, sizeof source);
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  double phys = (double)pages * (double)page;
  printf("limit %.1f MiB (%s); physical memory %.1f MiB\n", limit / MIB, source, phys / MIB);
  CHECK(limit > 0);
  CHECK((double)limit <= phys);
}

static void test_address_space_cap(void) {
  if (UNDER_ASAN) {
    printf("skip RLIMIT_AS: AddressSanitizer reserves terabytes of address space\n");
    return;
  }
  double vm_kib = status_kib("VmSize:");
  if (vm_kib < 0) {
    printf("skip RLIMIT_AS: no /proc/self/status\n");
    return;
  }
  struct rlimit old;
  CHECK(getrlimit(RLIMIT_AS, &old) == 0);
  double headroom = 512.0 * MIB;
  struct rlimit cap = {(rlim_t)(vm_kib * 1024.0 + headroom), old.rlim_max};
  if (old.rlim_max != RLIM_INFINITY && cap.rlim_cur > old.rlim_max) cap.rlim_cur = old.rlim_max;
  CHECK(setrlimit(RLIMIT_AS, &cap) == 0);
  char source[512];
  size_t limit = sf_memory_limit_bytes(source, sizeof source);
  printf("RLIMIT_AS %.1f MiB with %.1f MiB mapped: limit %.1f MiB (%s)\n", cap.rlim_cur / MIB, vm_kib / 1024.0,
         limit / MIB, source);
  CHECK(strstr(source, "RLIMIT_AS") != NULL);
  /* the headroom, less what the calls above mapped (stdio buffers) */
  CHECK_REL((double)limit, headroom, 0.02);
  /* the kernel agrees: over the limit is refused, under it is granted */
  size_t over = limit + (size_t)(64 * MIB), under = limit / 4 * 3;
  /* through a volatile pointer: Clang removes a malloc whose block is only
   * freed, and takes it as granted */
  void *(*volatile allocate)(size_t) = malloc;
  void *p = allocate(over);
  printf("malloc(limit + 64 MiB = %.1f MiB): %s\n", over / MIB, p ? "granted" : "refused");
  CHECK(p == NULL);
  free(p);
  char *q = allocate(under);
  printf("malloc(3/4 limit = %.1f MiB): %s\n", under / MIB, q ? "granted" : "refused");
  CHECK(q != NULL);
  if (q) {
    memset(q, 1, under);
    CHECK(q[under - 1] == 1);
  }
  free(q);
  CHECK(setrlimit(RLIMIT_AS, &old) == 0);
}

/* A temporary named after a process that has exited is stale; one named
 * after a live process (this one's parent) is not. */
static void test_stale_temporaries(void) {
  char dir[] = "/tmp/skyfit-memory-limit-XXXXXX";
  if (!mkdtemp(dir)) {
    CHECK(0);
    return;
  }
  pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, NULL, 0);
  char target[256], dead[320], live[320];
  snprintf(target, sizeof target, "%s/out.json", dir);
  snprintf(dead, sizeof dead, "%s.tmp.%ld.AbCdEf", target, (long)child);
  snprintf(live, sizeof live, "%s.tmp.%ld.GhIjKl", target, (long)getppid());
  FILE *f = fopen(dead, "w");
  if (f) fclose(f);
  f = fopen(live, "w");
  if (f) fclose(f);
  sf_atomic_file out;
  sf_error err = {0};
  CHECK(sf_atomic_open(&out, target, &err) == 0);
  fputs("{}\n", out.stream);
  CHECK(sf_atomic_commit(&out, &err) == 0);
  struct stat st;
  int dead_left = stat(dead, &st) == 0, live_left = stat(live, &st) == 0, written = stat(target, &st) == 0;
  printf("after writing %s: dead writer's temporary %s, live writer's %s\n", target,
         dead_left ? "left" : "removed", live_left ? "kept" : "removed");
  CHECK(!dead_left);
  CHECK(live_left);
  CHECK(written);
  /* The same for a whole folder (sf_atomic_remove_stale_in: what an
   * interrupted build leaves, names unknown): the dead writer's temporary
   * of any name goes; the live one's, and names that only look alike,
   * stay. */
  char other[320], lookalike[320];
  snprintf(other, sizeof other, "%s/table.exr.tmp.%ld.MnOpQr", dir, (long)child);
  snprintf(lookalike, sizeof lookalike, "%s/notes.tmp.%ld.txt", dir, (long)child);
  const char *made[] = {other, lookalike, live};
  for (int i = 0; i < 3; ++i) {
    f = fopen(made[i], "w");
    if (f) fclose(f);
  }
  sf_atomic_remove_stale_in(dir);
  int other_left = stat(other, &st) == 0, lookalike_left = stat(lookalike, &st) == 0;
  live_left = stat(live, &st) == 0;
  printf("a folder swept: dead writer's temporary %s, live writer's %s, a look-alike name %s\n",
         other_left ? "left" : "removed", live_left ? "kept" : "removed", lookalike_left ? "kept" : "removed");
  CHECK(!other_left);
  CHECK(live_left);
  CHECK(lookalike_left);
  unlink(lookalike);
  unlink(other);
  unlink(live);
  unlink(target);
  unlink(dead);
  rmdir(dir);
}

int main(void) {
  test_under_physical_memory();
  test_address_space_cap();
  test_stale_temporaries();
  return check_summary();
}
