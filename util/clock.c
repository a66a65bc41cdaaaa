#include "util/clock.h"

#include <time.h>

static double seconds_of(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sf_wall_seconds(void) { return seconds_of(CLOCK_MONOTONIC); }
double sf_cpu_seconds(void) { return seconds_of(CLOCK_PROCESS_CPUTIME_ID); }
