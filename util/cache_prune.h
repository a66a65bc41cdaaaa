/* A cache folder (OUT/cache of `skyfit build` and `skyfit report`; the
 * spectral tables' cache of `skyfit fit spectral4`, by default
 * skyfit-cache beside W.json) kept under a size limit, least recently used
 * entries removed first.
 *
 * Why: every entry's key names what made it, so entries that can no longer
 * be hit stay behind: tables of each atmosphere tried (tens of MB each, the
 * mission being to retrain for new atmospheres), and fits and timings of
 * every rebuilt skyfit executable (fit/candidate_cache.h keys them on a
 * hash of its bytes). Nothing else ever removes them.
 *
 * An entry is a file named "<name>-<16 hex digits>.<ext>" (the keys of
 * data/table_cache.h and fit/candidate_cache.h): tables, .exr, in the folder
 * itself; fits and timings, .json, in its fits/ and costs/ folders. No
 * other file is removed (but the temporaries below), nor the tables of a
 * folder that holds a tables.json: `skyfit sample`'s output folder, whose
 * tables are its outputs (`fit spectral4 --cache` pointed there had
 * removed them all, leaving tables.json listing missing files). An
 * entry's last use is its modification time: a cache hit marks the entry
 * used (sf_cache_entry_used), a miss writes it anew. Pruning also
 * removes, at any limit, the temporaries of writers that
 * do not run here and have not written for SF_CACHE_STALE_TEMP_SECONDS
 * (util/atomic_file.h: a shared cache's other writers are other hosts'). */
#ifndef SKYFIT_UTIL_CACHE_PRUNE_H
#define SKYFIT_UTIL_CACHE_PRUNE_H

#include <time.h>

#include "util/error.h"

/* The default limit of a build's cache: 2 GiB, about sixty atmospheres'
 * tables at the build's default resolution (34 MB each). */
#define SF_CACHE_LIMIT_DEFAULT_BYTES (2048LL * 1024 * 1024)
/* A dead writer's temporary is removed once this old (above). */
#define SF_CACHE_STALE_TEMP_SECONDS 3600

/* The cache's folders, relative to the cache folder ("" the folder
 * itself), and the extension of the entries each holds: tables; fits
 * (SF_CACHE_FITS) and timings (SF_CACHE_COSTS), the subfolders that
 * fit/candidate_cache.h's sf_cache_path writes into. The one list of them
 * that pruning and an interrupted build's cleanup (cli/build_command.c)
 * walk. */
#define SF_CACHE_FITS "fits"
#define SF_CACHE_COSTS "costs"
typedef struct sf_cache_folder {
  const char *sub, *ext;
} sf_cache_folder;
#define SF_CACHE_FOLDERS 3
extern const sf_cache_folder sf_cache_folders[SF_CACHE_FOLDERS];

/* Marks the cache entry at path used now (its modification time), so that
 * pruning keeps it before those unused longer. Silent: an entry that
 * cannot be marked is only removed sooner. */
void sf_cache_entry_used(const char *path);

typedef struct sf_cache_prune_result {
  int entries;                  /* entries found */
  long long bytes;              /* their sizes, before pruning */
  int removed;                  /* entries removed */
  long long removed_bytes;
} sf_cache_prune_result;

/* Removes entries of cache_dir, the least recently used first (equal times:
 * in name order), until their sizes add up to limit_bytes at most; entries
 * used at or after used_since (this run's) are never removed, even over the
 * limit. limit_bytes < 0: no limit, nothing removed. A missing cache_dir
 * holds no entries. An entry that cannot be removed is skipped and the
 * first such failure reported (SF_ERR_INPUT, naming the file) after the
 * others were tried; *res counts what was removed. */
int sf_cache_prune(const char *cache_dir, long long limit_bytes, struct timespec used_since,
                   sf_cache_prune_result *res, sf_error *err);

#endif
