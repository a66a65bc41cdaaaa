/* The --cache-limit option of the commands that keep a cache folder of
 * their own (skyfit build and report: OUT/cache; skyfit fit spectral4: its
 * --cache, by default skyfit-cache beside W.json), and the line they print
 * when pruning removed entries (util/cache_prune.h). */
#ifndef SKYFIT_CLI_CACHE_LIMIT_OPTION_H
#define SKYFIT_CLI_CACHE_LIMIT_OPTION_H

#include "util/cache_prune.h"

/* Parses value, a size in MiB (0..2^30) or "none" (-1: no limit), into
 * *bytes. On a bad value prints "COMMAND: --cache-limit: ..." to stderr
 * and returns 2; else 0. */
int sf_cli_parse_cache_limit(const char *command, const char *value, long long *bytes);

/* After sf_cache_prune: "COMMAND: cache: removed ..." on stdout when it
 * removed entries, nothing otherwise. */
void sf_cli_print_cache_pruned(const char *command, const sf_cache_prune_result *res, long long limit_bytes);

#endif
