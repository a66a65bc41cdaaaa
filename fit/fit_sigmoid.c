#include "fit/fit_sigmoid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fit/linear_lsq.h"
#include "models/tangent_sweep.h"
#include "models/optical_depth.h"
#include "models/ray_geometry.h"
#include "util/clock.h"

void sf_sigmoid_fit_options_default(sf_sigmoid_fit_options *o) {
  memset(o, 0, sizeof *o);
  o->n_h = 48;
  o->n_mu = 96;
  sf_lsq_options_default(&o->lsq);
}

typedef struct sigmoid_points {
  int n;
  const double *h, *mu, *t;
} sigmoid_points;

/* All residuals in one block: one callback per evaluation, no per-block overhead. */
static int sigmoid_residuals(void *user, const double *const *params, double *r, double **jac) {
  const sigmoid_points *s = user;
  for (int i = 0; i < s->n; ++i) {
    double grad[SF_SIGMOID_N_COEFFS];
    r[i] = sf_sigmoid_transmittance_grad(params[0], s->h[i], s->mu[i], grad) - s->t[i];
    if (jac && jac[0])
      for (int k = 0; k < SF_SIGMOID_N_COEFFS; ++k) jac[0][i * SF_SIGMOID_N_COEFFS + k] = grad[k];
  }
  return 1;
}

/* Weighted logit fit: the start. */
static void logit_start(int n, const double *h, const double *mu, const double *t, double *a) {
  double *A = malloc(sizeof *A * (size_t)n * SF_SIGMOID_N_COEFFS);
  double *b = malloc(sizeof *b * (size_t)n), *w = malloc(sizeof *w * (size_t)n);
  int ok = A && b && w;
  for (int i = 0; ok && i < n; ++i) {
    double ti = fmin(fmax(t[i], 1e-12), 1.0 - 1e-12);
    A[i * 4 + 0] = 1.0;
    A[i * 4 + 1] = h[i];
    A[i * 4 + 2] = mu[i];
    A[i * 4 + 3] = mu[i] * mu[i];
    b[i] = log(ti / (1.0 - ti));
    w[i] = ti * (1.0 - ti) + 1e-6;
  }
  if (!ok || sf_linear_lsq(n, SF_SIGMOID_N_COEFFS, A, b, w, a) != 0) {
    a[0] = 1.0;
    a[1] = a[2] = a[3] = 0.0;
  }
  free(A);
  free(b);
  free(w);
}

static void error_max(sf_sigmoid_error *e, double d, double h, double mu, int k) {
  if (!(fabs(d) <= e->max_abs)) {
    e->max_abs = fabs(d);
    e->worst_h_km = h;
    e->worst_mu = mu;
    e->worst_channel = k;
  }
}

static void error_add(sf_sigmoid_error *e, double *sse, double d, double h, double mu, int k) {
  *sse += d * d;
  e->n_points++;
  error_max(e, d, h, mu, k);
}

/* The full ray at (h, mu), model against the exact optical depth, into
 * rep->full and its ground or sky part; sse_* NULL: the maximum only. */
static void full_ray_error(const sf_atmosphere *atm, const sf_sigmoid_model *model, double h, double mu,
                           sf_sigmoid_fit_report *rep, double *sse_full, double *sse_ground, double *sse_sky) {
  double dep[SF_MAX_CONSTITUENTS], ref[SF_MAX_CHANNELS], mod[SF_MAX_CHANNELS];
  sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, dep);
  sf_transmittance_from_depth(atm, dep, ref);
  sf_sigmoid_model_eval(model, h, mu, mod);
  int ground = sf_ray_hits_sphere_from_above(atm->bottom_radius_km + h, mu, atm->bottom_radius_km);
  for (int k = 0; k < atm->n_channels; ++k) {
    double d = mod[k] - ref[k];
    if (sse_full) {
      error_add(&rep->full, sse_full, d, h, mu, k);
      error_add(ground ? &rep->full_ground : &rep->full_sky, ground ? sse_ground : sse_sky, d, h, mu, k);
    } else {
      error_max(&rep->full, d, h, mu, k);
      error_max(ground ? &rep->full_ground : &rep->full_sky, d, h, mu, k);
    }
  }
}

typedef struct horizon_job {
  const sf_atmosphere *atm;
  const sf_sigmoid_model *model;
  sf_sigmoid_fit_report *rep;
} horizon_job;

static void horizon_visit(void *ctx, double h, double mu) {
  const horizon_job *j = ctx;
  full_ray_error(j->atm, j->model, h, mu, j->rep, NULL, NULL, NULL);
}

/* The to-top grid (fit_sigmoid.h): only rays with mu >= 0 are asked for.
 * Its region holds every point where the model evaluates T_top for the
 * domain's rays, segments included: a segment's end (eq. 43 forward, on
 * a ray that misses the ground) lies anywhere up to the top, looking up
 * at up to the ray's exit cosine (largest from the lowest viewer, r_lo).
 * Fitted on the domain's altitudes alone, the segments had extrapolated
 * the fit: a flight scene's (0-15 km) ozone came out with a2 < 0, T_top
 * falling with altitude, and a longer segment of a ray was up to 0.12
 * more transparent than a shorter one. */
static void top_grid(const sf_scene_domain *dom, double h0, double bottom_radius, double top_radius,
                     int n_h, int n_mu, double *h, double *mu, sf_sigmoid_fit_report *rep) {
  int down = dom->mu_min < 0.0;
  double h_lo = down ? 0.0 : h0, h_hi = top_radius - bottom_radius;
  double lo = down ? 0.0 : dom->mu_min;
  double hi = down ? fmin(1.0, fmax(dom->mu_max, -dom->mu_min)) : dom->mu_max;
  /* the exit cosine at the top, sqrt(1 - (r/Rt)^2 (1 - hi^2)), without cancelling */
  double r_lo = bottom_radius + h_lo;
  if (hi < 1.0) hi = fmin(1.0, sqrt((top_radius - r_lo) * (top_radius + r_lo) + (r_lo * hi) * (r_lo * hi)) / top_radius);
  rep->fit_h_min_km = h_lo;
  rep->fit_h_max_km = h_hi;
  rep->fit_mu_min = lo;
  rep->fit_mu_max = hi;
  for (int i = 0; i < n_h; ++i)
    for (int j = 0; j < n_mu; ++j) {
      h[i * n_mu + j] = h_lo + (h_hi - h_lo) * i / (n_h - 1);
      mu[i * n_mu + j] = lo + (hi - lo) * j / (n_mu - 1);
    }
}

int sf_fit_sigmoid(const sf_atmosphere *atm, const sf_scene_domain *domain,
                   const sf_sigmoid_fit_options *o, sf_sigmoid_model *out,
                   sf_sigmoid_fit_report *rep, sf_error *err) {
  double t0 = sf_wall_seconds();
  memset(out, 0, sizeof *out);
  memset(rep, 0, sizeof *rep);
  if (o->n_h < 2 || o->n_mu < 2 || (long)o->n_h * o->n_mu > 4000000L)
    return sf_fail(err, SF_ERR_INPUT, "sigmoid fit: grid %d x %d: need 2..4e6 points per side product",
                   o->n_h, o->n_mu);
  int nc = atm->n_constituents, nk = atm->n_channels, n = o->n_h * o->n_mu;
  double thickness = sf_atmosphere_thickness_km(atm);
  double h0 = fmax(domain->h_min_km, 0.0), h1 = fmin(domain->h_max_km, thickness);
  if (h1 < h0) h0 = h1;
  out->n_constituents = nc;
  out->n_channels = nk;
  out->bottom_radius_km = atm->bottom_radius_km;
  out->top_radius_km = atm->top_radius_km;
  rep->n_points = n;
  double *h = malloc(sizeof *h * (size_t)n), *mu = malloc(sizeof *mu * (size_t)n);
  double *depth = malloc(sizeof *depth * (size_t)n * (size_t)nc);
  double *t = malloc(sizeof *t * (size_t)n);
  double *model_total = malloc(sizeof *model_total * (size_t)n * (size_t)nk);
  double *ref_total = malloc(sizeof *ref_total * (size_t)n * (size_t)nk);
  int status = (h && mu && depth && t && model_total && ref_total)
                   ? SF_OK
                   : sf_fail(err, SF_ERR_INTERNAL, "out of memory for the sigmoid fit");
  if (status == SF_OK)
    top_grid(domain, h0, atm->bottom_radius_km, atm->top_radius_km, o->n_h, o->n_mu, h, mu, rep);
  for (int i = 0; status == SF_OK && i < o->n_h; ++i) {
    for (int j = 0; j < o->n_mu; ++j) {
      int p = i * o->n_mu + j;
      if (sf_optical_depth_ray(atm, h[p], mu[p], SF_RAY_END_TOP, &depth[(size_t)p * nc]) != 0)
        status = sf_fail(err, SF_ERR_INTERNAL, "sigmoid fit: to-top ray at h %g km mu %.17g hits the ground",
                         h[p], mu[p]);
    }
    if (o->progress) o->progress(o->progress_ctx, "reference optical depth", (double)(i + 1) / (2 * o->n_h));
  }
  for (int p = 0; status == SF_OK && p < n * nk; ++p) model_total[p] = ref_total[p] = 1.0;
  for (int c = 0; c < nc && status == SF_OK; ++c) {
    for (int k = 0; k < nk && status == SF_OK; ++k) {
      sf_sigmoid_fit_entry *en = &rep->entry[c][k];
      double *a = out->a[c][k];
      double ext = sf_extinction(atm, c, k);
      for (int p = 0; p < n; ++p) t[p] = exp(-ext * depth[(size_t)p * nc + c]);
      if (ext == 0.0) {
        en->transparent = 1;
        a[0] = SF_SIGMOID_TRANSPARENT_A1;
        a[1] = a[2] = a[3] = 0.0;
      } else {
        logit_start(n, h, mu, t, a);
        sf_lsq_problem *prob = sf_lsq_problem_new();
        if (!prob) {
          status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
          break;
        }
        sigmoid_points pts = {n, h, mu, t};
        int block = sf_lsq_add_block(prob, a, SF_SIGMOID_N_COEFFS);
        sf_lsq_add_residuals(prob, sigmoid_residuals, &pts, n, 1, &block, SF_LSQ_LOSS_NONE, 0.0);
        sf_lsq_summary sum;
        int rc = sf_lsq_solve(prob, &o->lsq, &sum);
        sf_lsq_problem_free(prob);
        if (rc != 0) {
          status = sf_fail(err, SF_ERR_INTERNAL, "sigmoid fit of %s channel %s failed: %s",
                           atm->constituents[c].name, atm->channel_names[k], sum.message);
          break;
        }
        en->start_cost = sum.initial_cost;
        en->final_cost = sum.final_cost;
        en->iterations = sum.iterations;
      }
      double sse = 0;
      for (int p = 0; p < n; ++p) {
        double m = sf_sigmoid_transmittance(a, h[p], mu[p]), d = m - t[p];
        sse += d * d;
        if (!(fabs(d) <= en->max_abs)) {
          en->max_abs = fabs(d);
          en->worst_h_km = h[p];
          en->worst_mu = mu[p];
        }
        model_total[(size_t)p * nk + k] *= m;
        ref_total[(size_t)p * nk + k] *= t[p];
      }
      en->rmse = sqrt(sse / n);
      if (o->progress) o->progress(o->progress_ctx, "sigmoid fits", (double)(c * nk + k + 1) / (nc * nk));
    }
  }
  if (status == SF_OK) {
    double sse = 0;
    for (int p = 0; p < n; ++p)
      for (int k = 0; k < nk; ++k)
        error_add(&rep->top, &sse, model_total[(size_t)p * nk + k] - ref_total[(size_t)p * nk + k], h[p],
                  mu[p], k);
    rep->top.rmse = sqrt(sse / rep->top.n_points);
  }
  /* full rays over the domain box, exact reference */
  double sse_full = 0, sse_ground = 0, sse_sky = 0;
  for (int i = 0; status == SF_OK && i < o->n_h; ++i) {
    double hh = h0 + (h1 - h0) * i / (o->n_h - 1);
    for (int j = 0; j < o->n_mu; ++j) {
      double mm = domain->mu_min + (domain->mu_max - domain->mu_min) * j / (o->n_mu - 1);
      full_ray_error(atm, out, hh, mm, rep, &sse_full, &sse_ground, &sse_sky);
    }
    if (o->progress) o->progress(o->progress_ctx, "full-ray error", (double)(i + 1) / o->n_h);
  }
  /* The horizon, where the model errs most, enters the maximum
   * (models/tangent_sweep.h): the box's rows and columns miss it. */
  horizon_job hj = {atm, out, rep};
  if (status == SF_OK)
    sf_tangent_sweep(atm->bottom_radius_km, 0.0, h0, h1, domain->mu_min, domain->mu_max, horizon_visit, &hj);
  if (status == SF_OK) {
    rep->full.rmse = sqrt(sse_full / rep->full.n_points);
    if (rep->full_ground.n_points) rep->full_ground.rmse = sqrt(sse_ground / rep->full_ground.n_points);
    if (rep->full_sky.n_points) rep->full_sky.rmse = sqrt(sse_sky / rep->full_sky.n_points);
    rep->rmse = rep->full.rmse;
    rep->max_abs = rep->full.max_abs;
    rep->worst_h_km = rep->full.worst_h_km;
    rep->worst_mu = rep->full.worst_mu;
    rep->worst_channel = rep->full.worst_channel;
  }
  free(h);
  free(mu);
  free(depth);
  free(t);
  free(model_total);
  free(ref_total);
  rep->seconds = sf_wall_seconds() - t0;
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}
