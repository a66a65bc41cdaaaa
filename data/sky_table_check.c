#include "data/sky_table_check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/parallel_rows.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

enum { CHECK_ROW = 64 };

typedef struct check_job {
  const sf_sky_tables *sky;
  const double *inputs;
  size_t n;
  double *table, *direct, *multiple;   /* [i * nch + ch] */
  unsigned char *inside;               /* the point's ray meets the atmosphere */
} check_job;

/* The direct single-scattering sky radiance of one point, phases applied,
 * as the tables' lookup takes the viewer (a viewer above the top sees from
 * where its ray enters). Returns 0 when the ray never enters. */
static int direct_single(const sf_atmosphere *atm, double h, double mu, double mu_s, double nu, double *out) {
  double nu_c = sf_clamp_nu(mu, mu_s, nu);
  sf_view_ray ray;
  double mu_s_entry;
  const char *why;
  if (sf_view_ray_make_at_entry(atm, h, mu, mu_s, nu_c, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_entry, &why) ||
      !(ray.t1 > ray.t0))
    return 0;
  double all[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_single_scattering(atm, &ray, mu_s_entry, nu_c, all);
  int nch = atm->n_channels;
  for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    if (!sf_constituent_scatters(c, nch)) continue;
    double phase = sf_phase_value(&c->phase, nu_c);
    for (int ch = 0; ch < nch; ++ch) out[ch] += phase * all[i * nch + ch];
  }
  return 1;
}

static void check_row(void *ctx, int thread, long row) {
  (void)thread;
  const check_job *j = ctx;
  const sf_atmosphere *atm = j->sky->atm;
  int nch = atm->n_channels;
  size_t begin = (size_t)row * CHECK_ROW, end = begin + CHECK_ROW < j->n ? begin + CHECK_ROW : j->n;
  for (size_t i = begin; i < end; ++i) {
    const double *p = j->inputs + 4 * i;
    double *direct = j->direct + i * (size_t)nch;
    j->inside[i] = (unsigned char)direct_single(atm, p[0], p[1], p[2], p[3], direct);
    sf_sky_sample s;
    sf_sky_lookup(j->sky, p[0], p[1], p[2], p[3], &s);
    for (int ch = 0; ch < nch; ++ch) {
      j->table[i * (size_t)nch + ch] = s.radiance[ch] - s.multiple[ch];
      j->multiple[i * (size_t)nch + ch] = s.multiple[ch];
    }
  }
}

int sf_sky_table_check_points(const sf_sky_tables *sky, const double *inputs, size_t n,
                              const sf_precompute_options *run, sf_sky_table_check *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  static const double edges[SF_SKY_CHECK_BANDS + 1] = {INFINITY, 0.1, 0.0, -0.1, -INFINITY};
  for (int b = 0; b < SF_SKY_CHECK_BANDS; ++b) {
    out->band[b].mu_s_max = edges[b];
    out->band[b].mu_s_min = edges[b + 1];
  }
  int nch = sky->atm->n_channels;
  size_t nv = n * (size_t)nch;
  size_t nv1 = nv ? nv : 1;   /* malloc(0) may give NULL */
  check_job job = {sky, inputs, n, malloc(sizeof(double) * nv1), malloc(sizeof(double) * nv1),
                   malloc(sizeof(double) * nv1), malloc(n ? n : 1)};
  if (!job.table || !job.direct || !job.multiple || !job.inside) {
    free(job.table); free(job.direct); free(job.multiple); free(job.inside);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the reference check (%zu points)", n);
  }
  sf_precompute_options quiet = {0};
  if (run) quiet.n_threads = run->n_threads;
  sf_parallel_rows((long)((n + CHECK_ROW - 1) / CHECK_ROW), &quiet, NULL, check_row, &job);
  /* the sums in point order: the same bits on any number of threads */
  double sq = 0.0, ref_sq = 0.0, ms_sq = 0.0, sky_sq = 0.0;
  double band_sq[SF_SKY_CHECK_BANDS] = {0}, band_ref_sq[SF_SKY_CHECK_BANDS] = {0};
  for (size_t i = 0; i < n; ++i) {
    if (!job.inside[i]) {
      out->n_outside += 1;
      continue;
    }
    const double *p = inputs + 4 * i;
    int b = 0;
    while (b + 1 < SF_SKY_CHECK_BANDS && !(p[2] >= out->band[b].mu_s_min)) ++b;
    out->band[b].n_points += 1;
    out->n_points += 1;
    for (int ch = 0; ch < nch; ++ch) {
      size_t k = i * (size_t)nch + ch;
      double e = job.table[k] - job.direct[k], all = job.table[k] + job.multiple[k];
      sq += e * e;
      ref_sq += job.direct[k] * job.direct[k];
      band_sq[b] += e * e;
      band_ref_sq[b] += job.direct[k] * job.direct[k];
      ms_sq += job.multiple[k] * job.multiple[k];
      sky_sq += all * all;
      if (!(fabs(e) <= out->max_abs)) {
        out->max_abs = fabs(e);
        out->worst_h_km = p[0];
        out->worst_mu = p[1];
        out->worst_mu_s = p[2];
        out->worst_nu = sf_clamp_nu(p[1], p[2], p[3]);
        out->worst_channel = ch;
        snprintf(out->worst_channel_name, sizeof out->worst_channel_name, "%s", sky->atm->channel_names[ch]);
        out->worst_table = job.table[k];
        out->worst_direct = job.direct[k];
      }
    }
  }
  if (out->n_points > 0) {
    double count = (double)out->n_points * nch;
    out->present = 1;
    out->rmse = sqrt(sq / count);
    out->rel_rmse = ref_sq > 0.0 ? sqrt(sq / ref_sq) : NAN;
    out->multiple_share = sky_sq > 0.0 ? sqrt(ms_sq / sky_sq) : 0.0;
    for (int b = 0; b < SF_SKY_CHECK_BANDS; ++b)
      out->band[b].rel_rmse = band_ref_sq[b] > 0.0 ? sqrt(band_sq[b] / band_ref_sq[b]) : NAN;
  }
  free(job.table); free(job.direct); free(job.multiple); free(job.inside);
  return SF_OK;
}
