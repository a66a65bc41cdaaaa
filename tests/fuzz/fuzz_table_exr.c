/* libFuzzer target: table files (SPEC §6, data/table_exr.h). The input is
 * written to a temporary file and read back with sf_table_read_exr, as the
 * table cache reads its files. The table size bound is 64 MiB (the largest
 * seed is a few hundred bytes) so that a header promising a huge table costs
 * a clean rejection, not the fuzzer's memory limit. An accepted table must
 * describe itself validly and hold only finite values. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "data/table_exr.h"
#include "tests/fuzz/fuzz_common.h"

#define FUZZ_TABLE_MAX_BYTES ((size_t)64 << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *dir = getenv("TMPDIR");
  char path[4096];
  snprintf(path, sizeof path, "%s/skyfit-fuzz-table-XXXXXX", dir && dir[0] ? dir : "/tmp");
  int fd = mkstemp(path);
  fuzz_require(fd >= 0, "cannot create a temporary file");
  size_t done = 0;
  while (done < size) {
    ssize_t n = write(fd, data + done, size - done);
    fuzz_require(n > 0, "cannot write the temporary file");
    done += (size_t)n;
  }
  close(fd);
  sf_table table;
  sf_error err = {0};
  int status = sf_table_read_exr(path, FUZZ_TABLE_MAX_BYTES, &table, &err);
  unlink(path);
  fuzz_require_clean(status, &err);
  if (status == SF_OK) {
    sf_error err2 = {0};
    fuzz_require(sf_table_desc_check(&table.desc, FUZZ_TABLE_MAX_BYTES, &err2) == SF_OK,
                 "an accepted table has an invalid description");
    size_t n = sf_table_desc_points(&table.desc) * (size_t)table.desc.n_channels;
    for (size_t i = 0; i < n; ++i) fuzz_require(isfinite(table.data[i]), "a value is not finite");
    sf_table_free(&table);
  } else {
    fuzz_require(table.data == NULL && table.atmosphere_json == NULL, "a rejected table is not empty");
  }
  return 0;
}
