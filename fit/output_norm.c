#include "fit/output_norm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/linear_lsq.h"

typedef struct slice_key {
  double u, v;   /* normalised sqrt h, mu_s */
  long sample;
} slice_key;

static int compare_keys(const void *pa, const void *pb) {
  const slice_key *a = pa, *b = pb;
  if (a->u != b->u) return a->u < b->u ? -1 : 1;
  if (a->v != b->v) return a->v < b->v ? -1 : 1;
  return a->sample < b->sample ? -1 : (a->sample > b->sample);
}

/* The monomials u^a v^c in the order of sf_mlp_output_norm.coef. */
static void monomials(int A, int C, double u, double v, double *row) {
  double ua = 1.0;
  for (int a = 0; a <= A; ++a, ua *= u) {
    double vc = 1.0;
    for (int c = 0; c <= C; ++c, vc *= v) row[a * (C + 1) + c] = ua * vc;
  }
}

int sf_output_norm_fit(const sf_dataset *d, int degree_h, int degree_mu_s, double cap_below, sf_mlp_output_norm *out,
                       sf_error *err) {
  memset(out, 0, sizeof *out);
  if (!(cap_below >= 0.0))
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: cap %g below the brightest: expected >= 0 (or inf: none)",
                   cap_below);
  if (d->n_in != 4 || d->n_out < 1)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: a scattering set (4 inputs) expected");
  if (degree_h < 0 || degree_mu_s < 0 || degree_h > SF_MLP_NORM_MAX_DEGREE || degree_mu_s > SF_MLP_NORM_MAX_DEGREE)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: degrees %d, %d: expected 0..%d", degree_h,
                   degree_mu_s, SF_MLP_NORM_MAX_DEGREE);
  int n_coef = (degree_h + 1) * (degree_mu_s + 1), n_out = d->n_out;
  size_t rows = (size_t)(d->n > 0 ? d->n : 1);
  slice_key *keys = malloc(sizeof *keys * rows);
  double *A = malloc(sizeof *A * rows * (size_t)n_coef);
  double *b = malloc(sizeof *b * rows);
  if (!keys || !A || !b) {
    free(keys);
    free(A);
    free(b);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  for (long i = 0; i < d->n; ++i) keys[i] = (slice_key){d->x[i * 4 + 0], d->x[i * 4 + 2], i};
  qsort(keys, (size_t)d->n, sizeof *keys, compare_keys);
  int m = 0;   /* slices */
  double largest = 0.0;
  for (long s = 0; s < d->n;) {
    long e = s;
    double sum_sq = 0.0;
    for (; e < d->n && keys[e].u == keys[s].u && keys[e].v == keys[s].v; ++e) {
      const double *y = d->y + keys[e].sample * n_out;
      for (int o = 0; o < n_out; ++o) sum_sq += y[o] * y[o];
    }
    b[m] = sqrt(sum_sq / ((double)(e - s) * n_out));
    monomials(degree_h, degree_mu_s, keys[s].u, keys[s].v, A + (size_t)m * n_coef);
    if (b[m] > largest) largest = b[m];
    ++m;
    s = e;
  }
  int lit = 0;
  for (int s = 0; s < m; ++s)
    if (b[s] > SF_OUTPUT_NORM_FLOOR * largest) {
      memmove(A + (size_t)lit * n_coef, A + (size_t)s * n_coef, sizeof *A * (size_t)n_coef);
      b[lit++] = log(b[s]);
    }
  int status = SF_OK;
  if (!(largest > 0.0))
    status = sf_fail(err, SF_ERR_INPUT, "brightness normalisation: the set holds no light");
  else if (lit < n_coef)
    status = sf_fail(err, SF_ERR_INPUT, "brightness normalisation: %d lit slices of (altitude, sun elevation) "
                     "for %d coefficients", lit, n_coef);
  else if (sf_linear_lsq(lit, n_coef, A, b, NULL, out->coef))
    status = sf_fail(err, SF_ERR_INPUT, "brightness normalisation: the slices do not determine degrees %d, %d",
                     degree_h, degree_mu_s);
  free(keys);
  free(A);
  free(b);
  if (status != SF_OK) return status;
  out->degree_h = degree_h;
  out->degree_mu_s = degree_mu_s;
  if (isfinite(cap_below)) {
    out->has_cap = 1;
    out->cap = log(largest) - cap_below;
  }
  sf_mlp_output_norm_finish(out);
  return SF_OK;
}

/* The polynomial is fitted to the lit slices only; in the dark ones (a sun
 * below the horizon by more than the atmosphere's twilight arc: a thin
 * shell, a huge planet) it extrapolates, and where it falls far below the
 * brightest it scales a target by up to e^450: training diverged, or a
 * target overflowed. Such a set stays raw (SF_ERR_INPUT: the caller's
 * note says why). */
static int check_dark_slices(const sf_mlp_output_norm *n, const sf_dataset *d, sf_error *err) {
  double worst = 0.0;
  long at = -1;
  for (long i = 0; i < d->n && !isnan(worst); ++i) {   /* a NaN (0 times inf) is the worst */
    const double *x = d->x + i * d->n_in;
    double f = exp(-sf_mlp_output_norm_log_brightness(n, x[0], x[2]));
    for (int o = 0; o < d->n_out; ++o) {
      double scaled = fabs(d->y[i * d->n_out + o]) * f;
      if (!(scaled <= worst)) {
        worst = scaled;
        at = i;
        if (isnan(scaled)) break;
      }
    }
  }
  if (at >= 0 && !(worst <= SF_OUTPUT_NORM_MAX_SCALED))
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: extrapolated to a dark slice (normalised sqrt h %.3g, "
                   "mu_s %.3g) it scales a target to %.3g, above %g", d->x[at * d->n_in], d->x[at * d->n_in + 2],
                   worst, SF_OUTPUT_NORM_MAX_SCALED);
  return SF_OK;
}

int sf_output_norm_prepare(sf_dataset *d, double cap_below, sf_mlp_output_norm *out, char *why, size_t why_size,
                           sf_error *err) {
  if (why_size > 0) why[0] = '\0';
  if (!(cap_below >= 0.0))   /* a caller's error, not a set too coarse */
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: cap %g below the brightest: expected >= 0", cap_below);
  sf_error fit_err = {0};
  int status = sf_output_norm_fit(d, SF_OUTPUT_NORM_DEGREE_H, SF_OUTPUT_NORM_DEGREE_MU_S, cap_below, out, &fit_err);
  if (status == SF_OK) status = check_dark_slices(out, d, &fit_err);
  if (status == SF_OK) {
    sf_output_norm_apply(out, d);
    return SF_OK;
  }
  memset(out, 0, sizeof *out);
  if (status != SF_ERR_INPUT) return sf_fail(err, status, "%s", fit_err.message);
  if (why_size > 0) snprintf(why, why_size, "%s", fit_err.message);
  return SF_OK;
}

static void scale_targets(const sf_mlp_output_norm *n, sf_dataset *d, double sign) {
  for (long i = 0; i < d->n; ++i) {
    const double *x = d->x + i * d->n_in;
    double f = exp(sign * sf_mlp_output_norm_log_brightness(n, x[0], x[2]));
    double *y = d->y + i * d->n_out;
    for (int o = 0; o < d->n_out; ++o) y[o] *= f;
  }
}

void sf_output_norm_apply(const sf_mlp_output_norm *n, sf_dataset *d) { scale_targets(n, d, -1.0); }
void sf_output_norm_restore(const sf_mlp_output_norm *n, sf_dataset *d) { scale_targets(n, d, 1.0); }
