/* The training kernel's exponential (fit/mlp_lanes.h, sf_lanes_exp_n_capped)
 * as each build of the kernel compiles it (sf_mlp_exp_isa: baseline x86-64,
 * AVX2+FMA with its gathers, AVX-512 with its permutes, the Newton build),
 * against the portable representation (a struct of 8 doubles and libm's fma,
 * what compilers other than GCC and Clang get, compiled here), bit for bit,
 * at the exponential's cap (709) and the sigmoid's (700):
 *   - x evenly spaced over [-760, 760], past both clamps;
 *   - x at and next to every point where round(16 x / ln 2) changes (the
 *     table index and the power of two);
 *   - x at and next to the clamps, zeros, subnormals, infinities;
 *   - random bit patterns (every exponent, both signs, NaNs);
 *   - NaN with payloads, of either sign, gives NaN.
 * "Bit for bit" for NaN means NaN on both (payloads may differ). Builds the
 * CPU cannot run are skipped. tests/test_mlp_lanes.c measures the generic
 * representation against libm; tests/test_mlp_gradient.c whole kernels
 * against each other. */
#define SF_LANES_PORTABLE 1

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/mlp_backward.h"
#include "fit/mlp_lanes.h"
#include "models/rng.h"
#include "tests/check.h"
#include "tests/double_bits.h"

/* Values of x[0..n-1] whose e^x on the build isa differs from the portable
 * one (NaN: in being NaN), at both caps; prints the first. */
static long mismatches(sf_mlp_isa isa, const char *what, const double *x, long n, double *got, double *want) {
  static const double caps[] = {709.0, 700.0};
  long bad = 0;
  for (int c = 0; c < 2; ++c) {
    sf_mlp_exp_isa(isa, x, got, n, caps[c]);
    sf_lanes_exp_array(x, want, n, caps[c]);   /* this file's: the portable representation */
    for (long i = 0; i < n; ++i) {
      int same = isnan(want[i]) ? isnan(got[i]) != 0 : to_bits(got[i]) == to_bits(want[i]);
      if (!same) {
        if (bad == 0)
          printf("  %s, cap %g: first mismatch at x = %a: got %a, portable %a\n", what, caps[c], x[i], got[i], want[i]);
        bad += 1;
      }
    }
  }
  printf("  %-52s %8ld values, %ld not the portable bits\n", what, n, bad);
  return bad;
}

int main(void) {
  enum { MAX = 1 << 21 };
  double *x = malloc(sizeof(double) * MAX), *got = malloc(sizeof(double) * MAX), *want = malloc(sizeof(double) * MAX);
  CHECK(x && got && want);
  if (!x || !got || !want) return check_summary();
  int builds = 0;
  for (int q = SF_MLP_ISA_BASELINE; q < SF_MLP_ISA_COUNT; ++q) {
    sf_mlp_isa isa = (sf_mlp_isa)q;
    if (!sf_mlp_isa_available(isa)) {
      printf("%s: not on this CPU or build, skipped\n", sf_mlp_isa_name(isa));
      continue;
    }
    builds += 1;
    printf("%s:\n", sf_mlp_isa_name(isa));

    long n = 0;
    for (; n < MAX; ++n) x[n] = -760.0 + 1520.0 * (double)n / (MAX - 1);
    CHECK(mismatches(isa, "x evenly spaced over [-760, 760]", x, n, got, want) == 0);

    /* 16 x / ln 2 = k + 1/2: where the rounding to the table's grid turns */
    n = 0;
    for (long k = -16400; k < 16400; ++k) {
      double edge = ((double)k + 0.5) * (0.69314718055994530942 / 16.0);
      double below = nextafter(edge, -INFINITY), above = nextafter(edge, INFINITY);
      x[n++] = edge;
      x[n++] = below;
      x[n++] = above;
      x[n++] = nextafter(below, -INFINITY);
      x[n++] = nextafter(above, INFINITY);
    }
    CHECK(mismatches(isa, "at and next to each turn of round(16 x / ln 2)", x, n, got, want) == 0);

    n = 0;
    static const double ends[] = {700.0, 708.0, 709.0, 709.78, 745.0, 1e300};
    for (int e = 0; e < 6; ++e)
      for (int sign = -1; sign <= 1; sign += 2) {
        double v = sign * ends[e];
        x[n++] = v;
        x[n++] = nextafter(v, -INFINITY);
        x[n++] = nextafter(v, INFINITY);
      }
    static const double specials[] = {0.0, -0.0, 0x1p-1074, -0x1p-1074, 0x1p-1022, -0x1p-1022, INFINITY, -INFINITY};
    for (int s = 0; s < 8; ++s) x[n++] = specials[s];
    CHECK(mismatches(isa, "the clamps, zeros, subnormals, infinities", x, n, got, want) == 0);

    sf_rng rng;
    sf_rng_seed(&rng, 11, 0x65787062ull, 0);   /* "expb" */
    for (n = 0; n < MAX; ++n) {
      uint64_t bits = sf_rng_next(&rng);
      memcpy(&x[n], &bits, sizeof bits);
    }
    CHECK(mismatches(isa, "random bit patterns (NaNs among them)", x, n, got, want) == 0);

    static const uint64_t payloads[] = {0x7ff800000000abc0u, 0xfff8000000000ff0u, 0x7ff0000000000010u,
                                        0xfff0000000001230u, 0xfffffffffffffff0u};
    for (n = 0; n < 5; ++n) memcpy(&x[n], &payloads[n], sizeof x[n]);
    sf_mlp_exp_isa(isa, x, got, 5, 709.0);
    int nan_ok = 1;
    for (int k = 0; k < 5; ++k) nan_ok &= isnan(got[k]) != 0;
    printf("  NaNs with payloads stay NaN: %s\n", nan_ok ? "yes" : "no");
    CHECK(nan_ok);
  }
  CHECK(builds >= 1);
  free(x);
  free(got);
  free(want);
  return check_summary();
}
