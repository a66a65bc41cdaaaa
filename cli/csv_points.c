#include "cli/csv_points.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Reads one line of any length into *buf; returns its length or -1 at EOF. */
static long read_line(FILE *in, char **buf, size_t *cap) {
  size_t len = 0;
  int c;
  while ((c = fgetc(in)) != EOF && c != '\n') {
    if (len + 2 > *cap) {
      size_t ncap = *cap ? *cap * 2 : 256;
      char *nb = realloc(*buf, ncap);
      if (!nb) return -2;
      *buf = nb;
      *cap = ncap;
    }
    (*buf)[len++] = (char)c;
  }
  if (c == EOF && len == 0) return -1;
  if (!*buf) {
    *buf = malloc(1);
    if (!*buf) return -2;
    *cap = 1;
  }
  if (len > 0 && (*buf)[len - 1] == '\r') --len;
  (*buf)[len] = '\0';
  return (long)len;
}

static char *trim(char *s) {
  while (isspace((unsigned char)*s)) ++s;
  char *e = s + strlen(s);
  while (e > s && isspace((unsigned char)e[-1])) *--e = '\0';
  return s;
}

/* Splits line at commas in place; returns the field count (up to max + 1 so
 * the caller sees "too many"). */
static int split_fields(char *line, char **fields, int max) {
  int n = 0;
  char *p = line;
  for (;;) {
    char *comma = strchr(p, ',');
    if (comma) *comma = '\0';
    if (n <= max) fields[n] = trim(p);
    ++n;
    if (!comma) break;
    p = comma + 1;
  }
  return n;
}

static int in_list(const char *name, const char *const *list) {
  for (; *list; ++list)
    if (strcmp(name, *list) == 0) return 1;
  return 0;
}

int sf_csv_points_column(const sf_csv_points *p, const char *name) {
  for (int i = 0; i < p->n_columns; ++i)
    if (strcmp(p->column_names[i], name) == 0) return i;
  return -1;
}

long sf_csv_points_line(const sf_csv_points *p, long row) { return p->lines[row]; }

void sf_csv_points_free(sf_csv_points *p) {
  if (p->fields)
    for (long i = 0; i < p->n_rows * p->n_columns; ++i) free(p->fields[i]);
  free(p->fields);
  free(p->values);
  free(p->lines);
  memset(p, 0, sizeof *p);
}

static int parse_header(char *line, const char *source, const char *const *allowed,
                        const char *const *required, sf_csv_points *out, sf_error *err) {
  char *fields[SF_CSV_MAX_COLUMNS + 1];
  int n = split_fields(line, fields, SF_CSV_MAX_COLUMNS);
  if (n > SF_CSV_MAX_COLUMNS)
    return sf_fail(err, SF_ERR_INPUT, "%s: row 1 (header): too many columns (%d)", source, n);
  for (int i = 0; i < n; ++i) {
    if (fields[i][0] == '\0')
      return sf_fail(err, SF_ERR_INPUT, "%s: row 1 (header): column %d has no name", source, i + 1);
    if (!in_list(fields[i], allowed))
      return sf_fail(err, SF_ERR_INPUT, "%s: row 1 (header): unknown column '%.60s%s'", source, fields[i],
                     strlen(fields[i]) > 60 ? "..." : "");
    for (int j = 0; j < i; ++j)
      if (strcmp(fields[i], fields[j]) == 0)
        return sf_fail(err, SF_ERR_INPUT, "%s: row 1 (header): column '%s' appears twice", source,
                       fields[i]);
    snprintf(out->column_names[i], sizeof out->column_names[i], "%s", fields[i]);
  }
  out->n_columns = n;
  for (; *required; ++required)
    if (sf_csv_points_column(out, *required) < 0)
      return sf_fail(err, SF_ERR_INPUT, "%s: row 1 (header): missing column '%s'", source, *required);
  return 0;
}

static int append_row(sf_csv_points *out, long *capacity, char **fields, long row,
                      const char *source, sf_error *err) {
  int nc = out->n_columns;
  if (out->n_rows == *capacity) {
    long ncap = *capacity ? *capacity * 2 : 1024;
    double *nv = realloc(out->values, sizeof(double) * (size_t)(ncap * nc));
    if (nv) out->values = nv;
    char **nf = realloc(out->fields, sizeof(char *) * (size_t)(ncap * nc));
    if (nf) out->fields = nf;
    long *nl = realloc(out->lines, sizeof(long) * (size_t)ncap);
    if (nl) out->lines = nl;
    if (!nv || !nf || !nl) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", source);
    *capacity = ncap;
  }
  /* Every field is checked before any is copied, and a failed copy frees
   * this row's earlier copies: a rejected row owns nothing (n_rows, which
   * sf_csv_points_free goes by, does not count it). */
  double *row_values = out->values + out->n_rows * nc;
  char **row_fields = out->fields + out->n_rows * nc;
  for (int i = 0; i < nc; ++i) {
    char *end;
    double v = strtod(fields[i], &end);
    /* decimal only: strtod would read "0x10" as 16 */
    /* a long field is cut in the message, which had lost its verdict */
    const char *more = strlen(fields[i]) > 60 ? "..." : "";
    if (fields[i][0] == '\0' || *end != '\0' || strpbrk(fields[i], "xX"))
      return sf_fail(err, SF_ERR_INPUT, "%s: row %ld, column %s: '%.60s%s' is not a number", source, row,
                     out->column_names[i], fields[i], more);
    if (!isfinite(v))
      return sf_fail(err, SF_ERR_INPUT, "%s: row %ld, column %s: '%.60s%s' is not finite", source, row,
                     out->column_names[i], fields[i], more);
    row_values[i] = v;
  }
  for (int i = 0; i < nc; ++i) {
    row_fields[i] = strdup(fields[i]);
    if (!row_fields[i]) {
      while (i-- > 0) free(row_fields[i]);
      return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", source);
    }
  }
  out->lines[out->n_rows] = row;
  ++out->n_rows;
  return 0;
}

int sf_csv_points_read(FILE *in, const char *source, const char *const *allowed,
                       const char *const *required, sf_csv_points *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  char *line = NULL;
  size_t cap = 0;
  long len, row = 0, capacity = 0;
  int status = 0;
  while (status == 0) {
    len = read_line(in, &line, &cap);
    if (len == -1) break;
    if (len < -1) {
      status = sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", source);
      break;
    }
    ++row;
    /* a UTF-8 byte order mark (spreadsheets write one) is not part of the header */
    char *text = trim(row == 1 && strncmp(line, "\xEF\xBB\xBF", 3) == 0 ? line + 3 : line);
    if (row == 1) {
      if (text[0] == '\0')
        status = sf_fail(err, SF_ERR_INPUT, "%s: row 1: expected a header naming the columns", source);
      else
        status = parse_header(text, source, allowed, required, out, err);
      continue;
    }
    if (text[0] == '\0') continue;   /* blank lines (e.g. a trailing one) carry no point */
    char *fields[SF_CSV_MAX_COLUMNS + 1];
    int n = split_fields(text, fields, SF_CSV_MAX_COLUMNS);
    if (n != out->n_columns)
      status = sf_fail(err, SF_ERR_INPUT, "%s: row %ld: %d fields, the header names %d", source, row,
                       n, out->n_columns);
    else
      status = append_row(out, &capacity, fields, row, source, err);
  }
  /* a read error (stdin a folder, or closed) had been reported as empty input */
  if (status == 0 && ferror(in))
    status = sf_fail(err, SF_ERR_INPUT, "%s: cannot read: %s", source, strerror(errno ? errno : EIO));
  if (status == 0 && row == 0)
    status = sf_fail(err, SF_ERR_INPUT, "%s: empty input: expected a header row naming the columns",
                     source);
  free(line);
  if (status != 0) sf_csv_points_free(out);
  return status;
}
