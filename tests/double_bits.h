/* A double and its 64 bits, both ways (memcpy: no aliasing questions), for
 * the tests that compare results bit for bit or build special values. */
#ifndef SKYFIT_TESTS_DOUBLE_BITS_H
#define SKYFIT_TESTS_DOUBLE_BITS_H

#include <stdint.h>
#include <string.h>

static inline double from_bits(uint64_t u) {
  double d;
  memcpy(&d, &u, sizeof d);
  return d;
}

static inline uint64_t to_bits(double d) {
  uint64_t u;
  memcpy(&u, &d, sizeof u);
  return u;
}

#endif
