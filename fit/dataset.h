/* A training set for the networks (SPEC §7.4-7.5): n samples of n_in
 * normalised inputs and n_out targets, row-major, with the input
 * normalisation that produced them (stored in the weights file, SPEC §8) and
 * column names. Its CSV form: fit/dataset_csv.h. */
#ifndef SKYFIT_FIT_DATASET_H
#define SKYFIT_FIT_DATASET_H

#include <stdint.h>

#include "util/error.h"

#define SF_DATASET_MAX_COLUMNS 64
#define SF_DATASET_NAME_LEN 32

typedef struct sf_dataset {
  long n;
  int n_in, n_out;
  double *x, *y;                                   /* owned */
  char names[SF_DATASET_MAX_COLUMNS][SF_DATASET_NAME_LEN];  /* inputs, then targets */
  /* normalised input = (physical - offset) * scale (models/mlp.h names) */
  double input_offset[SF_DATASET_MAX_COLUMNS], input_scale[SF_DATASET_MAX_COLUMNS];
} sf_dataset;

/* Allocates n samples (names "x0".., "y0".., identity normalisation). */
int sf_dataset_init(sf_dataset *d, long n, int n_in, int n_out, sf_error *err);
void sf_dataset_free(sf_dataset *d);
/* Keeps the first n samples (n <= d->n). */
void sf_dataset_truncate(sf_dataset *d, long n);
/* a's samples then b's (same columns; names and normalisation from a). */
int sf_dataset_concat(const sf_dataset *a, const sf_dataset *b, sf_dataset *out, sf_error *err);

/* Splits d into train and validation sets: a seeded shuffle puts
 * round(fraction * n) samples into validation (fraction 0: none, and
 * validation is left empty). Both copies are owned by the caller. */
int sf_dataset_split(const sf_dataset *d, double fraction, uint64_t seed, sf_dataset *train,
                     sf_dataset *validation, sf_error *err);

/* A seeded random permutation of 0..n-1 (Fisher-Yates on the eight
 * streams of models/rng_lanes.h, swap k drawing from lane k % 8). */
void sf_dataset_permutation(int *perm, long n, uint64_t seed, uint64_t key_a, uint64_t key_b);

#endif
