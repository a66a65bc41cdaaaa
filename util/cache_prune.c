#include "util/cache_prune.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/atomic_file.h"

void sf_cache_entry_used(const char *path) {
  if (path && path[0]) (void)utimensat(AT_FDCWD, path, NULL, 0);
}

typedef struct cache_entry {
  char path[4200];
  long long size;
  struct timespec used;
} cache_entry;

typedef struct entry_list {
  cache_entry *items;
  int count, capacity;
} entry_list;

/* "<name>-<16 lowercase hex digits>.<ext>", name not empty. */
static int is_entry_name(const char *file, const char *ext) {
  size_t n = strlen(file), e = strlen(ext);
  if (n < 1 + 1 + 16 + 1 + e) return 0;
  const char *hex = file + n - e - 1 - 16;
  if (hex[-1] != '-' || hex[16] != '.' || strcmp(hex + 17, ext) != 0) return 0;
  for (int i = 0; i < 16; ++i)
    if (!((hex[i] >= '0' && hex[i] <= '9') || (hex[i] >= 'a' && hex[i] <= 'f'))) return 0;
  return 1;
}

/* Adds the entries (regular files named as entries with extension ext) of
 * folder; a missing folder adds none. */
static int list_entries(const char *folder, const char *ext, entry_list *list, sf_error *err) {
  DIR *dir = opendir(folder);
  if (!dir) {
    if (errno == ENOENT) return SF_OK;
    return sf_fail(err, SF_ERR_INPUT, "cache %s: cannot list it: %s", folder, strerror(errno));
  }
  for (struct dirent *d; (d = readdir(dir)) != NULL;) {
    if (!is_entry_name(d->d_name, ext)) continue;
    if (list->count == list->capacity) {
      int capacity = list->capacity ? 2 * list->capacity : 64;
      cache_entry *grown = realloc(list->items, (size_t)capacity * sizeof *grown);
      if (!grown) {
        closedir(dir);
        return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
      }
      list->items = grown;
      list->capacity = capacity;
    }
    cache_entry *c = &list->items[list->count];
    int w = snprintf(c->path, sizeof c->path, "%s/%s", folder, d->d_name);
    struct stat st;
    if (w < 0 || (size_t)w >= sizeof c->path || lstat(c->path, &st) != 0 || !S_ISREG(st.st_mode)) continue;
    c->size = (long long)st.st_size;
    c->used = st.st_mtim;
    list->count += 1;
  }
  closedir(dir);
  return SF_OK;
}

static int time_before(struct timespec a, struct timespec b) {
  return a.tv_sec < b.tv_sec || (a.tv_sec == b.tv_sec && a.tv_nsec < b.tv_nsec);
}

const sf_cache_folder sf_cache_folders[SF_CACHE_FOLDERS] = {{"", "exr"}, {SF_CACHE_FITS, "json"},
                                                             {SF_CACHE_COSTS, "json"}};

/* Least recently used first; equal times in path order (a fixed order). */
static int compare_by_use(const void *pa, const void *pb) {
  const cache_entry *a = pa, *b = pb;
  if (time_before(a->used, b->used)) return -1;
  if (time_before(b->used, a->used)) return 1;
  return strcmp(a->path, b->path);
}

int sf_cache_prune(const char *cache_dir, long long limit_bytes, struct timespec used_since,
                   sf_cache_prune_result *res, sf_error *err) {
  memset(res, 0, sizeof *res);
  entry_list list = {0};
  char folder[4096];
  /* a `skyfit sample` folder: its tables are outputs, listed there */
  snprintf(folder, sizeof folder, "%s/tables.json", cache_dir);
  struct stat listing;
  int sample_outputs = lstat(folder, &listing) == 0;
  for (int s = 0; s < SF_CACHE_FOLDERS; ++s) {
    const sf_cache_folder *f = &sf_cache_folders[s];
    int w = snprintf(folder, sizeof folder, "%s%s%s", cache_dir, f->sub[0] ? "/" : "", f->sub);
    if (w < 0 || (size_t)w >= sizeof folder) {
      free(list.items);
      return sf_fail(err, SF_ERR_INPUT, "cache %s: folder name too long", cache_dir);
    }
    /* a killed run's temporaries (tens of MB for a table) are counted
     * nowhere and would stay for good */
    sf_atomic_remove_stale_older(folder, SF_CACHE_STALE_TEMP_SECONDS);
    if (sample_outputs && !f->sub[0]) continue;
    int listed = list_entries(folder, f->ext, &list, err);
    if (listed != SF_OK) {
      free(list.items);
      return listed;
    }
  }
  if (list.count > 1) qsort(list.items, (size_t)list.count, sizeof *list.items, compare_by_use);
  long long total = 0;
  int status = SF_OK;
  for (int i = 0; i < list.count; ++i) total += list.items[i].size;
  res->entries = list.count;
  res->bytes = total;
  for (int i = 0; limit_bytes >= 0 && i < list.count && total > limit_bytes; ++i) {
    const cache_entry *c = &list.items[i];
    if (!time_before(c->used, used_since)) break;   /* this run's, and all after it */
    if (unlink(c->path) != 0) {
      if (status == SF_OK)
        status = sf_fail(err, SF_ERR_INPUT, "cache %s: cannot remove it: %s", c->path, strerror(errno));
      continue;
    }
    total -= c->size;
    res->removed += 1;
    res->removed_bytes += c->size;
  }
  free(list.items);
  return status;
}
