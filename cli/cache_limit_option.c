#include "cli/cache_limit_option.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MIB (1024LL * 1024)
#define MAX_MIB (1L << 30)

int sf_cli_parse_cache_limit(const char *command, const char *value, long long *bytes) {
  if (strcmp(value, "none") == 0) {
    *bytes = -1;
    return 0;
  }
  char *end;
  long mib = strtol(value, &end, 10);
  /* digits only: strtol also takes leading blanks and a sign (" 5", "+5") */
  if (*value < '0' || *value > '9' || *end != '\0' || mib < 0 || mib > MAX_MIB) {
    fprintf(stderr, "%s: --cache-limit: expected a size in MiB (0..%ld) or none, got '%s'\n", command, MAX_MIB,
            value);
    return 2;
  }
  *bytes = mib * MIB;
  return 0;
}

void sf_cli_print_cache_pruned(const char *command, const sf_cache_prune_result *res, long long limit_bytes) {
  long long kept = res->bytes - res->removed_bytes;
  if (res->removed <= 0) {
    if (limit_bytes >= 0 && kept > limit_bytes)
      printf("%s: cache: %d entries (%.1f MiB) over the limit of %lld MiB, all this run's own, never removed\n",
             command, res->entries, (double)kept / MIB, limit_bytes / MIB);
    return;
  }
  printf("%s: cache: removed %d entries unused the longest (%.1f MiB); %d kept (%.1f MiB, limit %lld MiB%s)\n",
         command, res->removed, (double)res->removed_bytes / MIB, res->entries - res->removed, (double)kept / MIB,
         limit_bytes / MIB, kept > limit_bytes ? ": this run's own entries, never removed, exceed it" : "");
}
