/* The CSV form of a training set (--dump-dataset, `skyfit fit mlp --data`,
 * and any other trainer given the same data): one header row of names,
 * inputs first, targets after, then one row per sample, each number with 17
 * significant digits so that it reads back to the same double.
 *
 * Both directions run on threads: the scattering set of the default tables
 * is 983,040 rows, 260 MB of text and 12.8 million numbers, and on one core
 * reading it took 2.8 s (strtod and a character at a time), writing it
 * about 3.5 s (printf). Each row's text depends on that row alone, so the
 * bytes written and the doubles read are the same for any thread count. */
#ifndef SKYFIT_FIT_DATASET_CSV_H
#define SKYFIT_FIT_DATASET_CSV_H

#include "fit/dataset.h"
#include "util/error.h"

/* Writes d as CSV, atomically (util/atomic_file.h), formatting on threads
 * (<= 0: OpenMP's default). */
int sf_dataset_write_csv(const sf_dataset *d, const char *path, int threads, sf_error *err);

/* Reads a CSV with a header row; the first n_in columns are inputs, the
 * rest targets; empty lines are skipped and a line may end in "\r\n".
 * Parses on threads (<= 0: OpenMP's default). SF_ERR_INPUT "<file>: line L,
 * column C (name): <problem>" for the first bad row of the file (a number
 * that is not finite, a ragged row), and for a header with too few columns,
 * a NUL byte, or no rows. */
int sf_dataset_read_csv(const char *path, int n_in, int threads, sf_dataset *d, sf_error *err);

#endif
