/* util/cache_prune.h: a build's cache kept under a size limit. Entries
 * (tables "<name>-<16 hex>.exr" in the folder, fits and timings ".json" in
 * fits/ and costs/) go least recently used first, until the rest fit the
 * limit; this run's entries stay even over it; files not named as entries,
 * other folders and entries of the wrong kind stay; a cache hit marks an
 * entry used. Sizes and times are set here, so the expected survivors
 * follow from the rule alone. */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/cache_prune.h"

typedef struct planted {
  const char *rel;    /* path under the cache folder */
  long size;          /* bytes */
  long age;           /* seconds before now; < 0: after used_since (this run's) */
} planted;

/* Sizes chosen so that every subset has its own sum. */
static const planted files[] = {
    {"transmittance-0123456789abcdef.exr", 1000, 500},     /* oldest entry */
    {"single_mie-00000000ffffffff.exr", 5000, 400},
    {"fits/hosek-fedcba9876543210.json", 100, 300},
    {"costs/hosek-fedcba9876543210.json", 50, 300},       /* same time: path order, costs/ first */
    {"fits/sigmoid-1111111111111111.json", 3000, -1},     /* used by this run */
    /* not entries: never looked at */
    {"notes.txt", 20000, 9000},
    {"weights.json", 20000, 9000},
    {"fits/hosek-0123.json", 20000, 9000},                 /* 4 hex digits */
    {"fits/hosek-0123456789ABCDEF.json", 20000, 9000},     /* upper case */
    {"fits/hosek-0123456789abcdef.exr", 20000, 9000},      /* a table's extension in fits/ */
    {"multiple-0123456789abcdef.json", 20000, 9000},       /* a fit's extension beside the tables */
    {"multiple-0123456789abcdef.exr.tmp.1.abcdef", 20000, 9000},   /* a write in progress (pid 1 runs) */
    {"views/ground-0123456789abcdef.exr", 20000, 9000},   /* another folder */
};
#define N_FILES (int)(sizeof files / sizeof files[0])
#define N_ENTRIES 5

static int plant(const char *dir, const planted *p, time_t now) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, p->rel);
  FILE *f = fopen(path, "wb");
  if (!f) return -1;
  for (long i = 0; i < p->size; ++i) fputc('x', f);
  fclose(f);
  struct timespec t[2] = {{now - p->age, 0}, {now - p->age, 0}};
  return utimensat(AT_FDCWD, path, t, 0);
}

static int exists(const char *dir, const char *rel) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, rel);
  struct stat st;
  return stat(path, &st) == 0;
}

static void make_cache(const char *dir, time_t now) {
  const char *subs[] = {"fits", "costs", "views"};
  for (int s = 0; s < 3; ++s) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, subs[s]);
    mkdir(path, 0777);
  }
  for (int i = 0; i < N_FILES; ++i) CHECK(plant(dir, &files[i], now) == 0);
}

/* Which planted files survive a prune to limit: printed, and compared. */
static void prune_and_check(const char *dir, long long limit, struct timespec since, const int *survives,
                            int want_removed, long long want_removed_bytes) {
  sf_cache_prune_result res;
  sf_error err = {0};
  CHECK(sf_cache_prune(dir, limit, since, &res, &err) == SF_OK);
  printf("limit %lld: %d entries, %lld bytes; removed %d, %lld bytes\n", limit, res.entries, res.bytes,
         res.removed, res.removed_bytes);
  CHECK(res.removed == want_removed);
  CHECK(res.removed_bytes == want_removed_bytes);
  for (int i = 0; i < N_FILES; ++i) {
    int kept = exists(dir, files[i].rel);
    printf("  %-48s %s\n", files[i].rel, kept ? "kept" : "removed");
    CHECK(kept == survives[i]);
  }
}

int main(void) {
  char dir[] = "/tmp/skyfit-cache-prune-XXXXXX";
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return 1;
  }
  time_t now = time(NULL);
  struct timespec since = {now - 60, 0};   /* the run started a minute ago */
  make_cache(dir, now);

  /* No limit: nothing goes. */
  int all[N_FILES];
  for (int i = 0; i < N_FILES; ++i) all[i] = 1;
  prune_and_check(dir, -1, since, all, 0, 0);

  /* 9150 bytes of entries against 3200: the two oldest tables go (1000,
   * then 5000: 3150 left), the fits and timings, younger, stay. */
  int over_3200[N_FILES];
  memcpy(over_3200, all, sizeof all);
  over_3200[0] = over_3200[1] = 0;
  prune_and_check(dir, 3200, since, over_3200, 2, 6000);

  /* Limit 0: every entry older than the run goes, the timing before the fit
   * of the same time (path order); this run's fit stays over the limit. */
  int over_0[N_FILES];
  memcpy(over_0, over_3200, sizeof all);
  over_0[2] = over_0[3] = 0;
  prune_and_check(dir, 0, since, over_0, 2, 150);

  /* A hit marks an entry used: an old entry marked stays at limit 0. */
  CHECK(plant(dir, &files[0], now) == 0);
  sf_cache_entry_used(NULL);   /* no entry: nothing */
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, files[0].rel);
  sf_cache_entry_used(path);
  struct stat st;
  CHECK(stat(path, &st) == 0 && st.st_mtim.tv_sec >= now);
  over_0[0] = 1;
  prune_and_check(dir, 0, since, over_0, 0, 0);

  /* Equal times go in path order: the oldest table (1000 bytes) leaves
   * 3150 against 3100, then of the fit and the timing of one time the
   * timing goes ("costs/" before "fits/"). */
  CHECK(plant(dir, &files[0], now) == 0 && plant(dir, &files[2], now) == 0 && plant(dir, &files[3], now) == 0);
  int tie[N_FILES];
  memcpy(tie, over_0, sizeof tie);
  tie[0] = 0;
  tie[2] = 1;
  tie[3] = 0;
  prune_and_check(dir, 3100, since, tie, 2, 1050);

  /* A folder holding tables.json is a `skyfit sample` output: its tables
   * stay at limit 0, its other entries go as before. */
  const planted listing = {"tables.json", 10, 9000};
  CHECK(plant(dir, &files[0], now - 3600) == 0 && plant(dir, &files[2], now - 3600) == 0 && plant(dir, &listing, now) == 0);
  int sample_folder[N_FILES];
  memcpy(sample_folder, tie, sizeof tie);
  sample_folder[0] = 1;   /* the table, an hour older than before */
  sample_folder[2] = 0;   /* the fit */
  prune_and_check(dir, 0, since, sample_folder, 1, 100);

  /* A killed writer's temporaries go at any limit once an hour old (pid
   * 999999999 runs nowhere: Linux's pid_max is at most 4194304); a younger
   * one may be another host's writer on a shared cache, and stays. */
  const planted stale[3] = {{"multiple-0123456789abcdef.exr.tmp.999999999.abcdef", 30000, 9000},
                            {"fits/sigmoid-1111111111111111.json.tmp.999999999.abcdef", 30000, 9000},
                            {"costs/sigmoid-1111111111111111.json.tmp.999999999.abcdef", 30000, 60}};
  CHECK(plant(dir, &stale[0], now) == 0 && plant(dir, &stale[1], now) == 0 && plant(dir, &stale[2], now) == 0);
  prune_and_check(dir, -1, since, sample_folder, 0, 0);
  CHECK(!exists(dir, stale[0].rel) && !exists(dir, stale[1].rel) && exists(dir, stale[2].rel));

  /* A missing folder holds no entries; a folder name too long is refused. */
  sf_cache_prune_result res;
  sf_error err = {0};
  CHECK(sf_cache_prune("/nonexistent/skyfit-cache", 0, since, &res, &err) == SF_OK && res.entries == 0);
  char long_name[5000];
  memset(long_name, 'a', sizeof long_name - 1);
  long_name[sizeof long_name - 1] = '\0';
  CHECK(sf_cache_prune(long_name, 0, since, &res, &err) == SF_ERR_INPUT);
  printf("long name: %.60s...\n", err.message);

  char cmd[600];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) printf("note: could not remove %s\n", dir);
  return check_summary();
}
