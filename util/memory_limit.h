/* How much memory this process may still allocate, so that a request that
 * cannot fit is refused up front with a message instead of ending in an
 * allocation failure halfway or in the kernel's OOM killer (issue 9).
 *
 * The limit is the smallest of:
 *  - MemAvailable of /proc/meminfo: the kernel's estimate of what can be
 *    allocated without swapping (free memory plus reclaimable page cache).
 *    Physical RAM (sysconf) would accept requests that only fit by pushing
 *    other processes into swap or getting this one OOM-killed; MemAvailable
 *    is what is actually available now. Where /proc is missing (not Linux):
 *    physical RAM, _SC_PHYS_PAGES x _SC_PAGE_SIZE;
 *  - the memory cgroup's limit less what the group already uses (without
 *    its inactive page cache, which the kernel reclaims first): cgroup v2
 *    memory.max / memory.current, v1 memory.limit_in_bytes /
 *    memory.usage_in_bytes, for this process's group and its ancestors;
 *  - RLIMIT_AS (ulimit -v) less the address space already mapped (VmSize),
 *    RLIMIT_DATA (ulimit -d) less the data already mapped (VmData). */
#ifndef SKYFIT_UTIL_MEMORY_LIMIT_H
#define SKYFIT_UTIL_MEMORY_LIMIT_H

#include <stddef.h>

/* Bytes this process may still allocate; source (size n) says which of the
 * limits above gave it, with its figures, for messages. SIZE_MAX with
 * "no memory limit found" when none could be read. */
size_t sf_memory_limit_bytes(char *source, size_t n);

#endif
