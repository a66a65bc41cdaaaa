/* libFuzzer target: the CSV that `skyfit eval` reads on stdin
 * (cli/csv_points.h), with the columns of the 4D quantities allowed and
 * h_km, mu required, as `skyfit eval single_scattering` has them. An
 * accepted input must hold finite values in every cell. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/csv_points.h"
#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size == 0) return 0;  /* fmemopen needs a non-empty buffer */
  FILE *in = fmemopen((void *)data, size, "r");
  if (!in) return 0;
  static const char *const allowed[] = {"h_km", "mu", "mu_s", "nu", NULL};
  static const char *const required[] = {"h_km", "mu", NULL};
  sf_csv_points points;
  sf_error err = {0};
  int status = sf_csv_points_read(in, "stdin", allowed, required, &points, &err);
  fclose(in);
  fuzz_require_clean(status, &err);
  if (status == SF_OK) {
    fuzz_require(points.n_columns >= 2 && points.n_columns <= 4, "column count");
    fuzz_require(sf_csv_points_column(&points, "h_km") >= 0 && sf_csv_points_column(&points, "mu") >= 0,
                 "a required column is missing");
    for (long i = 0; i < points.n_rows * points.n_columns; ++i)
      fuzz_require(isfinite(points.values[i]) && points.fields[i] != NULL, "a cell is not finite");
    sf_csv_points_free(&points);
  }
  return 0;
}
