/* fit/mlp_lanes.h: the table-driven exponential of the training kernel
 * against libm's exp, in units in the last place, over the whole clamped
 * range, near 0 and at tiny arguments, every lane of a vector at once; the
 * clamps and NaN passing through; its table against 2^(j/16) computed
 * independently; several vectors at once against one at a time; and the
 * lane operations the kernel uses (select, abs, scale, max, min, negated
 * multiply-adds, table lookup) against their scalar definitions. This file is compiled without
 * instruction-set flags (the generic representation); the AVX2 and AVX-512
 * builds give the same bits (tests/test_mlp_exp_builds.c, the exponential
 * of each build against the portable one; tests/test_mlp_gradient.c,
 * kernel against kernel). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* the baseline's emulated multiply-add called, not inlined: inlined into
 * this file's unrolled loops it took GCC 330 s to compile at -O3
 * (fit/mlp_lanes_fma.h; the same arithmetic either way) */
#define SF_FMA_LANES_CALLED 1
#include "fit/mlp_lanes.h"
#include "tests/check.h"

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#endif

static double ulp_error(double got, double want) {
  double ulp = nextafter(want, INFINITY) - want;
  return fabs(got - want) / ulp;
}

/* Worst error over n + 1 evenly spaced x in [lo, hi], 8 per vector. */
static double worst_ulp(double lo, double hi, int n) {
  double worst = 0.0;
  for (int i = 0; i <= n; i += SF_LANES) {
    double x[SF_LANES], y[SF_LANES];
    for (int k = 0; k < SF_LANES; ++k) x[k] = lo + (hi - lo) * (double)(i + k < n ? i + k : n) / n;
    sf_lanes_store(y, sf_lanes_exp(sf_lanes_load(x)));
    for (int k = 0; k < SF_LANES; ++k) worst = worst_of(worst, ulp_error(y[k], exp(x[k])));
  }
  return worst;
}

int main(void) {
  double whole = worst_ulp(-708.0, 709.0, 2000000);
  double near0 = worst_ulp(-20.0, 20.0, 1000000);
  double tiny = worst_ulp(-1e-6, 1e-6, 100000);
  printf("sf_lanes_exp worst error vs libm exp: [-708, 709] %.3g ulp, [-20, 20] %.3g ulp, [-1e-6, 1e-6] %.3g ulp\n",
         whole, near0, tiny);
  CHECK(whole <= 2.0);
  CHECK(near0 <= 2.0);
  CHECK(tiny <= 2.0);

  /* Clamps, zero, NaN. */
  double x[SF_LANES] = {-1e6, -INFINITY, 1e6, INFINITY, 0.0, -0.0, NAN, 1.0}, y[SF_LANES];
  sf_lanes_store(y, sf_lanes_exp(sf_lanes_load(x)));
  CHECK_REL(y[0], exp(-708.0), 4.5e-16);
  CHECK_REL(y[1], exp(-708.0), 4.5e-16);
  CHECK_REL(y[2], exp(709.0), 4.5e-16);
  CHECK_REL(y[3], exp(709.0), 4.5e-16);
  CHECK(y[4] == 1.0 && y[5] == 1.0);
  CHECK(isnan(y[6]));
  CHECK_REL(y[7], exp(1.0), 4.5e-16);
  /* NaNs with payloads (x86 arithmetic carries a NaN operand's payload
   * through, which a scaling by integer addition to the exponent bits
   * would turn into a number), of either sign. */
  const uint64_t payloads[SF_LANES] = {0x7ff800000000abc0u, 0xfff8000000000ff0u, 0x7ff8fedcba987650u, 0x7ff0000000000010u,
                                       0xfff0000000001230u, 0x7ff800000000fff0u, 0xfffffffffffffff0u, 0x7ff8000000000100u};
  for (int k = 0; k < SF_LANES; ++k) memcpy(&x[k], &payloads[k], sizeof x[k]);
  sf_lanes_store(y, sf_lanes_exp(sf_lanes_load(x)));
  int nan_ok = 1;
  for (int k = 0; k < SF_LANES; ++k) nan_ok &= isnan(y[k]);
  printf("NaNs with payloads stay NaN: %s\n", nan_ok ? "yes" : "no");
  CHECK(nan_ok);

  /* Lane operations against their scalar definitions. */
  double a[SF_LANES] = {-3.5, 2.0, -0.0, 7.25, -1e-300, 1e300, 0.5, -2.0};
  double b[SF_LANES] = {1.0, 3.0, 0.0, -7.0, -2e-300, 1e299, 0.25, -2.0};
  double sel[SF_LANES], ab[SF_LANES], sc[SF_LANES], as[SF_LANES];
  sf_lanes va = sf_lanes_load(a), vb = sf_lanes_load(b);
  sf_lanes_store(sel, sf_lanes_select(sf_lanes_lt(va, vb), va, vb));
  sf_lanes_store(ab, sf_lanes_abs(va));
  sf_lanes_store(sc, sf_lanes_scale(va, 3.0));
  sf_lanes_store(as, sf_lanes_add_scalar(va, 0.125));
  int ops_ok = 1;
  for (int k = 0; k < SF_LANES; ++k) {
    double want_sel = a[k] < b[k] ? a[k] : b[k];
    ops_ok &= memcmp(&sel[k], &want_sel, sizeof(double)) == 0;
    ops_ok &= ab[k] == fabs(a[k]) && !signbit(ab[k]);
    ops_ok &= sc[k] == a[k] * 3.0 && as[k] == a[k] + 0.125;
  }
  printf("select, abs, scale, add_scalar match their scalar definitions on 8 lanes: %s\n", ops_ok ? "yes" : "no");
  CHECK(ops_ok);

  /* The negated multiply-adds: c - a w rounded once; and what the kernel's
   * forward pass relies on, u - a w = -(a w + (-u)) exactly (up to a
   * zero's sign), on lanes that round up, down, to even, cancel to zero
   * and overflow. */
  double c[SF_LANES] = {1.0, 0x1p-53, -0.0, 7.25 * -7.0, 1e-300, -1e300, 0.1, 3.0};
  double fn[SF_LANES], fns[SF_LANES];
  int fnma_ok = 1;
  const double ws[] = {0.1, -1.0 / 3.0, 1.0, 1e300, -0.0};
  for (int m = 0; m < 5; ++m) {
    sf_lanes_store(fn, sf_lanes_fnma_scalar(va, ws[m], sf_lanes_load(c)));
    for (int k = 0; k < SF_LANES; ++k) {
      sf_lanes_store(fns, sf_lanes_fnma_scalars(va, ws[m], c[k]));
      double want = fma(-a[k], ws[m], c[k]), negated = -fma(a[k], ws[m], -c[k]);
      fnma_ok &= memcmp(&fn[k], &want, sizeof want) == 0 && memcmp(&fns[k], &want, sizeof want) == 0;
      fnma_ok &= fn[k] == negated || (isnan(fn[k]) && isnan(negated));
    }
  }
  printf("fnma_scalar(s): c - a w rounded once, the negation of a w - c: %s\n", fnma_ok ? "yes" : "no");
  CHECK(fnma_ok);

  /* max and min: a > b ? a : b, a < b ? a : b, so b where either is NaN
   * (the x86 rule the clamps of sf_lanes_exp rely on to keep a NaN). */
  double p[SF_LANES] = {1.0, NAN, -0.0, 0.0, 3.0, -INFINITY, 2.0, NAN};
  double q[SF_LANES] = {2.0, 1.0, 0.0, -0.0, NAN, 5.0, 2.0, NAN};
  double mx[SF_LANES], mn[SF_LANES];
  sf_lanes_store(mx, sf_lanes_max(sf_lanes_load(p), sf_lanes_load(q)));
  sf_lanes_store(mn, sf_lanes_min(sf_lanes_load(p), sf_lanes_load(q)));
  int minmax_ok = 1;
  for (int k = 0; k < SF_LANES; ++k) {
    double want_max = p[k] > q[k] ? p[k] : q[k], want_min = p[k] < q[k] ? p[k] : q[k];
    minmax_ok &= memcmp(&mx[k], &want_max, sizeof(double)) == 0 && memcmp(&mn[k], &want_min, sizeof(double)) == 0;
  }
  printf("max, min: the x86 rule on zeros, NaN and equal lanes: %s\n", minmax_ok ? "yes" : "no");
  CHECK(minmax_ok);

  /* The table: entry j plus j << 48 and 1023 << 52 is the bits of 2^(j/16)
   * correctly rounded, against libm's long double exp2 (64-bit
   * significand: 11 bits beyond double's) rounded to double; and adding m
   * << 52 more scales it by 2^m, as sf_lanes_bits_add_shl48 of the low
   * bits 16 (m + 1023) + j does, for m at the ends of the clamped range
   * and between. */
  int table_ok = 1;
  static const int ms[] = {-1022, -1021, -500, -1, 0, 1, 700, 1022};
  for (int j = 0; j < 16; ++j) {
    uint64_t bits = sf_lanes_exp2_sixteenths_bits[j] + ((uint64_t)j << 48) + ((uint64_t)1023 << 52);
    double entry;
    memcpy(&entry, &bits, sizeof entry);
    table_ok &= entry == (double)exp2l(j / 16.0L);
    double low[SF_LANES], t[SF_LANES];
    for (int k = 0; k < SF_LANES; ++k) {
      /* the low bits as sf_lanes_exp's shifted holds them: 1.5 2^52 + n */
      double shifted = 6755399441055744.0 + (double)(16 * (ms[k] + 1023) + j);
      uint64_t table_bits = sf_lanes_exp2_sixteenths_bits[j];
      memcpy(&low[k], &shifted, sizeof shifted);
      memcpy(&t[k], &table_bits, sizeof t[k]);
    }
    double scaled[SF_LANES];
    sf_lanes_store(scaled, sf_lanes_bits_add_shl48(sf_lanes_load(t), sf_lanes_load(low)));
    for (int k = 0; k < SF_LANES; ++k) table_ok &= scaled[k] == ldexp(entry, ms[k]);
  }
  printf("exponential's table: 2^(j/16) for j = 0..15, times 2^m by the added bits: %s\n", table_ok ? "yes" : "no");
  CHECK(table_ok);
  /* lookup by the low 4 bits of each lane's bits, the rest ignored */
  uint64_t idx_bits[SF_LANES] = {0, 15, 16 + 3, 0xfff0u + 9, UINT64_MAX, 7, 0x4338000000000000u + 12, 1};
  double idx[SF_LANES], looked[SF_LANES];
  memcpy(idx, idx_bits, sizeof idx);
  sf_lanes_store(looked, sf_lanes_lookup16_bits(sf_lanes_exp2_sixteenths_bits, sf_lanes_load(idx)));
  int lookup_ok = 1;
  for (int k = 0; k < SF_LANES; ++k)
    lookup_ok &= memcmp(&looked[k], &sf_lanes_exp2_sixteenths_bits[idx_bits[k] & 15], sizeof(double)) == 0;
  printf("lookup16_bits reads table[bits & 15] on 8 lanes: %s\n", lookup_ok ? "yes" : "no");
  CHECK(lookup_ok);

  /* Several vectors at once (sf_lanes_exp_n, as the kernel's layers take
   * them): each the bits of its own sf_lanes_exp, whatever n and whatever
   * its neighbours hold (a step reading another vector's values fails). */
  int batch_ok = 1;
  for (int n = 1; n <= SF_LANES_EXP_MAX; ++n) {
    sf_lanes xs[SF_LANES_EXP_MAX];
    double in[SF_LANES_EXP_MAX][SF_LANES];
    for (int v = 0; v < n; ++v) {
      for (int k = 0; k < SF_LANES; ++k) in[v][k] = -750.0 + 1459.0 * (double)((v * 37 + k * 11 + n * 5) % 64) / 63.0;
      in[v][v % SF_LANES] = v % 2 ? NAN : -1e-300;
      xs[v] = sf_lanes_load(in[v]);
    }
    /* n a constant in each call, as in the kernel */
    switch (n) {
      case 1: sf_lanes_exp_n(xs, 1); break;
      case 2: sf_lanes_exp_n(xs, 2); break;
      case 3: sf_lanes_exp_n(xs, 3); break;
      case 4: sf_lanes_exp_n(xs, 4); break;
      case 5: sf_lanes_exp_n(xs, 5); break;
      case 6: sf_lanes_exp_n(xs, 6); break;
      case 7: sf_lanes_exp_n(xs, 7); break;
      default: sf_lanes_exp_n(xs, 8); break;
    }
    for (int v = 0; v < n; ++v) {
      double got[SF_LANES], want[SF_LANES];
      sf_lanes_store(got, xs[v]);
      sf_lanes_store(want, sf_lanes_exp(sf_lanes_load(in[v])));
      batch_ok &= memcmp(got, want, sizeof got) == 0;
    }
  }
  printf("exp of 1..%d vectors at once: the bits of one at a time: %s\n", SF_LANES_EXP_MAX, batch_ok ? "yes" : "no");
  CHECK(batch_ok);
  return check_summary();
}
