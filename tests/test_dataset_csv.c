/* The CSV form of a training set (fit/dataset_csv.h):
 *   - the text written on 1 and 2 threads is, byte for byte, a plain serial
 *     fprintf("%.17g") of every value, over more rows than one round of the
 *     writer's blocks;
 *   - reading it back on 1 and 2 threads gives every double's bits, for
 *     awkward values (random bit patterns, subnormals, -0, the extremes);
 *   - line endings "\r\n", empty lines and a last line without '\n' read
 *     as the rows they hold;
 *   - bad files are refused with the line, column and problem: the first
 *     bad row of the file whatever the threads, counting empty lines; a
 *     NUL byte; a ragged row; no rows; no header; too few columns. */
#define _GNU_SOURCE /* open_memstream, mkdtemp */
#include <float.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "fit/dataset_csv.h"

static uint64_t splitmix64(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/* Value k of the test set: every eighth a fixed awkward one, the rest
 * random finite bit patterns or uniform in [-1, 1]. */
static double awkward_value(uint64_t *rng, long k) {
  static const double fixed[] = {0.0, -0.0, DBL_MAX, -DBL_MAX, DBL_MIN, 4.9406564584124654e-324,
                                 -2.2250738585072009e-308, 0.1, 1.0 / 3.0, 1e22, 9007199254740993.0};
  if (k % 8 == 0) return fixed[(k / 8) % (long)(sizeof fixed / sizeof fixed[0])];
  uint64_t bits = splitmix64(rng);
  if (k % 2) return (double)(bits >> 11) * 0x1.0p-52 - 1.0;
  double v;
  memcpy(&v, &bits, sizeof v);
  return isfinite(v) ? v : 0.5;
}

static char *read_file(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  rewind(f);
  char *text = malloc((size_t)n + 1);
  *len = fread(text, 1, (size_t)n, f);
  fclose(f);
  return text;
}

static void write_text(const char *path, const char *text, size_t len) {
  FILE *f = fopen(path, "wb");
  fwrite(text, 1, len, f);
  fclose(f);
}

/* Reads text as a CSV with n_in inputs on the given threads; returns the
 * status, the message in err. */
static int read_text(const char *dir, const char *text, size_t len, int n_in, int threads, sf_dataset *d,
                     sf_error *err) {
  char path[256];
  snprintf(path, sizeof path, "%s/case.csv", dir);
  write_text(path, text, len);
  sf_error_clear(err);
  return sf_dataset_read_csv(path, n_in, threads, d, err);
}

static void check_refused(const char *dir, const char *text, size_t len, int n_in, const char *want) {
  for (int threads = 1; threads <= 2; ++threads) {
    sf_dataset d;
    sf_error err = {0};
    int status = read_text(dir, text, len, n_in, threads, &d, &err);
    int ok = status == SF_ERR_INPUT && strstr(err.message, want) != NULL && d.x == NULL;
    printf("%s %d thread(s): '%s' (want '%s')\n", ok ? "ok  " : "FAIL", threads, err.message, want);
    CHECK(ok);
    sf_dataset_free(&d);
  }
}

static void test_round_trip(const char *dir) {
  /* 64 columns: the writer's blocks hold 655 rows, a round of 16 blocks
   * 10480; 10500 rows take two rounds */
  const long n = 10500;
  const int n_in = 6, n_out = 58;
  sf_dataset d;
  sf_error err = {0};
  CHECK(sf_dataset_init(&d, n, n_in, n_out, &err) == SF_OK);
  uint64_t rng = 12345;
  for (long i = 0, k = 0; i < n; ++i) {
    for (int j = 0; j < n_in; ++j) d.x[i * n_in + j] = awkward_value(&rng, k++);
    for (int j = 0; j < n_out; ++j) d.y[i * n_out + j] = awkward_value(&rng, k++);
  }
  snprintf(d.names[0], SF_DATASET_NAME_LEN, "sqrt_h_km");
  /* the text a serial fprintf writes */
  char *want = NULL;
  size_t want_len = 0;
  FILE *m = open_memstream(&want, &want_len);
  for (int k = 0; k < n_in + n_out; ++k) fprintf(m, "%s%s", k ? "," : "", d.names[k]);
  fputc('\n', m);
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < n_in + n_out; ++k)
      fprintf(m, "%.17g%c", k < n_in ? d.x[i * n_in + k] : d.y[i * n_out + k - n_in], k + 1 < n_in + n_out ? ',' : '\n');
  fclose(m);
  for (int threads = 1; threads <= 2; ++threads) {
    char path[256];
    snprintf(path, sizeof path, "%s/set%d.csv", dir, threads);
    sf_error_clear(&err);
    CHECK(sf_dataset_write_csv(&d, path, threads, &err) == SF_OK);
    size_t len = 0;
    char *got = read_file(path, &len);
    int same_text = got && len == want_len && memcmp(got, want, len) == 0;
    printf("%s written on %d thread(s): %zu bytes, a serial fprintf's %zu\n", same_text ? "ok  " : "FAIL", threads,
           len, want_len);
    CHECK(same_text);
    free(got);
    for (int read_threads = 1; read_threads <= 2; ++read_threads) {
      sf_dataset back;
      sf_error_clear(&err);
      int status = sf_dataset_read_csv(path, n_in, read_threads, &back, &err);
      int same = status == SF_OK && back.n == n && back.n_in == n_in && back.n_out == n_out &&
                 memcmp(back.x, d.x, sizeof(double) * (size_t)(n * n_in)) == 0 &&
                 memcmp(back.y, d.y, sizeof(double) * (size_t)(n * n_out)) == 0 &&
                 strcmp(back.names[0], "sqrt_h_km") == 0 && strcmp(back.names[n_in + n_out - 1], "y57") == 0;
      printf("%s read back on %d thread(s): %ld rows, every double's bits %s\n", same ? "ok  " : "FAIL",
             read_threads, back.n, same ? "the same" : "NOT the same");
      CHECK(same);
      sf_dataset_free(&back);
    }
  }
  free(want);
  sf_dataset_free(&d);
}

static void test_line_endings(const char *dir) {
  static const char text[] = "a,b,t\r\n1,2,3\r\n\r\n\n-4.5, 5e-3,6\n7,8,9";
  for (int threads = 1; threads <= 2; ++threads) {
    sf_dataset d;
    sf_error err = {0};
    int status = read_text(dir, text, sizeof text - 1, 2, threads, &d, &err);
    int ok = status == SF_OK && d.n == 3 && d.n_in == 2 && d.n_out == 1 && d.x[0] == 1 && d.x[1] == 2 &&
             d.y[0] == 3 && d.x[2] == -4.5 && d.x[3] == 5e-3 && d.y[1] == 6 && d.x[4] == 7 && d.x[5] == 8 &&
             d.y[2] == 9 && strcmp(d.names[1], "b") == 0 && strcmp(d.names[2], "t") == 0;
    printf("%s CRLF, empty lines, no final newline, %d thread(s): %ld rows %s\n", ok ? "ok  " : "FAIL", threads, d.n,
           err.message);
    CHECK(ok);
    sf_dataset_free(&d);
  }
  /* a UTF-8 byte order mark before the header (spreadsheets write one) */
  static const char bom[] = "\xEF\xBB\xBF" "a,t\n1,2\n";
  sf_dataset d;
  sf_error err = {0};
  int status = read_text(dir, bom, sizeof bom - 1, 1, 1, &d, &err);
  int ok = status == SF_OK && d.n == 1 && strcmp(d.names[0], "a") == 0 && d.x[0] == 1 && d.y[0] == 2;
  printf("%s byte order mark: first column named '%s' %s\n", ok ? "ok  " : "FAIL", status == SF_OK ? d.names[0] : "",
         err.message);
  CHECK(ok);
  if (status == SF_OK) sf_dataset_free(&d);
}

static void test_refusals(const char *dir) {
  /* the first bad row of the file (line 5, after an empty line 3), with
   * another bad one far below: on 2 threads the second half's is found
   * too, and the earlier reported */
  size_t cap = 64 + 20000 * 8;
  char *big = malloc(cap);
  size_t len = (size_t)snprintf(big, cap, "a,b\n1,2\n\n3,4\n5,x\n");
  for (int i = 0; i < 20000; ++i) len += (size_t)snprintf(big + len, cap - len, i == 15000 ? "7,\n" : "6,7\n");
  check_refused(dir, big, len, 1, "line 5, column 2 (b): expected a finite number ending the row");
  /* the far one alone: its line counted on every thread */
  big[sizeof "a,b\n1,2\n\n3,4\n5," - 1] = '4';
  check_refused(dir, big, len, 1, "line 15006, column 2 (b): expected a finite number ending the row");
  free(big);
  static const char nul[] = "a,b\n1,2\n3\0,4\n";
  check_refused(dir, nul, sizeof nul - 1, 1, "line 3: a NUL byte");
  /* strtod skips white space, newlines too: an empty last field must not
   * take the next line's number */
  check_refused(dir, "a,b,c\n1,2, \n3,4,5\n", 18, 2, "line 2, column 3 (c): expected a finite number ending the row");
  check_refused(dir, "a,b,c\n1,2\n", 10, 2, "line 2, column 2 (b): expected a finite number followed by a comma");
  check_refused(dir, "a,b\n1,2,3\n", 10, 1, "line 2, column 2 (b): expected a finite number ending the row");
  check_refused(dir, "a,b\n1,inf\n", 10, 1, "line 2, column 2 (b): expected a finite number");
  check_refused(dir, "a,b\n1,nan\n", 10, 1, "line 2, column 2 (b): expected a finite number");
  check_refused(dir, "a,b\n1,1e999\n", 12, 1, "line 2, column 2 (b): expected a finite number");
  check_refused(dir, "a,b\n\r\n\n", 7, 1, "no data rows after the header");
  check_refused(dir, "", 0, 1, "line 1: expected a header row");
  check_refused(dir, "a,b\n1,2\n", 8, 2, "line 1: 2 columns, but --inputs 2 leaves no target column");
  /* decimal only (strtod reads "0x10" as 16); a file without its header
   * row would lose its first row to it */
  check_refused(dir, "a,b\n0x10,2\n", 11, 1, "line 2, column 1 (a): expected a finite number");
  check_refused(dir, "a,b\n1,0X1p3\n", 12, 1, "line 2, column 2 (b): expected a finite number");
  check_refused(dir, "1,2\n3,4\n", 8, 1, "line 1 holds numbers: expected a header row");
  sf_dataset d;
  sf_error err = {0};
  char missing[256];
  snprintf(missing, sizeof missing, "%s/missing.csv", dir);
  int status = sf_dataset_read_csv(missing, 1, 1, &d, &err);
  printf("%s missing file: '%s'\n", status == SF_ERR_INPUT ? "ok  " : "FAIL", err.message);
  CHECK(status == SF_ERR_INPUT && strstr(err.message, "cannot open") != NULL);
}

int main(void) {
  char dir[] = "/tmp/skyfit-dataset-csv-XXXXXX";
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return 1;
  }
  test_round_trip(dir);
  test_line_endings(dir);
  test_refusals(dir);
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) printf("could not remove %s\n", dir);
  return check_summary();
}
