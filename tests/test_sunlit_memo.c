/* The memo of the single tables' sunlit air (data/sample_memo.h, kept by
 * the table set for data/sky_lookup.c). The memo alone: records read back
 * as first kept, per sample, storage taken only for the slices used. The
 * lookup: with the memo, filled by 4 threads at once and then read back,
 * the same bits as without it (F computed at every corner, as before the
 * memo) at 1040 low-sun views, in both parameterisations (their mu_s
 * axes differ: 0 for Bruneton, 2 for Leenman). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/parallel_rows.h"
#include "data/sample_memo.h"
#include "data/sky_lookup.h"
#include "data/table_interp.h"
#include "data/table_set.h"
#include "models/atmosphere_file.h"
#include "tests/check.h"
#include "util/constants.h"

static void record_of(long offset, double *r) {
  r[0] = (double)offset;
  r[1] = 0.5 * (double)offset + 1.0;
  r[2] = -(double)offset;
}

static void memo_checks(void) {
  const int size[4] = {3, 4, 5, 2};
  const long n = 3 * 4 * 5 * 2, per_slice = 3 * 4 * 2;
  CHECK(sf_sample_memo_make(size, 4, 3) == NULL);
  CHECK(sf_sample_memo_make(size, 2, 0) == NULL);
  sf_sample_memo *m = sf_sample_memo_make(size, 2, 3);
  if (!CHECK(m != NULL)) return;
  CHECK(sf_sample_memo_record_len(m) == 3);
  double r[3], got[3];
  int none = 1;
  for (long o = 0; o < n; ++o) none &= !sf_sample_memo_get(m, o, got);
  CHECK(none);
  /* slice 1 of axis 2 only: offsets whose third index is 1 */
  size_t before = sf_sample_memo_bytes(m);
  for (long o = 0; o < n; ++o)
    if ((o / (3 * 4)) % 5 == 1) {
      record_of(o, r);
      sf_sample_memo_put(m, o, r);
    }
  size_t grew = sf_sample_memo_bytes(m) - before, records = (size_t)per_slice * (3 * sizeof(double) + 1);
  printf("one slice: %zu bytes (its records and states %zu)\n", grew, records);
  CHECK(grew >= records && grew <= records + 64);
  int kept_right = 1;
  for (long o = 0; o < n; ++o) {
    int in_slice = (o / (3 * 4)) % 5 == 1, held = sf_sample_memo_get(m, o, got);
    record_of(o, r);
    kept_right &= held == in_slice && (!held || memcmp(got, r, sizeof r) == 0);
  }
  CHECK(kept_right);
  /* the first record kept stays */
  long o = 2 + 3 * (0 + 4 * (1 + 5 * 1));   /* index (2, 0, 1, 1) */
  double other[3] = {7.0, 8.0, 9.0};
  sf_sample_memo_put(m, o, other);
  record_of(o, r);
  CHECK(sf_sample_memo_get(m, o, got) && memcmp(got, r, sizeof r) == 0);
  /* every sample */
  for (long k = 0; k < n; ++k) {
    record_of(k, r);
    sf_sample_memo_put(m, k, r);
  }
  int all = 1;
  for (long k = 0; k < n; ++k) {
    record_of(k, r);
    all &= sf_sample_memo_get(m, k, got) && memcmp(got, r, sizeof r) == 0;
  }
  CHECK(all);
  CHECK(sf_sample_memo_bytes(m) - before == 5 * (grew));
  sf_sample_memo_free(m);
}

/* Views: sun -11..+14 deg (every lookup through the sunlit air, some
 * blended), altitudes 0..60 km, view elevations and azimuths around. */
enum { N_SUN = 13, N_H = 4, N_EL = 5, N_AZ = 4, N_VIEWS = N_SUN * N_H * N_EL * N_AZ };

static void view_of(long v, double *h, double *mu, double *mu_s, double *nu) {
  int az = v % N_AZ, el = (v / N_AZ) % N_EL, ih = (v / (N_AZ * N_EL)) % N_H, sun = v / (N_AZ * N_EL * N_H);
  double D = SF_PI / 180.0, e_sun = (-11.0 + 25.0 * sun / (N_SUN - 1)) * D, e = (-60.0 + 37.0 * el) * D;
  *h = 20.0 * ih;
  *mu = sin(e);
  *mu_s = sin(e_sun);
  *nu = *mu * *mu_s + cos(e) * cos(e_sun) * cos(55.0 * az * D);
}

typedef struct lookups {
  const sf_sky_tables *sky;
  sf_sky_sample *out;
} lookups;

static void lookup_row(void *ctx, int thread, long v) {
  (void)thread;
  const lookups *l = ctx;
  double h, mu, mu_s, nu;
  view_of(v, &h, &mu, &mu_s, &nu);
  sf_sky_lookup(l->sky, h, mu, mu_s, nu, &l->out[v]);
}

static int same_single(const sf_sky_sample *a, const sf_sky_sample *b, long n) {
  for (long v = 0; v < n; ++v)
    if (memcmp(a[v].single, b[v].single, sizeof a[v].single) != 0) return 0;
  return 1;
}

static void lookup_checks(const char *name, sf_parameterization kind, const char *res) {
  sf_atmosphere a;
  sf_atmosphere_default(&a);
  sf_atmosphere_finalize(&a);
  sf_table_set_options o;
  sf_table_set_options_default(&o);
  o.kind = kind;
  o.orders = 1;
  o.stop_fraction = 0.0;
  o.run.n_threads = 2;
  sf_error err = {0};
  sf_table_set set;
  if (!CHECK(sf_table_resolution_parse(res, &o.res, &err) == 0)) return;
  if (!CHECK(sf_table_set_make(&set, &a, &o, &err) == 0)) return;
  sf_sky_tables sky, bare;
  sf_sky_tables_of_set(&sky, &a, &set);
  bare = sky;
  bare.sunlit = NULL;
  CHECK(sky.sunlit == set.single_sunlit && sky.sunlit != NULL);
  /* the memo is the set's atmosphere's: a view of another (same channels
   * and constituents, a denser Mie) must not read its F */
  sf_atmosphere other = a;
  for (int ch = 0; ch < other.n_channels; ++ch) other.constituents[1].scattering[ch] *= 2.0;
  sf_sky_tables other_sky;
  sf_sky_tables_of_set(&other_sky, &other, &set);
  CHECK(other_sky.sunlit == NULL);
  sf_sky_sample *want = calloc(N_VIEWS, sizeof *want), *got = calloc(N_VIEWS, sizeof *got);
  if (!CHECK(want && got)) {
    free(want);
    free(got);
    sf_table_set_free(&set);
    return;
  }
  lookups serial_bare = {&bare, want}, memo = {&sky, got};
  sf_precompute_options one = {0}, four = {0};
  one.n_threads = 1;
  four.n_threads = 4;
  size_t empty = sf_sample_memo_bytes(set.single_sunlit);
  sf_parallel_rows(N_VIEWS, &one, NULL, lookup_row, &serial_bare);
  sf_parallel_rows(N_VIEWS, &four, NULL, lookup_row, &memo);   /* filling it */
  size_t filled = sf_sample_memo_bytes(set.single_sunlit);
  printf("%s: memo %zu bytes after %d views\n", name, filled, N_VIEWS);
  CHECK(filled > empty);
  CHECK(same_single(got, want, N_VIEWS));
  memset(got, 0, N_VIEWS * sizeof *got);
  sf_parallel_rows(N_VIEWS, &one, NULL, lookup_row, &memo);    /* read back */
  CHECK(same_single(got, want, N_VIEWS));
  CHECK(sf_sample_memo_bytes(set.single_sunlit) == filled);
  /* the lookups read what the memo holds: a copy of it with every record
   * doubled halves their single scattering (corners over 2F, times F at
   * the point) wherever the sunlit air is all of it */
  sf_grid_view g = sf_grid_view_of(&set.single[0]);
  int rec_len = sf_sample_memo_record_len(set.single_sunlit);
  sf_sample_memo *doubled = sf_sample_memo_make(g.size, kind == SF_PARAM_BRUNETON ? 0 : 2, rec_len);
  if (CHECK(doubled != NULL)) {
    double rec[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
    long n_samples = (long)g.size[0] * g.size[1] * g.size[2] * g.size[3], kept = 0;
    for (long off = 0; off < n_samples; ++off) {
      if (!sf_sample_memo_get(set.single_sunlit, off, rec)) continue;
      for (int i = 0; i < rec_len; ++i) rec[i] *= 2.0;
      sf_sample_memo_put(doubled, off, rec);
      ++kept;
    }
    CHECK(kept > 0);
    sf_sky_tables poisoned = sky;
    poisoned.sunlit = doubled;
    lookups halved = {&poisoned, got};
    sf_parallel_rows(N_VIEWS, &one, NULL, lookup_row, &halved);
    long n_halved = 0, n_lit = 0;
    for (long v = 0; v < N_VIEWS; ++v) {
      double a = want[v].single[0][0], b = got[v].single[0][0];
      if (a > 0.0) ++n_lit;
      if (a > 0.0 && fabs(b - 0.5 * a) <= 1e-12 * a) ++n_halved;
    }
    printf("%s: %ld of %ld lit views halved through the doubled memo\n", name, n_halved, n_lit);
    CHECK(n_halved > n_lit / 4);
    sf_sample_memo_free(doubled);
  }
  double lit = 0.0;
  for (long v = 0; v < N_VIEWS; ++v) lit += want[v].single[0][0];
  CHECK(lit > 0.0);
  free(want);
  free(got);
  sf_table_set_free(&set);
}

int main(void) {
  memo_checks();
  lookup_checks("bruneton", SF_PARAM_BRUNETON, "64x16,8x32x32x8");
  lookup_checks("leenman", SF_PARAM_LEENMAN, "64x16,8x32x32x8");
  return check_summary();
}
