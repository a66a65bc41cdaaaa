/* Sorting doubles (qsort with the comparison every caller needs) and the
 * median of a sample, for timings and statistics. */
#ifndef SKYFIT_UTIL_SORT_DOUBLES_H
#define SKYFIT_UTIL_SORT_DOUBLES_H

#include <stddef.h>

/* v[0..n-1] in ascending order (no NaN). */
void sf_sort_doubles(double *v, size_t n);
/* The median of v[0..n-1] (n >= 1; the mean of the two middle values when n
 * is even); sorts v. */
double sf_median_doubles(double *v, size_t n);

#endif
