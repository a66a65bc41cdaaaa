/* fit/mlp_lanes_reciprocal.h: the AVX-512 Newton reciprocal of the
 * training kernel's sigmoids against the IEEE division 1.0 / d, bit for
 * bit, on its domain 1 <= d <= 2^1020:
 *   - d = (2 - 2^-52) 2^k, significand all ones, k = 0..1019: the one
 *     significand where Markstein's last step may round the wrong way
 *     (the header's proof), fixed by setting the last bit;
 *   - d = (2 - a 2^-52) 2^k for odd a: (2^53 - a)(2^53 + a) = 2^106 - a^2,
 *     so 1/d lies only a^2 2^-106 (relative) from a midpoint between two
 *     doubles (a = 1: as close as any 1/d comes), hard roundings;
 *   - powers of two, 1 + j 2^-52, and the ends of the domain;
 *   - random significands and exponents, and the sigmoid's own
 *     denominators 1 + e^x, x in [-745, 700];
 *   - NaN gives NaN.
 * Skipped where the CPU or the build has no AVX-512 (the kernel then
 * divides). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/mlp_backward.h"
#include "models/rng.h"
#include "tests/check.h"
#include "tests/double_bits.h"

/* Values of d[0..n-1] whose Newton reciprocal differs from 1.0 / d in any
 * bit; prints the first. */
static long mismatches(const char *what, const double *d, long n) {
  double *got = malloc(sizeof(double) * (size_t)n);
  if (!got) return n;
  sf_mlp_reciprocals_newton(d, got, n);
  long bad = 0;
  for (long i = 0; i < n; ++i) {
    double want = 1.0 / d[i];
    if (to_bits(got[i]) != to_bits(want)) {
      if (bad == 0) printf("  %s: first mismatch at d = %a: got %a, 1/d = %a\n", what, d[i], got[i], want);
      bad += 1;
    }
  }
  printf("%-58s %9ld values, %ld not bit for bit 1.0 / d\n", what, n, bad);
  free(got);
  return bad;
}

int main(void) {
  double probe = 2.0, probe_out;
  if (!sf_mlp_reciprocals_newton(&probe, &probe_out, 1)) {
    printf("skip: no AVX-512 kernel on this CPU or build\n");
    return check_summary();
  }
  enum { MAX = 1 << 22 };
  double *d = malloc(sizeof(double) * MAX);
  CHECK(d != NULL);
  if (!d) return check_summary();

  /* significand all ones, every exponent of the domain */
  long n = 0;
  for (int k = 0; k < 1020; ++k) d[n++] = ldexp(2.0 - 0x1p-52, k);
  CHECK(mismatches("d = (2 - 2^-52) 2^k, k = 0..1019", d, n) == 0);

  /* the hardest roundings: 1/d within a^2 2^-106 of a midpoint */
  static const int exps[] = {0, 1, 52, 511, 1019};
  n = 0;
  for (int e = 0; e < 5; ++e)
    for (long a = 1; a < (1L << 17); a += 2) d[n++] = ldexp(2.0 - (double)a * 0x1p-52, exps[e]);
  CHECK(mismatches("d = (2 - a 2^-52) 2^k, odd a < 2^17, 5 exponents", d, n) == 0);

  /* powers of two, just above 1, and the ends */
  n = 0;
  for (int k = 0; k <= 1020; ++k) d[n++] = ldexp(1.0, k);
  for (long j = 0; j < 100000; ++j) d[n++] = 1.0 + (double)j * 0x1p-52;
  d[n++] = nextafter(0x1p1020, 0.0);
  d[n++] = 1.0 + exp(700.0);
  CHECK(mismatches("powers of two, 1 + j 2^-52 (j < 1e5), the ends", d, n) == 0);

  /* random significands and exponents */
  sf_rng rng;
  sf_rng_seed(&rng, 7, 0x72637072ull, 0);   /* "rcpr" */
  for (n = 0; n < MAX; ++n) {
    uint64_t significand = sf_rng_next(&rng) >> 12;
    uint64_t exponent = 1023 + sf_rng_next(&rng) % 1020;
    d[n] = from_bits(exponent << 52 | significand);
  }
  CHECK(mismatches("random significands, exponents 0..1019", d, n) == 0);

  /* what the sigmoid divides by: 1 + e^x, x = -z up to its cap */
  for (n = 0; n < MAX; ++n) d[n] = 1.0 + exp(-745.0 + 1445.0 * sf_rng_uniform(&rng));
  CHECK(mismatches("1 + e^x, x uniform in [-745, 700]", d, n) == 0);
  for (n = 0; n < MAX; ++n) d[n] = 1.0 + exp(-40.0 + 80.0 * sf_rng_uniform(&rng));
  CHECK(mismatches("1 + e^x, x uniform in [-40, 40]", d, n) == 0);

  double nan_in = NAN, nan_out = 0.0;
  sf_mlp_reciprocals_newton(&nan_in, &nan_out, 1);
  printf("1 / NaN = %g\n", nan_out);
  CHECK(isnan(nan_out));
  free(d);
  return check_summary();
}
