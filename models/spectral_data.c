#include "models/spectral_data.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/color_space.h"
#include "util/data_path.h"

#define CSV_LINE_MAX 1024
#define CSV_MAX_COLUMNS 16

/* Splits line in place at commas (and the line end); returns the count. */
static int split_csv(char *line, char **fields) {
  int n = 0;
  line[strcspn(line, "\r\n")] = '\0';
  char *p = line;
  while (n < CSV_MAX_COLUMNS) {
    fields[n++] = p;
    char *comma = strchr(p, ',');
    if (!comma) break;
    *comma = '\0';
    p = comma + 1;
  }
  return n;
}

static int column_index(char **fields, int n, const char *name) {
  for (int i = 0; i < n; ++i)
    if (strcmp(fields[i], name) == 0) return i;
  return -1;
}

static int parse_number(const char *text, double *out) {
  char *end = NULL;
  errno = 0;
  *out = strtod(text, &end);
  return end != text && *end == '\0' && errno == 0 && isfinite(*out);
}

int sf_spectrum_load(const char *file_name, const char *column, sf_spectrum *out, sf_error *err) {
  char path[4096];
  if (sf_data_file_path(file_name, path, sizeof path, err)) return SF_ERR_INPUT;
  FILE *f = fopen(path, "r");
  if (!f) return sf_fail(err, SF_ERR_INPUT, "%s: cannot open", path);
  char line[CSV_LINE_MAX];
  char *fields[CSV_MAX_COLUMNS];
  int rc = 0, line_no = 1;
  if (!fgets(line, sizeof line, f)) {
    rc = sf_fail(err, SF_ERR_INPUT, "%s: empty file", path);
    goto done;
  }
  int nf = split_csv(line, fields);
  int lambda_col = column_index(fields, nf, "lambda_nm"), value_col = column_index(fields, nf, column);
  if (lambda_col < 0 || value_col < 0) {
    rc = sf_fail(err, SF_ERR_INPUT, "%s: line 1: no column \"%s\"", path,
                 lambda_col < 0 ? "lambda_nm" : column);
    goto done;
  }
  out->n = 0;
  while (fgets(line, sizeof line, f)) {
    ++line_no;
    if (line[0] == '\n' || line[0] == '\0') continue;
    nf = split_csv(line, fields);
    double x, y;
    if (nf <= lambda_col || nf <= value_col || !parse_number(fields[lambda_col], &x) ||
        !parse_number(fields[value_col], &y)) {
      rc = sf_fail(err, SF_ERR_INPUT, "%s: line %d: expected numbers in columns lambda_nm and %s", path,
                   line_no, column);
      goto done;
    }
    if (out->n >= SF_SPECTRUM_MAX_POINTS) {
      rc = sf_fail(err, SF_ERR_INPUT, "%s: more than %d rows", path, SF_SPECTRUM_MAX_POINTS);
      goto done;
    }
    if (out->n > 0 && !(x > out->lambda_nm[out->n - 1])) {
      rc = sf_fail(err, SF_ERR_INPUT, "%s: line %d: wavelengths must increase (%g after %g)", path,
                   line_no, x, out->lambda_nm[out->n - 1]);
      goto done;
    }
    out->lambda_nm[out->n] = x;
    out->value[out->n] = y;
    ++out->n;
  }
  if (out->n < 2) rc = sf_fail(err, SF_ERR_INPUT, "%s: fewer than 2 rows", path);
done:
  fclose(f);
  return rc;
}

int sf_spectrum_covers(const sf_spectrum *s, double lambda_nm) {
  return s->n >= 2 && lambda_nm >= s->lambda_nm[0] && lambda_nm <= s->lambda_nm[s->n - 1];
}

/* Index i with lambda in [x_i, x_{i+1}] (binary search); -1 outside. */
static int segment(const sf_spectrum *s, double lambda_nm) {
  if (!sf_spectrum_covers(s, lambda_nm)) return -1;
  int lo = 0, hi = s->n - 1;
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (s->lambda_nm[mid] <= lambda_nm) lo = mid;
    else hi = mid;
  }
  return lo;
}

double sf_spectrum_linear(const sf_spectrum *s, double lambda_nm) {
  int i = segment(s, lambda_nm);
  if (i < 0) return NAN;
  double t = (lambda_nm - s->lambda_nm[i]) / (s->lambda_nm[i + 1] - s->lambda_nm[i]);
  if (t == 0.0) return s->value[i];
  if (t == 1.0) return s->value[i + 1];
  return s->value[i] + t * (s->value[i + 1] - s->value[i]);
}

double sf_spectrum_loglog(const sf_spectrum *s, double lambda_nm) {
  int i = segment(s, lambda_nm);
  if (i < 0) return NAN;
  if (lambda_nm == s->lambda_nm[i]) return s->value[i];
  if (lambda_nm == s->lambda_nm[i + 1]) return s->value[i + 1];
  double t = log(lambda_nm / s->lambda_nm[i]) / log(s->lambda_nm[i + 1] / s->lambda_nm[i]);
  return s->value[i] * pow(s->value[i + 1] / s->value[i], t);
}

double sf_spectrum_window_mean(const sf_spectrum *s, double lo_nm, double hi_nm) {
  if (!(hi_nm > lo_nm) || !sf_spectrum_covers(s, lo_nm) || !sf_spectrum_covers(s, hi_nm)) return NAN;
  double sum = 0.0;
  int i = segment(s, lo_nm);
  double a = lo_nm;
  while (a < hi_nm && i < s->n - 1) {
    double b = fmin(hi_nm, s->lambda_nm[i + 1]);
    if (b > a) sum += 0.5 * (sf_spectrum_linear(s, a) + sf_spectrum_linear(s, b)) * (b - a); /* exact: linear piece */
    a = b;
    ++i;
  }
  return sum / (hi_nm - lo_nm);
}

int sf_cmf_load(sf_cmf *out, sf_error *err) {
  static const char *const file = "cie1931_2deg_5nm.csv";
  if (sf_spectrum_load(file, "xbar", &out->x, err) || sf_spectrum_load(file, "ybar", &out->y, err) ||
      sf_spectrum_load(file, "zbar", &out->z, err))
    return SF_ERR_INPUT;
  return 0;
}

void sf_cmf_at(const sf_cmf *cmf, double lambda_nm, double xyz_bar[3]) {
  const sf_spectrum *s[3] = {&cmf->x, &cmf->y, &cmf->z};
  for (int i = 0; i < 3; ++i)
    xyz_bar[i] = sf_spectrum_covers(s[i], lambda_nm) ? sf_spectrum_linear(s[i], lambda_nm) : 0.0;
}

void sf_spectral4_to_xyz(const sf_cmf *cmf, const double lambda_nm[4], const double weight_nm[4],
                         double to_xyz[12]) {
  for (int i = 0; i < 4; ++i) {
    double bar[3];
    sf_cmf_at(cmf, lambda_nm[i], bar);
    for (int c = 0; c < 3; ++c) to_xyz[c * 4 + i] = bar[c] * weight_nm[i];
  }
}

void sf_spectral4_srgb_of_xyz(const double to_xyz[12], double to_linear_srgb[12]) {
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i < 4; ++i) {
      to_linear_srgb[r * 4 + i] = 0.0;
      for (int c = 0; c < 3; ++c) to_linear_srgb[r * 4 + i] += sf_xyz_to_linear_srgb_matrix[r][c] * to_xyz[c * 4 + i];
    }
}
