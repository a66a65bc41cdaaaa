#include "fit/dataset_csv.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/atomic_file.h"
#include "util/read_file.h"

/* A field as written: "%.17g" is at most 24 characters
 * ("-1.2345678901234567e-308"), then its comma or the row's newline. */
#define FIELD_MAX 25
/* Rows are formatted WRITE_BLOCKS blocks of about a MiB at a time, the
 * blocks on threads, then written in order. */
#define WRITE_BLOCKS 16
#define WRITE_BLOCK_BYTES (1L << 20)

static int thread_count(int threads) { return threads > 0 ? threads : omp_get_max_threads(); }

/* Sample i's row as text at out (room for cols FIELD_MAX bytes and a NUL);
 * returns its length. */
static size_t format_row(const sf_dataset *d, long i, char *out) {
  const int cols = d->n_in + d->n_out;
  char *p = out;
  for (int k = 0; k < cols; ++k) {
    double v = k < d->n_in ? d->x[i * d->n_in + k] : d->y[i * d->n_out + (k - d->n_in)];
    if (k) *p++ = ',';
    p += snprintf(p, FIELD_MAX, "%.17g", v);
  }
  *p++ = '\n';
  return (size_t)(p - out);
}

int sf_dataset_write_csv(const sf_dataset *d, const char *path, int threads, sf_error *err) {
  const int cols = d->n_in + d->n_out;
  const long row_max = (long)cols * FIELD_MAX;
  const long block_rows = WRITE_BLOCK_BYTES / row_max > 0 ? WRITE_BLOCK_BYTES / row_max : 1;
  const long block_bytes = block_rows * row_max + 1;
  char *text = malloc((size_t)(WRITE_BLOCKS * block_bytes));
  if (!text) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory for the CSV text", path);
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err)) {
    free(text);
    return err->status;
  }
  for (int k = 0; k < cols; ++k) fprintf(f.stream, "%s%s", k ? "," : "", d->names[k]);
  fputc('\n', f.stream);
  const int n_threads = thread_count(threads);
  size_t used[WRITE_BLOCKS];
  for (long first = 0; first < d->n; first += WRITE_BLOCKS * block_rows) {
#pragma omp parallel for schedule(static, 1) num_threads(n_threads) if (n_threads > 1)
    for (int b = 0; b < WRITE_BLOCKS; ++b) {
      long begin = first + b * block_rows, end = begin + block_rows < d->n ? begin + block_rows : d->n;
      char *out = text + b * block_bytes;
      used[b] = 0;
      for (long i = begin; i < end; ++i) used[b] += format_row(d, i, out + used[b]);
    }
    for (int b = 0; b < WRITE_BLOCKS; ++b) fwrite(text + b * block_bytes, 1, used[b], f.stream);
  }
  free(text);
  return sf_atomic_commit(&f, err);   /* reports a failed write (ferror) */
}

/* The fields of one row (a NUL-terminated line, perhaps ending in '\r')
 * into x[0..n_in-1] and y[..]; returns -1, or the first column that is not
 * a finite number followed by a comma (ending the row, for the last). The
 * line being a C string keeps strtod, which skips leading white space,
 * from reading on into the next line. */
static int parse_row(const char *line, int cols, int n_in, double *x, double *y) {
  const char *p = line;
  for (int k = 0; k < cols; ++k) {
    char *end;
    double v = strtod(p, &end);
    int ends = k + 1 == cols ? *end == '\0' || (end[0] == '\r' && end[1] == '\0') : *end == ',';
    /* decimal only: strtod would read "0x10" as 16 */
    int hex = memchr(p, 'x', (size_t)(end - p)) || memchr(p, 'X', (size_t)(end - p));
    if (end == p || !isfinite(v) || !ends || hex) return k;
    if (k < n_in) x[k] = v;
    else y[k - n_in] = v;
    p = end + 1;
  }
  return -1;
}

/* 1-based line number of text[offset], a data row's: line 2 starts at
 * text[body], and split_rows ended each line from there with a NUL (the
 * file holds none of its own). */
static long line_number(const char *text, size_t body, long offset) {
  long line = 2;
  for (long i = (long)body; i < offset; ++i) line += text[i] == '\0';
  return line;
}

/* Column names of the header line (NUL-terminated, perhaps ending in '\r'),
 * which this splits; returns how many, or -1 beyond SF_DATASET_MAX_COLUMNS. */
static int parse_header(char *line, char names[][SF_DATASET_NAME_LEN]) {
  size_t n = strlen(line);
  if (n > 0 && line[n - 1] == '\r') line[n - 1] = '\0';
  int cols = 0;
  for (char *tok = line, *next;; tok = next + 1) {
    next = strchr(tok, ',');
    if (next) *next = '\0';
    if (cols >= SF_DATASET_MAX_COLUMNS) return -1;
    snprintf(names[cols++], SF_DATASET_NAME_LEN, "%.31s", tok);
    if (!next) return cols;
  }
}

/* Ends every line of text[from..len) with a NUL in place of its '\n' and
 * stores the offsets of the non-empty ones ("" or "\r" are empty) in
 * *starts (the caller frees it); returns how many, or -1 out of memory. */
static long split_rows(char *text, size_t from, size_t len, long **starts) {
  long lines = 1;
  for (const char *p = text + from; (p = memchr(p, '\n', len - (size_t)(p - text))) != NULL; ++p) ++lines;
  *starts = malloc((size_t)lines * sizeof(long));
  if (!*starts) return -1;
  long rows = 0;
  for (size_t at = from; at < len;) {
    char *nl = memchr(text + at, '\n', len - at);
    size_t next = nl ? (size_t)(nl - text) + 1 : len;
    if (nl) *nl = '\0';
    if (text[at] != '\0' && !(text[at] == '\r' && text[at + 1] == '\0')) (*starts)[rows++] = (long)at;
    at = next;
  }
  return rows;
}

int sf_dataset_read_csv(const char *path, int n_in, int threads, sf_dataset *d, sf_error *err) {
  memset(d, 0, sizeof *d);
  static const sf_file_rules rules = {"training set", "", SIZE_MAX / 4};
  char *text = NULL;
  size_t len = 0;
  int status = sf_read_file(path, &rules, &text, &len, err);
  if (status) return status;
  long *starts = NULL;
  char names[SF_DATASET_MAX_COLUMNS][SF_DATASET_NAME_LEN];
  const char *nul = memchr(text, '\0', len);
  if (nul) {
    long line = 1;
    for (const char *p = text; p < nul; ++p) line += *p == '\n';
    status = sf_fail(err, SF_ERR_INPUT, "%s: line %ld: a NUL byte (not a text file?)", path, line);
    goto done;
  }
  if (len == 0) {
    status = sf_fail(err, SF_ERR_INPUT, "%s: line 1: expected a header row naming the columns", path);
    goto done;
  }
  char *header_end = memchr(text, '\n', len);
  size_t body = header_end ? (size_t)(header_end - text) + 1 : len;
  if (header_end) *header_end = '\0';
  /* a UTF-8 byte order mark (spreadsheets write one) is not part of the header */
  int cols = parse_header(len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? text + 3 : text, names);
  if (cols < 0) {
    status = sf_fail(err, SF_ERR_INPUT, "%s: line 1: more than %d columns", path, SF_DATASET_MAX_COLUMNS);
    goto done;
  }
  int numbers = 0;
  for (int k = 0; k < cols; ++k) {
    char *end;
    strtod(names[k], &end);
    numbers += end != names[k] && *end == '\0';
  }
  if (numbers == cols) {
    status = sf_fail(err, SF_ERR_INPUT, "%s: line 1 holds numbers: expected a header row naming the columns (as "
                                        "--dump-dataset writes)", path);
    goto done;
  }
  if (n_in < 1 || cols <= n_in) {
    status = sf_fail(err, SF_ERR_INPUT, "%s: line 1: %d columns, but --inputs %d leaves no target column", path,
                     cols, n_in);
    goto done;
  }
  long n = split_rows(text, body, len, &starts);
  if (n < 0) {
    status = sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory for the row index", path);
    goto done;
  }
  if (n == 0) {
    status = sf_fail(err, SF_ERR_INPUT, "%s: no data rows after the header", path);
    goto done;
  }
  if ((status = sf_dataset_init(d, n, n_in, cols - n_in, err)) != SF_OK) goto done;
  memcpy(d->names, names, (size_t)cols * sizeof names[0]);
  const int n_threads = thread_count(threads), n_out = cols - n_in;
  long first_bad = n;
#pragma omp parallel for schedule(static) num_threads(n_threads) if (n_threads > 1) reduction(min : first_bad)
  for (long i = 0; i < n; ++i)
    if (parse_row(text + starts[i], cols, n_in, d->x + i * n_in, d->y + i * n_out) >= 0 && i < first_bad)
      first_bad = i;
  if (first_bad < n) {
    int k = parse_row(text + starts[first_bad], cols, n_in, d->x, d->y);
    status = sf_fail(err, SF_ERR_INPUT, "%s: line %ld, column %d (%s): expected a finite number%s", path,
                     line_number(text, body, starts[first_bad]), k + 1, names[k],
                     k + 1 == cols ? " ending the row" : " followed by a comma");
    sf_dataset_free(d);
  }
done:
  free(starts);
  free(text);
  return status;
}
