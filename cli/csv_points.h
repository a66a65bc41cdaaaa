/* The CSV that `skyfit eval` reads on stdin (SPEC §11): a header row naming
 * the columns, then one point per row. Everything is read and checked before
 * anything is computed, so a bad row leaves stdout empty. */
#ifndef SKYFIT_CLI_CSV_POINTS_H
#define SKYFIT_CLI_CSV_POINTS_H

#include <stdio.h>
#include "util/error.h"

#define SF_CSV_MAX_COLUMNS 8

typedef struct sf_csv_points {
  int n_columns;
  char column_names[SF_CSV_MAX_COLUMNS][32];
  long n_rows;
  double *values;       /* n_rows * n_columns, row-major */
  char **fields;        /* the rows' original text, n_rows * n_columns */
  long *lines;          /* each row's line in the input (1 = header): blank
                           lines are skipped, so row k is not always line k + 2 */
} sf_csv_points;

/* Reads the whole stream. allowed lists the column names this quantity
 * accepts (NULL-terminated); required those it needs. Errors name the
 * source, the row (1 = header) and the column. */
int sf_csv_points_read(FILE *in, const char *source, const char *const *allowed,
                       const char *const *required, sf_csv_points *out, sf_error *err);
/* The input line of data row `row` (0-based), for messages. */
long sf_csv_points_line(const sf_csv_points *p, long row);
/* Index of the named column, or -1. */
int sf_csv_points_column(const sf_csv_points *p, const char *name);
void sf_csv_points_free(sf_csv_points *p);

#endif
