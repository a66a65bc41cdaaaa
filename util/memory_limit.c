#include "util/memory_limit.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#define GIB (1024.0 * 1024.0 * 1024.0)
/* cgroup v1 writes "no limit" as 2^63 rounded down to pages; v2 as "max". */
#define NO_LIMIT ((uint64_t)1 << 62)

/* The smallest limit seen so far and what it came from. */
typedef struct limit_pick {
  double bytes;
  char *source;
  size_t n;
} limit_pick;

static void consider(limit_pick *p, double bytes, const char *source) {
  if (bytes < 0.0) bytes = 0.0;
  if (bytes >= p->bytes) return;
  p->bytes = bytes;
  snprintf(p->source, p->n, "%s", source);
}

/* The number after "key" (e.g. "MemAvailable:") in a "key value" text file. */
static int read_field(const char *path, const char *key, double *value) {
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  char line[512];
  size_t key_len = strlen(key);
  int found = 0;
  while (!found && fgets(line, sizeof line, f)) {
    if (strncmp(line, key, key_len) != 0) continue;
    found = sscanf(line + key_len, "%lf", value) == 1;
  }
  fclose(f);
  return found;
}

/* A file holding one number, or "max" (returned as NO_LIMIT). */
static int read_number_file(const char *path, double *value) {
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  char text[64] = {0};
  int ok = fgets(text, sizeof text, f) != NULL;
  fclose(f);
  if (!ok) return 0;
  if (strncmp(text, "max", 3) == 0) {
    *value = (double)NO_LIMIT;
    return 1;
  }
  return sscanf(text, "%lf", value) == 1;
}

static void consider_meminfo(limit_pick *p) {
  double kib;
  if (read_field("/proc/meminfo", "MemAvailable:", &kib)) {
    consider(p, kib * 1024.0, "MemAvailable in /proc/meminfo");
    return;
  }
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) consider(p, (double)pages * (double)page, "physical memory (sysconf)");
#endif
}

/* One cgroup folder: its limit less its use (inactive page cache aside). */
static void consider_cgroup_dir(limit_pick *p, const char *dir, int v2) {
  char path[4400], text[4600];
  double limit, usage = 0.0, inactive = 0.0;
  snprintf(path, sizeof path, "%s/%s", dir, v2 ? "memory.max" : "memory.limit_in_bytes");
  if (!read_number_file(path, &limit) || limit >= (double)NO_LIMIT) return;
  snprintf(path, sizeof path, "%s/%s", dir, v2 ? "memory.current" : "memory.usage_in_bytes");
  if (!read_number_file(path, &usage)) usage = 0.0;
  snprintf(path, sizeof path, "%s/memory.stat", dir);
  if (!read_field(path, v2 ? "inactive_file " : "total_inactive_file ", &inactive)) inactive = 0.0;
  double used = usage > inactive ? usage - inactive : 0.0;
  snprintf(text, sizeof text, "cgroup %s %s/%s of %.2f GiB, %.2f GiB of it in use", v2 ? "v2" : "v1", dir,
           v2 ? "memory.max" : "memory.limit_in_bytes", limit / GIB, used / GIB);
  consider(p, limit - used, text);
}

/* The group at root/group and every ancestor up to root (a parent's limit
 * holds for its children too). */
static void consider_cgroup_tree(limit_pick *p, const char *root, const char *group, int v2) {
  char dir[4096];
  int len = snprintf(dir, sizeof dir, "%s%s", root, strcmp(group, "/") == 0 ? "" : group);
  if (len < 0 || (size_t)len >= sizeof dir) return;
  size_t root_len = strlen(root);
  for (;;) {
    consider_cgroup_dir(p, dir, v2);
    char *slash = strrchr(dir, '/');
    if (!slash || (size_t)(slash - dir) < root_len) break;
    *slash = '\0';
  }
}

static void consider_cgroups(limit_pick *p) {
  FILE *f = fopen("/proc/self/cgroup", "r");
  if (!f) return;
  char line[4096];
  while (fgets(line, sizeof line, f)) {
    line[strcspn(line, "\n")] = '\0';
    /* "id:controllers:path"; v2 is "0::path" */
    char *first = strchr(line, ':');
    char *second = first ? strchr(first + 1, ':') : NULL;
    if (!second) continue;
    *second = '\0';
    const char *controllers = first + 1, *group = second + 1;
    if (group[0] != '/') continue;
    if (controllers[0] == '\0') {
      consider_cgroup_tree(p, "/sys/fs/cgroup", group, 1);
      consider_cgroup_tree(p, "/sys/fs/cgroup/unified", group, 1);
    } else {
      /* one of a comma-separated list */
      char list[256];
      snprintf(list, sizeof list, ",%s,", controllers);
      if (strstr(list, ",memory,")) consider_cgroup_tree(p, "/sys/fs/cgroup/memory", group, 0);
    }
  }
  fclose(f);
}

/* RLIMIT_AS or RLIMIT_DATA less what this process already has mapped. */
static void consider_rlimit(limit_pick *p, int resource, const char *name, const char *status_key) {
  struct rlimit rl;
  if (getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return;
  double kib = 0.0;
  if (!read_field("/proc/self/status", status_key, &kib)) kib = 0.0;
  char text[256];
  snprintf(text, sizeof text, "%s of %.2f GiB, %.2f GiB of it already mapped", name, (double)rl.rlim_cur / GIB,
           kib * 1024.0 / GIB);
  consider(p, (double)rl.rlim_cur - kib * 1024.0, text);
}

size_t sf_memory_limit_bytes(char *source, size_t n) {
  limit_pick p = {(double)SIZE_MAX, source, n};
  if (n > 0) snprintf(source, n, "no memory limit found");
  consider_meminfo(&p);
  consider_cgroups(&p);
  consider_rlimit(&p, RLIMIT_AS, "RLIMIT_AS (ulimit -v)", "VmSize:");
  consider_rlimit(&p, RLIMIT_DATA, "RLIMIT_DATA (ulimit -d)", "VmData:");
  return p.bytes >= (double)SIZE_MAX ? SIZE_MAX : (size_t)p.bytes;
}
