/* Clocks for progress, ETAs and benchmarks: wall time that never jumps
 * (CLOCK_MONOTONIC) and the CPU time of the whole process, every thread
 * (CLOCK_PROCESS_CPUTIME_ID), both in seconds from an arbitrary origin. */
#ifndef SKYFIT_UTIL_CLOCK_H
#define SKYFIT_UTIL_CLOCK_H

double sf_wall_seconds(void);
double sf_cpu_seconds(void);

#endif
