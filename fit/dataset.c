#include "fit/dataset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/rng_lanes.h"

/* rng stream keys of this file */
#define SPLIT_KEY 0x73706c6974ull   /* "split" */

int sf_dataset_init(sf_dataset *d, long n, int n_in, int n_out, sf_error *err) {
  memset(d, 0, sizeof *d);
  if (n_in < 1 || n_out < 1 || n_in + n_out > SF_DATASET_MAX_COLUMNS)
    return sf_fail(err, SF_ERR_INPUT, "dataset: need 1..%d columns, got %d inputs and %d targets",
                   SF_DATASET_MAX_COLUMNS, n_in, n_out);
  d->n = n;
  d->n_in = n_in;
  d->n_out = n_out;
  d->x = malloc((size_t)(n > 0 ? n : 1) * (size_t)n_in * sizeof(double));
  d->y = malloc((size_t)(n > 0 ? n : 1) * (size_t)n_out * sizeof(double));
  if (!d->x || !d->y) {
    sf_dataset_free(d);
    return sf_fail(err, SF_ERR_INTERNAL, "dataset: out of memory for %ld samples", n);
  }
  for (int k = 0; k < n_in; ++k) {
    snprintf(d->names[k], SF_DATASET_NAME_LEN, "x%d", k);
    d->input_offset[k] = 0.0;
    d->input_scale[k] = 1.0;
  }
  for (int k = 0; k < n_out; ++k) snprintf(d->names[n_in + k], SF_DATASET_NAME_LEN, "y%d", k);
  return SF_OK;
}

void sf_dataset_free(sf_dataset *d) {
  free(d->x);
  free(d->y);
  d->x = d->y = NULL;
  d->n = 0;
}

void sf_dataset_truncate(sf_dataset *d, long n) {
  if (n < d->n) d->n = n;
}

int sf_dataset_concat(const sf_dataset *a, const sf_dataset *b, sf_dataset *out, sf_error *err) {
  if (a->n_in != b->n_in || a->n_out != b->n_out)
    return sf_fail(err, SF_ERR_INTERNAL, "sf_dataset_concat: %d+%d and %d+%d columns", a->n_in, a->n_out, b->n_in,
                   b->n_out);
  if (sf_dataset_init(out, a->n + b->n, a->n_in, a->n_out, err)) return err->status;
  memcpy(out->names, a->names, sizeof out->names);
  memcpy(out->input_offset, a->input_offset, sizeof out->input_offset);
  memcpy(out->input_scale, a->input_scale, sizeof out->input_scale);
  size_t xa = (size_t)a->n * (size_t)a->n_in, ya = (size_t)a->n * (size_t)a->n_out;
  if (a->n > 0) {
    memcpy(out->x, a->x, sizeof(double) * xa);
    memcpy(out->y, a->y, sizeof(double) * ya);
  }
  if (b->n > 0) {
    memcpy(out->x + xa, b->x, sizeof(double) * (size_t)b->n * (size_t)b->n_in);
    memcpy(out->y + ya, b->y, sizeof(double) * (size_t)b->n * (size_t)b->n_out);
  }
  return SF_OK;
}

/* Swap partners drawn (and prefetched) ahead of their swaps: perm of a
 * training set is larger than the L2 cache, and each swap's random read
 * would otherwise wait on its own miss. A multiple of SF_RNG_LANES. */
#define PERMUTATION_AHEAD 64

void sf_dataset_permutation(int *perm, long n, uint64_t seed, uint64_t key_a, uint64_t key_b) {
  /* Eight lanes (models/rng_lanes.h): every epoch shuffles the training
   * set, and one serial stream made the shuffle a fifth of a small
   * network's epoch. */
  sf_rng_lanes rng;
  sf_rng_lanes_seed(&rng, seed, key_a, key_b);
  for (long i = 0; i < n; ++i) perm[i] = (int)i;
  /* Fisher-Yates, i from n - 1 down to 1 swapped with j uniform in 0..i;
   * swap k (i = n - 1 - k) takes draw k of the lanes, so the permutation
   * does not depend on how far ahead they are drawn. */
  long partner[PERMUTATION_AHEAD];
  for (long top = n - 1; top > 0; top -= PERMUTATION_AHEAD) {
    long count = top < PERMUTATION_AHEAD ? top : PERMUTATION_AHEAD;
    sf_rng_lanes_partners(&rng, top, partner, (count + SF_RNG_LANES - 1) / SF_RNG_LANES);
#if defined(__GNUC__)
    for (long k = 0; k < count; ++k) __builtin_prefetch(perm + partner[k], 1);
#endif
    for (long k = 0; k < count; ++k) {
      long i = top - k, j = partner[k];
      int t = perm[i];
      perm[i] = perm[j];
      perm[j] = t;
    }
  }
}

static void copy_rows(const sf_dataset *from, const int *index, long count, sf_dataset *to) {
  for (long i = 0; i < count; ++i) {
    memcpy(to->x + i * from->n_in, from->x + (long)index[i] * from->n_in, (size_t)from->n_in * sizeof(double));
    memcpy(to->y + i * from->n_out, from->y + (long)index[i] * from->n_out, (size_t)from->n_out * sizeof(double));
  }
}

static void copy_header(const sf_dataset *from, sf_dataset *to) {
  memcpy(to->names, from->names, sizeof to->names);
  memcpy(to->input_offset, from->input_offset, sizeof to->input_offset);
  memcpy(to->input_scale, from->input_scale, sizeof to->input_scale);
}

int sf_dataset_split(const sf_dataset *d, double fraction, uint64_t seed, sf_dataset *train,
                     sf_dataset *validation, sf_error *err) {
  memset(train, 0, sizeof *train);
  memset(validation, 0, sizeof *validation);
  long n_val = (long)floor(fraction * (double)d->n + 0.5);
  if (n_val < 0) n_val = 0;
  if (n_val >= d->n) return sf_fail(err, SF_ERR_INPUT, "dataset: validation fraction %g leaves no training samples", fraction);
  int *perm = malloc((size_t)d->n * sizeof(int));
  if (!perm) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_dataset_permutation(perm, d->n, seed, SPLIT_KEY, 0);
  if (sf_dataset_init(train, d->n - n_val, d->n_in, d->n_out, err) ||
      sf_dataset_init(validation, n_val, d->n_in, d->n_out, err)) {
    free(perm);
    sf_dataset_free(train);
    sf_dataset_free(validation);
    return err->status;
  }
  copy_header(d, train);
  copy_header(d, validation);
  copy_rows(d, perm, n_val, validation);
  copy_rows(d, perm + n_val, d->n - n_val, train);
  free(perm);
  return SF_OK;
}
