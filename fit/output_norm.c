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

/* One slice of equal (u, v): the RMS of its targets. */
typedef struct slice {
  double u, v, rms;
} slice;

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

/* d's slices, sorted by u, then v; *out (free it) holds *m of them. */
static int collect_slices(const sf_dataset *d, slice **out, int *m, sf_error *err) {
  size_t rows = (size_t)(d->n > 0 ? d->n : 1);
  slice_key *keys = malloc(sizeof *keys * rows);
  slice *s_out = malloc(sizeof *s_out * rows);
  if (!keys || !s_out) {
    free(keys);
    free(s_out);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  for (long i = 0; i < d->n; ++i) keys[i] = (slice_key){d->x[i * 4 + 0], d->x[i * 4 + 2], i};
  qsort(keys, (size_t)d->n, sizeof *keys, compare_keys);
  int count = 0;
  for (long s = 0; s < d->n;) {
    long e = s;
    double sum_sq = 0.0;
    for (; e < d->n && keys[e].u == keys[s].u && keys[e].v == keys[s].v; ++e) {
      const double *y = d->y + keys[e].sample * d->n_out;
      for (int o = 0; o < d->n_out; ++o) sum_sq += y[o] * y[o];
    }
    s_out[count++] = (slice){keys[s].u, keys[s].v, sqrt(sum_sq / ((double)(e - s) * d->n_out))};
    s = e;
  }
  free(keys);
  *out = s_out;
  *m = count;
  return SF_OK;
}

static double largest_rms(const slice *sl, int m) {
  double largest = 0.0;
  for (int s = 0; s < m; ++s)
    if (sl[s].rms > largest) largest = sl[s].rms;
  return largest;
}

/* sf_output_norm_fit on the slices of its set. */
static int fit_slices(const slice *sl, int m, int degree_h, int degree_mu_s, double cap_below, sf_mlp_output_norm *out,
                      sf_error *err) {
  memset(out, 0, sizeof *out);
  if (!(cap_below >= 0.0))
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: cap %g below the brightest: expected >= 0 (or inf: none)",
                   cap_below);
  if (degree_h < 0 || degree_mu_s < 0 || degree_h > SF_MLP_NORM_MAX_DEGREE || degree_mu_s > SF_MLP_NORM_MAX_DEGREE)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: degrees %d, %d: expected 0..%d", degree_h,
                   degree_mu_s, SF_MLP_NORM_MAX_DEGREE);
  int n_coef = (degree_h + 1) * (degree_mu_s + 1);
  size_t rows = (size_t)(m > 0 ? m : 1);
  double *A = malloc(sizeof *A * rows * (size_t)n_coef);
  double *b = malloc(sizeof *b * rows);
  if (!A || !b) {
    free(A);
    free(b);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  double largest = largest_rms(sl, m);
  int lit = 0;
  for (int s = 0; s < m; ++s)
    if (sl[s].rms > SF_OUTPUT_NORM_FLOOR * largest) {
      monomials(degree_h, degree_mu_s, sl[s].u, sl[s].v, A + (size_t)lit * n_coef);
      b[lit++] = log(sl[s].rms);
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

int sf_output_norm_fit(const sf_dataset *d, int degree_h, int degree_mu_s, double cap_below, sf_mlp_output_norm *out,
                       sf_error *err) {
  memset(out, 0, sizeof *out);
  if (d->n_in != 4 || d->n_out < 1)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: a scattering set (4 inputs) expected");
  slice *sl = NULL;
  int m = 0;
  int status = collect_slices(d, &sl, &m, err);
  if (status == SF_OK) status = fit_slices(sl, m, degree_h, degree_mu_s, cap_below, out, err);
  free(sl);
  return status;
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

/* The polynomial passes near every lit slice but, between two slices far
 * apart in v, is free: where a table's sun axis has few entries (Bruneton's
 * mu_s spacing puts 2 of 16 above 40 degrees) a degree-6 fit dipped there
 * by up to 2.3 in log, and since the network never sees a sample between
 * the slices, its outputs times exp(b) dipped alike: a hazy Earth's sky
 * 0.15x the reference's at sun 64 degrees, in every direction, at every
 * altitude (its relative RMSE 0.233, trained raw 0.045). The brightness
 * between two slices of one altitude should not fall far below both of
 * them (capped: the cap is the most it weighs); the largest such dip, on
 * SF_OUTPUT_NORM_DIP_STEPS points between each pair, in *dip (log), at
 * (*at_u, *at_v). */
static double largest_dip(const sf_mlp_output_norm *n, const slice *sl, int m, double *at_u, double *at_v) {
  double dark = SF_OUTPUT_NORM_FLOOR * largest_rms(sl, m), worst = 0.0;
  int prev = -1;
  for (int s = 0; s < m; ++s) {
    if (!(sl[s].rms > dark)) continue;
    if (prev >= 0 && sl[prev].u == sl[s].u) {
      double lo = fmin(log(sl[prev].rms), log(sl[s].rms));
      if (n->has_cap) lo = fmin(lo, n->cap);
      for (int k = 1; k < SF_OUTPUT_NORM_DIP_STEPS; ++k) {
        double v = sl[prev].v + (sl[s].v - sl[prev].v) * k / SF_OUTPUT_NORM_DIP_STEPS;
        double dip = lo - sf_mlp_output_norm_log_brightness(n, sl[s].u, v);
        if (dip > worst) {
          worst = dip;
          *at_u = sl[s].u;
          *at_v = v;
        }
      }
    }
    prev = s;
  }
  return worst;
}

int sf_output_norm_prepare(sf_dataset *d, double cap_below, sf_mlp_output_norm *out, char *why, size_t why_size,
                           sf_error *err) {
  if (why_size > 0) why[0] = '\0';
  memset(out, 0, sizeof *out);
  if (!(cap_below >= 0.0))   /* a caller's error, not a set too coarse */
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: cap %g below the brightest: expected >= 0", cap_below);
  sf_error fit_err = {0};
  if (d->n_in != 4 || d->n_out < 1) {
    sf_fail(&fit_err, SF_ERR_INPUT, "brightness normalisation: a scattering set (4 inputs) expected");
    if (why_size > 0) snprintf(why, why_size, "%s", fit_err.message);
    return SF_OK;
  }
  slice *sl = NULL;
  int m = 0;
  int status = collect_slices(d, &sl, &m, err);
  if (status != SF_OK) return status;
  /* The default degree first; one lower while the fit dips between slices
   * (the sets that need it are the coarse ones: the default scene's at the
   * default resolution keeps degree 6). */
  for (int degree = SF_OUTPUT_NORM_DEGREE_MU_S; degree >= SF_OUTPUT_NORM_DEGREE_MU_S_MIN; --degree) {
    sf_error_clear(&fit_err);
    status = fit_slices(sl, m, SF_OUTPUT_NORM_DEGREE_H, degree, cap_below, out, &fit_err);
    if (status == SF_OK) status = check_dark_slices(out, d, &fit_err);
    if (status != SF_OK) break;
    double at_u = 0.0, at_v = 0.0, dip = largest_dip(out, sl, m, &at_u, &at_v);
    if (dip <= SF_OUTPUT_NORM_MAX_DIP) break;
    status = sf_fail(&fit_err, SF_ERR_INPUT, "brightness normalisation: with degree %d in mu_s down to %d, the "
                     "fit dips %.3g (natural log) below the slices either side (at normalised sqrt h %.3g, mu_s "
                     "%.3g): too few sun elevations in the tables (--resolution)", SF_OUTPUT_NORM_DEGREE_MU_S, degree,
                     dip, at_u, at_v);
  }
  free(sl);
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
