#include "util/sort_doubles.h"

#include <stdlib.h>

static int compare_doubles(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

void sf_sort_doubles(double *v, size_t n) { qsort(v, n, sizeof *v, compare_doubles); }

double sf_median_doubles(double *v, size_t n) {
  sf_sort_doubles(v, n);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
