#include "fit/fit_sky_elevation.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fit/fit_sky_config.h"
#include "fit/linear_lsq.h"
#include "fit/published_sky.h"
#include "fit/sky_bezier_gram.h"
#include "fit/sky_radiance_samples.h"
#include "models/preetham.h"
#include "util/constants.h"
#include "util/clock.h"

#define MAX_PARAMS (SF_BEZIER_POINTS * SF_HOSEK_N_COEFFS)
#define MAX_CURVE_SUNS (SF_SKY_CURVE_STEPS * (SF_SKY_MAX_ELEVATIONS - 1) + 1)
_Static_assert(MAX_CURVE_SUNS <= SF_SKY_BEZIER_MAX_ELEVATIONS, "step 3's suns must fit a Bezier Gram");

static const double start_turbidities[3] = {2.0, 4.0, 7.0};

void sf_sky_elevation_options_default(sf_sky_elevation_options *o, sf_sky_form form) {
  memset(o, 0, sizeof *o);
  o->form = form;
  o->elevation_min_rad = 0.0;
  o->elevation_max_rad = 0.5 * SF_PI;
  o->n_elevations = 19;
  o->n_theta = 16;
  o->n_phi = 24;
  sf_sky_fit_options_default(&o->lsq);
  o->elevation_fit_max_iterations = SF_SKY_ELEVATION_FIT_MAX_ITERATIONS;
}

/* sf_lsq_gram_fn over blocks [0] coefficient control points [6][nc], [1]
 * scale control points [6]. */
static int global_gram(void *user, const double *const *params, double *sum_squares, double *gram) {
  sf_sky_bezier_gram_eval(user, params[0], params[1], sum_squares, gram);
  return 1;
}

/* One Ceres fit of a channel's control points from P, Q (solved in place),
 * through the Gram matrix of all its samples (fit/sky_bezier_gram.h: the
 * same bits on any CPU). Returns SF_OK when usable, SF_ERR_INTERNAL when
 * out of memory, -1 when this start failed (not finite, or the solver gave
 * up). */
static int global_fit(const sf_sky_bezier_gram *bezier, const sf_lsq_options *lsq, double *P, double *Q,
                      sf_lsq_summary *sum, sf_error *err) {
  const sf_sky_form form = bezier->form;
  int nc = sf_sky_form_n_coeffs(form);
  memset(sum, 0, sizeof *sum);
  sf_lsq_problem *p = sf_lsq_problem_new();
  if (!p) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int blocks[2] = {sf_lsq_add_block(p, P, SF_BEZIER_POINTS * nc),
                   sf_lsq_add_block(p, Q, SF_BEZIER_POINTS)};
  for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
    for (int i = 0; i < nc; ++i) {
      double lo, hi;
      sf_sky_coeff_bounds(form, SF_SKY_BOUNDS_PHYSICAL, i, &lo, &hi);
      sf_lsq_set_bounds(p, blocks[0], j * nc + i, lo, hi);
    }
    if (form == SF_SKY_FORM_PEREZ) sf_lsq_set_bounds(p, blocks[1], j, 0.0, INFINITY);
  }
  if (form == SF_SKY_FORM_HOSEK) sf_lsq_set_constant(p, blocks[1]);
  /* the callback only reads it */
  sf_lsq_add_gram_residuals(p, global_gram, (void *)bezier, 2, blocks);
  double start_cost;
  int rc = -1;
  if (sf_lsq_cost(p, &start_cost) == 0 && isfinite(start_cost))
    rc = sf_lsq_solve(p, lsq, sum) == 0 && isfinite(sum->final_cost) ? SF_OK : -1;
  else snprintf(sum->message, sizeof sum->message, "start not finite");
  sf_lsq_problem_free(p);
  return rc;
}

/* Best factor a minimising sum (a model_i - data_i)^2. */
static double best_factor(double sum_md, double sum_mm) { return sum_mm > 0 ? sum_md / sum_mm : 1.0; }

/* Step 2 starts for elevation e, channel k: starts[s][0..nc] (coeffs, scale). */
static int make_starts(const sf_sky_elevation_options *o, const sf_hosek_dataset *published,
                       const sf_atmosphere *atm, const sf_sky_samples *s, int k, double zenith,
                       const double *previous, double starts[][SF_HOSEK_N_COEFFS + 1],
                       char names[][32]) {
  int nc = sf_sky_form_n_coeffs(o->form);
  int n = 0;
  for (int t = 0; t < 3; ++t) {
    double *c = starts[n];
    double T = start_turbidities[t];
    if (o->form == SF_SKY_FORM_HOSEK) {
      if (!published) continue;
      int dch = atm->n_channels == 3 ? k : 1;
      double albedo = fmin(fmax(atm->ground_albedo[k], 0.0), 1.0), R;
      sf_error e = {0};
      double elev = fmin(fmax(s->elevation_rad, 0.0), 0.5 * SF_PI);
      if (sf_hosek_dataset_state(published, dch, T, albedo, elev, c, &R, &e) != SF_OK) continue;
      /* the published shape with its linear part (C, D, F, G, I) rescaled */
      double md = 0, mm = 0;
      for (int i = 0; i < s->n; ++i) {
        double f = zenith * sf_hosek_f(c, s->cos_theta[i], s->gamma[i]);
        md += f * s->radiance[(size_t)i * s->n_channels + k];
        mm += f * f;
      }
      double a = best_factor(md, mm);
      const int linear[5] = {SF_HOSEK_C, SF_HOSEK_D, SF_HOSEK_F, SF_HOSEK_G, SF_HOSEK_I};
      for (int q = 0; q < 5; ++q) c[linear[q]] *= a;
      c[nc] = zenith;
    } else {
      sf_preetham_coefficients(SF_PREETHAM_Y, T, c);
      double md = 0, mm = 0;
      for (int i = 0; i < s->n; ++i) {
        double f = sf_perez_f(c, s->cos_theta[i], s->gamma[i]);
        md += f * s->radiance[(size_t)i * s->n_channels + k];
        mm += f * f;
      }
      c[nc] = best_factor(md, mm);
    }
    snprintf(names[n], 32, "published T=%g", T);
    ++n;
  }
  if (previous) {
    memcpy(starts[n], previous, sizeof(double) * (size_t)(nc + 1));
    if (o->form == SF_SKY_FORM_HOSEK) starts[n][nc] = zenith;
  }
  snprintf(names[n], 32, "previous elevation");
  if (previous) ++n;
  return n;
}

/* Bezier control points from values v[e] at x[e] (weights w may be NULL). */
static int bezier_lsq(int n_e, const double (*bernstein)[SF_BEZIER_POINTS], const double *v,
                      const double *w, double *p, int stride) {
  double A[SF_SKY_MAX_ELEVATIONS * SF_BEZIER_POINTS], x[SF_BEZIER_POINTS];
  for (int e = 0; e < n_e; ++e)
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) A[e * SF_BEZIER_POINTS + j] = bernstein[e][j];
  if (sf_linear_lsq(n_e, SF_BEZIER_POINTS, A, v, w, x) != 0) return -1;
  for (int j = 0; j < SF_BEZIER_POINTS; ++j) p[j * stride] = x[j];
  return 0;
}

double sf_sky_fit_elevation(const sf_sky_elevation_options *o, int e, double *x) {
  double x0 = sf_bezier_x_of_elevation(o->elevation_min_rad);
  double x1 = sf_bezier_x_of_elevation(o->elevation_max_rad);
  *x = x0 + (x1 - x0) * e / (o->n_elevations - 1);
  return 0.5 * SF_PI * *x * *x * *x;
}

double sf_sky_curve_elevation(const sf_sky_elevation_options *o, int c, double *x) {
  /* every SF_SKY_CURVE_STEPS-th is a fit sun, to the bit */
  if (c % SF_SKY_CURVE_STEPS == 0) return sf_sky_fit_elevation(o, c / SF_SKY_CURVE_STEPS, x);
  double x0 = sf_bezier_x_of_elevation(o->elevation_min_rad);
  double x1 = sf_bezier_x_of_elevation(o->elevation_max_rad);
  *x = x0 + (x1 - x0) * c / (SF_SKY_CURVE_STEPS * (o->n_elevations - 1));
  return 0.5 * SF_PI * *x * *x * *x;
}

/* The published skies on the metric grid (fit/published_sky.h): their
 * RMSE and turbidity, NAN where they do not apply. */
static void baseline_scan(const sf_sky_samples *samples, int n_e, const sf_atmosphere *atm,
                          const sf_hosek_dataset *published, int preetham,
                          double *best_rmse, double *best_T) {
  sf_published_sky p;
  sf_error ignored = {0};
  sf_published_sky_fit(samples, n_e, atm, published, preetham, &p, best_rmse, &ignored);
  *best_T = p.turbidity;
}

/* Sum of the squared reference radiances of channel k over samples s (the
 * RMS that normalises residuals per elevation, steps 1 and 4). */
static double channel_sum_squares(const sf_sky_samples *s, int k, int nk) {
  double ss = 0.0;
  for (int i = 0; i < s->n; ++i) {
    double v = s->radiance[(size_t)i * nk + k];
    ss += v * v;
  }
  return ss;
}

/* Step 4's sun elevations: the fit's n_e and, held out, the n_e - 1
 * midpoints in x between them (where the curves are not fitted: with 10
 * fit elevations a Hosek fit of the built-in Earth measured 0.00096 at
 * them and 0.0039 on random suns, 0.0086 between 63 and 90 deg). Returns
 * their count, 2 n_e - 1. */
static int metric_elevations(const double *fit_rad, int n_e, double *out_rad, int *held_out) {
  int n = 0;
  for (int e = 0; e < n_e; ++e) {
    if (e > 0) {
      double xm = 0.5 * (sf_bezier_x_of_elevation(fit_rad[e - 1]) + sf_bezier_x_of_elevation(fit_rad[e]));
      held_out[n] = 1;
      out_rad[n++] = 0.5 * SF_PI * xm * xm * xm;
    }
    held_out[n] = 0;
    out_rad[n++] = fit_rad[e];
  }
  return n;
}

/* Step 4's samples (fit_sky_elevation.h) at each metric elevation: grid[e]
 * at the midpoints of 4 n_theta equal steps of the view zenith angle over
 * [0, 90] deg (the fit's 16 rows end at 87.2 deg, and a Hosek fit erred
 * 0.031 at 89.3 deg where they found 0.0079), band[e] the horizon band's
 * rows at mu = 0.03 down to 1e-4, where these models err most. */
static int metric_samples(const sf_sky_tables *sky, const sf_sky_elevation_options *o, int n_m,
                          const double *elevation_rad, sf_sky_samples *grid, sf_sky_samples *band, sf_error *err) {
  static const double horizon_mu[] = {0.03, 0.02, 0.015, 0.01, 0.007, 0.005, 0.003, 0.002, 0.001, 1e-4};
  enum { N_HORIZON = sizeof horizon_mu / sizeof horizon_mu[0] };
  int n_grid = 4 * o->n_theta;
  double *theta = malloc(sizeof *theta * (size_t)n_grid), band_theta[N_HORIZON];
  if (!theta) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < n_grid; ++i) theta[i] = (i + 0.5) / n_grid * 0.5 * SF_PI;
  for (int i = 0; i < N_HORIZON; ++i) band_theta[i] = acos(horizon_mu[i]);
  int status = SF_OK;
  for (int e = 0; e < n_m && status == SF_OK; ++e) {
    status = sf_sky_samples_at(sky, elevation_rad[e], n_grid, theta, o->n_phi, &grid[e], err);
    if (status == SF_OK) status = sf_sky_samples_at(sky, elevation_rad[e], N_HORIZON, band_theta, o->n_phi, &band[e], err);
  }
  free(theta);
  return status;
}

/* The fitted model's errors: RMSE, relative and normalised RMSE (each
 * elevation's residuals divided by its metric grid's RMS reference
 * radiance, as step 1 divides by its fit grid's; the held-out elevations
 * have no fit grid) over the grids of all metric elevations, the RMSE
 * over the held-out ones alone, the largest error over the grids and the
 * bands. */
static void sky_metrics(const sf_elevation_sky_model *model, int n_m, const int *held_out, const sf_sky_samples *grid,
                        const sf_sky_samples *band, sf_sky_elevation_report *rep) {
  int nk = model->n_channels;
  double sse = 0, sse_rel = 0, sse_norm = 0, sse_held = 0, max_abs = 0;
  long n = 0, n_rel = 0, n_held = 0;
  for (int e = 0; e < n_m; ++e) {
    double weight[SF_MAX_CHANNELS];
    for (int k = 0; k < nk; ++k) {
      double ss = channel_sum_squares(&grid[e], k, nk);
      weight[k] = ss > 0.0 ? sqrt(grid[e].n / ss) : 0.0;
    }
    for (int part = 0; part < 2; ++part) {
      const sf_sky_samples *s = part == 0 ? &grid[e] : &band[e];
      for (int i = 0; i < s->n; ++i) {
        double m[SF_MAX_CHANNELS];
        sf_elevation_sky_radiance(model, s->elevation_rad, s->theta[i], s->gamma[i], m);
        for (int k = 0; k < nk; ++k) {
          double ref = s->radiance[(size_t)i * nk + k], d = m[k] - ref;
          if (part == 0) {
            sse += d * d;
            sse_norm += d * d * weight[k] * weight[k];
            ++n;
            if (held_out[e]) {
              sse_held += d * d;
              ++n_held;
            }
            if (ref > 0) {
              sse_rel += (d / ref) * (d / ref);
              ++n_rel;
            }
          }
          if (!(fabs(d) <= max_abs)) {
            max_abs = fabs(d);
            rep->worst_elevation_rad = s->elevation_rad;
            rep->worst_theta = s->theta[i];
            rep->worst_gamma = s->gamma[i];
          }
        }
      }
    }
  }
  rep->n_metric_elevations = n_m;
  rep->n_metric_samples = n / nk;
  rep->rmse = sqrt(sse / (double)n);
  rep->held_out_rmse = n_held ? sqrt(sse_held / (double)n_held) : NAN;
  rep->normalised_rmse = sqrt(sse_norm / (double)n);
  rep->rel_rmse = n_rel ? sqrt(sse_rel / (double)n_rel) : NAN;
  rep->max_abs = max_abs;
}

int sf_fit_sky_elevation(const sf_sky_tables *sky, const sf_sky_elevation_options *o,
                         const sf_hosek_dataset *published, sf_elevation_sky_model *out,
                         sf_sky_elevation_report *rep, sf_error *err) {
  const sf_atmosphere *atm = sky->atm;
  double t0 = sf_wall_seconds();
  memset(rep, 0, sizeof *rep);
  memset(out, 0, sizeof *out);
  int n_e = o->n_elevations, nk = atm->n_channels, nc = sf_sky_form_n_coeffs(o->form);
  if (n_e < SF_BEZIER_POINTS || n_e > SF_SKY_MAX_ELEVATIONS)
    return sf_fail(err, SF_ERR_INPUT, "sky fit: %d sun elevations; need %d..%d", n_e,
                   SF_BEZIER_POINTS, SF_SKY_MAX_ELEVATIONS);
  /* a single elevation had been told it was not "a range within [0, 90]" */
  if (o->elevation_min_rad >= 0.0 && o->elevation_min_rad == o->elevation_max_rad)
    return sf_fail(err, SF_ERR_INPUT,
                   "sky fit: a single sun elevation (%g deg): Perez and Hosek are fitted across a range of "
                   "elevations (a curve in elevation, as Hosek's), not at one",
                   o->elevation_min_rad * 180 / SF_PI);
  if (!(o->elevation_min_rad >= 0.0 && o->elevation_min_rad < o->elevation_max_rad &&
        o->elevation_max_rad <= 0.5 * SF_PI + 1e-12))
    return sf_fail(err, SF_ERR_INPUT,
                   "sky fit: sun elevation range [%g, %g] deg must be a range within [0, 90] "
                   "(Perez and Hosek hold only for a sun above the horizon)",
                   o->elevation_min_rad * 180 / SF_PI, o->elevation_max_rad * 180 / SF_PI);
  out->form = o->form;
  out->n_coeffs = nc;
  out->n_channels = nk;
  out->elevation_min_rad = o->elevation_min_rad;
  out->elevation_max_rad = fmin(o->elevation_max_rad, 0.5 * SF_PI);
  rep->n_elevations = n_e;
  rep->n_channels = nk;
  const int n_c = SF_SKY_CURVE_STEPS * (n_e - 1) + 1;   /* step 3's suns; fit sun e is c = 3 e */
  rep->n_curve_elevations = n_c;

  /* samples and weights per step 3's sun c */
  sf_sky_samples *samples = calloc((size_t)n_c, sizeof *samples);
  double *weights = calloc((size_t)n_c * (size_t)nk, sizeof *weights);
  /* per-elevation solutions [e][k][nc + 1] */
  double *solved = calloc((size_t)n_e * (size_t)nk * (size_t)(nc + 1), sizeof *solved);
  double bernstein[SF_SKY_MAX_ELEVATIONS][SF_BEZIER_POINTS];   /* per fit sun */
  double curve_bernstein[MAX_CURVE_SUNS][SF_BEZIER_POINTS];   /* per step 3's sun */
  int status = (samples && weights && solved) ? SF_OK
                                              : sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  for (int c = 0; c < n_c && status == SF_OK; ++c) {
    double x;
    double elev = sf_sky_curve_elevation(o, c, &x);
    sf_bezier_weights(x, curve_bernstein[c]);
    status = sf_sky_samples_from_tables(sky, elev, o->n_theta, o->n_phi, &samples[c], err);
    if (c % SF_SKY_CURVE_STEPS == 0) {
      const int e = c / SF_SKY_CURVE_STEPS;
      rep->elevation_rad[e] = elev;
      memcpy(bernstein[e], curve_bernstein[c], sizeof bernstein[e]);
      rep->n_samples += status == SF_OK ? samples[c].n : 0;
    }
    for (int k = 0; k < nk && status == SF_OK; ++k) {
      double rms = sqrt(channel_sum_squares(&samples[c], k, nk) / samples[c].n);
      if (!(rms > 0) || !(samples[c].zenith_radiance[k] > 0))
        status = sf_fail(err, SF_ERR_INPUT,
                         "sky fit: the reference sky is dark in channel %d at sun elevation %g deg",
                         k, elev * 180 / SF_PI);
      weights[c * nk + k] = 1.0 / rms;
    }
  }

  /* Step 2: per elevation and channel, multi-start. */
  double sse_per_elevation = 0.0;
  for (int k = 0; k < nk && status == SF_OK; ++k) {
    for (int e = 0; e < n_e && status == SF_OK; ++e) {
      const int c = SF_SKY_CURVE_STEPS * e;
      const sf_sky_samples *s = &samples[c];
      sf_sky_fit_data d = {o->form, s->n, s->cos_theta, s->gamma, s->cos_gamma,
                           s->radiance + k, nk, weights[c * nk + k]};
      double starts[SF_SKY_MAX_STARTS][SF_HOSEK_N_COEFFS + 1];
      char names[SF_SKY_MAX_STARTS][32];
      const double *previous = e > 0 ? &solved[((size_t)(e - 1) * nk + k) * (nc + 1)] : NULL;
      int n_starts = make_starts(o, published, atm, s, k, s->zenith_radiance[k], previous, starts,
                                 names);
      if (n_starts == 0) {
        /* no published set to start Hosek from: a flat sky */
        memset(starts[0], 0, sizeof starts[0]);
        starts[0][SF_HOSEK_C] = 1.0;
        starts[0][SF_HOSEK_H] = 0.5;
        starts[0][nc] = s->zenith_radiance[k];
        snprintf(names[0], 32, "flat sky");
        n_starts = 1;
      }
      if (e == 1 || rep->n_starts == 0) {
        rep->n_starts = (published || o->form == SF_SKY_FORM_PEREZ) ? 4 : 2;
        for (int q = 0; q < SF_SKY_MAX_STARTS; ++q) {
          if (q < 3 && (published || o->form == SF_SKY_FORM_PEREZ))
            snprintf(rep->start_names[q], 32, "published T=%g", start_turbidities[q]);
        }
        snprintf(rep->start_names[rep->n_starts - 1], 32, "previous elevation");
        if (!(published || o->form == SF_SKY_FORM_PEREZ)) snprintf(rep->start_names[0], 32, "flat sky");
      }
      double *sol = &solved[((size_t)e * nk + k) * (nc + 1)];
      int winner;
      sf_lsq_summary sum;
      status = sf_fit_sky_multistart(&d, SF_SKY_BOUNDS_PHYSICAL, o->form == SF_SKY_FORM_HOSEK,
                                     &o->lsq, n_starts, (const double(*)[SF_HOSEK_N_COEFFS + 1])starts, sol, &sol[nc], &winner, &sum,
                                     NULL, err);
      if (status != SF_OK) break;
      /* map the winner to the report's start list by name */
      int slot = 0;
      for (int q = 0; q < rep->n_starts; ++q)
        if (strcmp(rep->start_names[q], names[winner]) == 0) slot = q;
      rep->winner[e][k] = slot;
      rep->start_wins[slot]++;
      sse_per_elevation += 2.0 * sum.final_cost / (weights[c * nk + k] * weights[c * nk + k]);
      if (o->progress)
        o->progress(o->progress_ctx, "per-elevation fits", (double)(k * n_e + e + 1) / (nk * n_e));
    }
  }
  rep->per_elevation_rmse = sqrt(sse_per_elevation / ((double)rep->n_samples * nk));

  /* Step 3: Bezier control points per channel, then the global fit. */
  for (int k = 0; k < nk && status == SF_OK; ++k) {
    double v[SF_SKY_MAX_ELEVATIONS], w[SF_SKY_MAX_ELEVATIONS];
    for (int i = 0; i <= nc && status == SF_OK; ++i) {
      for (int e = 0; e < n_e; ++e) {
        v[e] = solved[((size_t)e * nk + k) * (nc + 1) + i];
        w[e] = i == nc ? 1.0 / v[e] : 1.0;   /* the scale: relative error */
      }
      double *p = i < nc ? &out->coefficients[k][0][i] : &out->scale[k][0];
      if (bezier_lsq(n_e, bernstein, v, i == nc && v[0] > 0 ? w : NULL, p,
                     i < nc ? SF_HOSEK_N_COEFFS : 1) != 0)
        status = sf_fail(err, SF_ERR_INTERNAL, "sky fit: Bezier control points are singular");
    }
    if (status != SF_OK) break;
    /* the channel's samples at every sun of step 3, prepared once for its
     * four starts */
    sf_sky_fit_data data[MAX_CURVE_SUNS];
    for (int c = 0; c < n_c; ++c) {
      const sf_sky_samples *s = &samples[c];
      data[c] = (sf_sky_fit_data){o->form, s->n, s->cos_theta, s->gamma, s->cos_gamma,
                                  s->radiance + k, nk, weights[c * nk + k]};
    }
    sf_sky_bezier_gram bezier;
    if (sf_sky_bezier_gram_init(&bezier, o->form, n_c, data,
                                (const double(*)[SF_BEZIER_POINTS])curve_bernstein)) {
      status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
      break;
    }
    /* Global starts: the curve through the per-elevation fits, and constant
     * curves holding one elevation's coefficients (finite everywhere, where
     * the first can swing far off between the elevations it passes). */
    sf_lsq_options lsq = o->lsq;
    lsq.max_iterations = o->elevation_fit_max_iterations;
    double best_cost = INFINITY;
    double best_P[MAX_PARAMS], best_Q[SF_BEZIER_POINTS];
    int best_start = -1;
    const int constant_from[3] = {n_e / 4, n_e / 2, (3 * n_e) / 4};
    for (int st = 0; st < 4 && status == SF_OK; ++st) {
      double P[MAX_PARAMS], Q[SF_BEZIER_POINTS];
      for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
        for (int i = 0; i < nc; ++i)
          P[j * nc + i] = st == 0 ? out->coefficients[k][j][i]
                                  : solved[((size_t)constant_from[st - 1] * nk + k) * (nc + 1) + i];
        Q[j] = out->scale[k][j];
        double scale_j = Q[j];
        sf_sky_clamp_to_bounds(o->form, SF_SKY_BOUNDS_PHYSICAL, &P[j * nc], &scale_j);
        if (o->form == SF_SKY_FORM_PEREZ) Q[j] = scale_j;
      }
      sf_lsq_summary sum;
      int rc = global_fit(&bezier, &lsq, P, Q, &sum, err);
      if (rc > 0) status = rc;
      if (status != SF_OK) break;
      if (rc == SF_OK && sum.final_cost < best_cost) {
        best_cost = sum.final_cost;
        best_start = st;
        memcpy(best_P, P, sizeof P);
        memcpy(best_Q, Q, sizeof Q);
        rep->global_initial_cost_channel[k] = sum.initial_cost;
        rep->global_iterations_channel[k] = sum.iterations;
        rep->global_at_cap_channel[k] = sum.termination == SF_LSQ_NO_CONVERGENCE;
        rep->global_termination_channel[k] = sum.termination;
      }
    }
    sf_sky_bezier_gram_free(&bezier);
    if (status == SF_OK && best_start < 0)
      status = sf_fail(err, SF_ERR_INTERNAL, "sky fit: every elevation fit of channel %d failed", k);
    if (status != SF_OK) break;
    rep->global_start_wins[best_start]++;
    rep->global_initial_cost += rep->global_initial_cost_channel[k];
    rep->global_final_cost += best_cost;
    rep->global_iterations += rep->global_iterations_channel[k];
    rep->global_channels_at_cap += rep->global_at_cap_channel[k];
    rep->global_max_iterations = lsq.max_iterations;
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
      for (int i = 0; i < nc; ++i) out->coefficients[k][j][i] = best_P[j * nc + i];
      out->scale[k][j] = best_Q[j];
    }
    if (o->progress) o->progress(o->progress_ctx, "elevation Bezier fit", (double)(k + 1) / nk);
  }

  /* Step 4: metrics over the domain, and the baselines on the same grid. */
  double metric_rad[2 * SF_SKY_MAX_ELEVATIONS];
  int held_out[2 * SF_SKY_MAX_ELEVATIONS];
  int n_m = metric_elevations(rep->elevation_rad, n_e, metric_rad, held_out);
  sf_sky_samples *grid = calloc((size_t)n_m, sizeof *grid), *band = calloc((size_t)n_m, sizeof *band);
  if (status == SF_OK && (!grid || !band)) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) status = metric_samples(sky, o, n_m, metric_rad, grid, band, err);
  if (status == SF_OK) {
    sky_metrics(out, n_m, held_out, grid, band, rep);
    if (!isfinite(rep->rmse)) status = sf_fail(err, SF_ERR_INTERNAL, "sky fit: the fitted model is not finite");
    baseline_scan(grid, n_m, atm, published, 1, &rep->preetham_rmse, &rep->preetham_turbidity);
    baseline_scan(grid, n_m, atm, published, 0, &rep->hosek_published_rmse, &rep->hosek_published_turbidity);
  }
  for (int e = 0; e < n_m; ++e) {
    if (grid) sf_sky_samples_free(&grid[e]);
    if (band) sf_sky_samples_free(&band[e]);
  }
  free(grid);
  free(band);
  for (int c = 0; samples && c < n_c; ++c) sf_sky_samples_free(&samples[c]);
  free(samples);
  free(weights);
  free(solved);
  rep->seconds = sf_wall_seconds() - t0;
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}
