/* fit/mlp_lanes_fma.h: the baseline kernel's multiply-add by exact
 * arithmetic gives the bits of libm's correctly rounded fma (the
 * instruction on this machine when it has one), 8 lanes at a time, on:
 *   - random exponents and mantissas, products and sums of every scale;
 *   - cancellations: c = -RN(a b) and its neighbours (the result is the
 *     product's rounding error, the emulation's hardest part);
 *   - half-way cases: c = -RN(a b) +- 2^k just above the error's leading
 *     bit, so a b + c needs 54 bits, about 6 % of them exactly half-way
 *     (counted with __float128 while writing this test);
 *   - next to half-way: RN(a b) + c half-way, a b + c not (the rounding to
 *     odd decides these: without it, this kind fails);
 *   - short mantissas (exact products, ties of the sum);
 *   - random bit patterns (infinities, NaNs, subnormals: libm's lanes);
 *   - the edges of the exact path's domain (|a|, |b| = 2^-450, 2^500; |c| =
 *     2^1000; results near 2^-1021, zero and subnormal), signed zeros.
 * NaN against NaN counts as equal (payloads aside). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "models/rng.h"
#include "tests/check.h"
#include "tests/double_bits.h"

#if defined(__SSE2__)
#pragma GCC diagnostic ignored "-Wpsabi"
#include "fit/mlp_lanes_fma.h"

/* random sign and mantissa, exponent e */
static double with_exponent(sf_rng *rng, int e) {
  uint64_t mantissa = sf_rng_next(rng) & ((UINT64_C(1) << 52) - 1), sign = sf_rng_next(rng) & 1;
  return from_bits(sign << 63 | (uint64_t)(e + 1023) << 52 | mantissa);
}
static double exponent_in(sf_rng *rng, int lo, int hi) {
  return with_exponent(rng, lo + (int)(sf_rng_next(rng) % (uint64_t)(hi - lo + 1)));
}
/* the low k bits of the mantissa cleared, k random */
static double shortened(sf_rng *rng, double x) {
  return from_bits(to_bits(x) & ~((UINT64_C(1) << (sf_rng_next(rng) % 52)) - 1));
}

enum { RANDOM, CANCEL, HALF_WAY, NEAR_HALF_WAY, SHORT, BIT_PATTERNS, EDGES, N_KINDS };
static const char *const kind_names[N_KINDS] = {"random scales",   "cancellations",       "half-way cases",
                                                "next to half-way", "short mantissas",     "random bit patterns",
                                                "domain edges"};

/* One triple of a kind. */
static void make_triple(sf_rng *rng, int kind, double *a, double *b, double *c) {
  switch (kind) {
    case RANDOM:
      *a = exponent_in(rng, -60, 60);
      *b = exponent_in(rng, -60, 60);
      *c = exponent_in(rng, -130, 130);
      break;
    case CANCEL: {
      *a = exponent_in(rng, -5, 5);
      *b = exponent_in(rng, -5, 5);
      double p = *a * *b;
      *c = from_bits(to_bits(-p) + sf_rng_next(rng) % 7 - 3);
      break;
    }
    case HALF_WAY: {
      *a = exponent_in(rng, -8, 8);
      *b = exponent_in(rng, -8, 8);
      double p = *a * *b, error = fma(*a, *b, -p);
      *c = -p;
      if (error != 0.0) *c += ldexp(sf_rng_next(rng) & 1 ? 1.0 : -1.0, ilogb(error) + 1 + (int)(sf_rng_next(rng) % 3));
      break;
    }
    case NEAR_HALF_WAY: {
      /* a = RN(2^E / b): RN(a b) is 2^E about half the time, with an
       * error below half an ulp of 2^-53 2^E; c's last bit 2^(E+1), so
       * RN(a b) + c is half-way between doubles and a b + c just off it.
       * Rounding se + pe to nearest loses the error; only the rounding to
       * odd carries it through to break the tie. */
      *b = exponent_in(rng, -8, 8);
      *a = ldexp(1.0, (int)(sf_rng_next(rng) % 17) - 8) / *b;
      double p = *a * *b;
      int lowest = ilogb(p) - 52 + __builtin_ctzll(to_bits(p) | UINT64_C(1) << 52);
      *c = with_exponent(rng, lowest + 1 + 52);
      break;
    }
    case SHORT: {
      *a = shortened(rng, exponent_in(rng, -4, 4));
      *b = shortened(rng, exponent_in(rng, -4, 4));
      int e = ilogb(*a * *b);
      *c = shortened(rng, exponent_in(rng, e - 60, e + 2));
      break;
    }
    case BIT_PATTERNS:
      *a = from_bits(sf_rng_next(rng));
      *b = from_bits(sf_rng_next(rng));
      *c = from_bits(sf_rng_next(rng));
      break;
    default: {
      static const double edges[] = {0x1p-450, 0x1p+500, 0x1p+1000, 0x1p-1021, 0x1p-1022, 0x1p-1074, 0.0};
      double e = edges[sf_rng_next(rng) % 7];
      /* an edge, or one ulp either side, on one operand; c sometimes made
       * to cancel the product down to tiny or subnormal results */
      double near = from_bits(to_bits(e) + sf_rng_next(rng) % 3 - (e > 0.0 ? 1 : 0));
      *a = exponent_in(rng, -470, 520);
      *b = exponent_in(rng, -470, 520);
      *c = exponent_in(rng, -1074 + 52, 1023);
      switch (sf_rng_next(rng) % 4) {
        case 0: *a = near; break;
        case 1: *b = near; break;
        case 2: *c = near; break;
        default: {
          *a = exponent_in(rng, -520, -500);
          *b = exponent_in(rng, -520, -500);
          *c = from_bits(to_bits(-(*a * *b)) + sf_rng_next(rng) % 5 - 2);
        }
      }
      if (sf_rng_next(rng) % 8 == 0) *a = sf_rng_next(rng) & 1 ? -0.0 : 0.0;
      if (sf_rng_next(rng) % 8 == 0) *c = sf_rng_next(rng) & 1 ? -0.0 : 0.0;
      break;
    }
  }
}

static int same(double x, double y) { return (isnan(x) && isnan(y)) || to_bits(x) == to_bits(y); }

int main(void) {
  sf_rng rng;
  sf_rng_seed(&rng, 20261204, 0, 0);
  const long per_kind = 2000000;
  for (int kind = 0; kind < N_KINDS; ++kind) {
    long differ = 0;
    for (long i = 0; i < per_kind; i += 8) {
      sf_fma_lanes a, b, c;
      for (int k = 0; k < 8; ++k) {
        double ak, bk, ck;
        make_triple(&rng, kind, &ak, &bk, &ck);
        a[k] = ak;
        b[k] = bk;
        c[k] = ck;
      }
      sf_fma_lanes r = sf_fma_lanes_emulated(a, b, c);
      for (int k = 0; k < 8; ++k) {
        double want = fma(a[k], b[k], c[k]);
        if (same(r[k], want)) continue;
        if (differ < 5) printf("  differs: fma(%a, %a, %a) = %a, emulated %a\n", a[k], b[k], c[k], want, r[k]);
        differ += 1;
      }
    }
    printf("%-22s %8ld triples, %ld not libm's bits\n", kind_names[kind], per_kind, differ);
    CHECK(differ == 0);
  }

  /* signed zeros and specials, every combination */
  static const double special[] = {0.0, -0.0, 1.0, -1.0, 0x1p-1074, -0x1p-1074, INFINITY, -INFINITY, NAN, 3.0};
  const int ns = (int)(sizeof special / sizeof special[0]);
  long combos = 0, differ = 0;
  for (int i = 0; i < ns; ++i)
    for (int j = 0; j < ns; ++j)
      for (int l = 0; l < ns; l += 8) {
        sf_fma_lanes a, b, c;
        for (int k = 0; k < 8; ++k) {
          a[k] = special[i];
          b[k] = special[j];
          c[k] = special[(l + k) % ns];
        }
        sf_fma_lanes r = sf_fma_lanes_emulated(a, b, c);
        for (int k = 0; k < 8; ++k, ++combos)
          if (!same(r[k], fma(a[k], b[k], c[k]))) {
            if (differ++ < 5) printf("  differs: fma(%a, %a, %a), emulated %a\n", a[k], b[k], c[k], r[k]);
          }
      }
  printf("%-22s %8ld triples, %ld not libm's bits\n", "zeros and specials", combos, differ);
  CHECK(differ == 0);
  return check_summary();
}
#else
int main(void) {
  printf("no SSE2 (not x86): the multiply-add is an instruction, nothing emulated\n");
  return 0;
}
#endif
