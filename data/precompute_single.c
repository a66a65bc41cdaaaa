#include "data/precompute_single.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/parallel_rows.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/sun_shadow.h"

int sf_single_table_name(const sf_constituent *c, char name[SF_TABLE_NAME_LEN], sf_error *err) {
  int n = snprintf(name, SF_TABLE_NAME_LEN, "single_%s", c->name);
  if (n < 0 || n >= SF_TABLE_NAME_LEN)
    return sf_fail(err, SF_ERR_INPUT,
                   "constituent '%s': its table name 'single_%s' is longer than %d characters",
                   c->name, c->name, SF_TABLE_NAME_LEN - 1);
  for (const char *p = c->name; *p; ++p)
    if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
          *p == '_' || *p == '-' || *p == '.'))
      return sf_fail(err, SF_ERR_INPUT,
                     "constituent '%s': a table is named after it, so its name may only use [A-Za-z0-9_.-]",
                     c->name);
  return SF_OK;
}

/* Adds the contributions of nodes whose view transmittance times weight
 * (wt, per channel), scattering densities and radius are given. */
typedef struct sun_sum {
  const sf_scattering_setup *s;
  sf_sun_line ground;         /* the sun lines against the ground (the shadow;
                                 its r_mu_s and nu give the sun's cosine) */
  double beta_max[SF_MAX_CONSTITUENTS];   /* largest extinction over channels */
} sun_sum;

/* Adds one node to sum; returns the sun's optical thickness at the node in
 * the most opaque channel (an upper bound), or -1 in the planet's shadow. */
static inline double add_node(const sun_sum *acc, double *sum, double t, double inv_radius,
                              const sf_depth_grid_radius *at, const double *wt, const double *density) {
  const sf_scattering_setup *s = acc->s;
  /* the planet's shadow, decided as the reference does (models/sun_shadow.h) */
  if (sf_sun_line_hidden(&acc->ground, t)) return -1.0;
  double mu_sun = (acc->ground.r_mu_s + t * acc->ground.nu) * inv_radius;
  mu_sun = mu_sun > 1.0 ? 1.0 : (mu_sun < -1.0 ? -1.0 : mu_sun);
  double sun[SF_MAX_CONSTITUENTS], transmittance[SF_MAX_CHANNELS];
  sf_depth_grid_lookup_at(&s->sun_depth, at, mu_sun, sun);
  sf_setup_transmittance(s, sun, transmittance);
  int nch = s->atm->n_channels, ns = s->n_scattering, nc = s->atm->n_constituents;
  for (int k = 0; k < ns; ++k) {
    double d = density[s->scattering[k]];
    double *row = sum + k * nch;
    for (int ch = 0; ch < nch; ++ch) row[ch] += wt[ch] * transmittance[ch] * d;
  }
  double tau = 0.0;
  for (int i = 0; i < nc; ++i) tau += acc->beta_max[i] * sun[i];
  return tau;
}

/* Piece p of the row cut at the points cuts[0..n-1] (inside it): each part
 * gets its own Gauss rule; the optical depth at the new nodes comes from the
 * piece's interpolating polynomial. */
static void add_cut_piece(const sun_sum *acc, double *sum, const sf_view_row *row, int p, const double *cuts,
                          int n, double *tau_lo, double *tau_hi) {
  const sf_scattering_setup *s = acc->s;
  const sf_atmosphere *atm = s->atm;
  const sf_gauss_rule *rule = &s->rule;
  int nc = atm->n_constituents, nch = atm->n_channels;
  double ends[2 * (SF_MAX_KINKS + 1) + SF_SUN_SPLIT_MAX + 2];
  int n_ends = 0;
  ends[n_ends++] = row->nodes.piece_start[p];
  for (int k = 0; k < n; ++k) ends[n_ends++] = cuts[k];
  ends[n_ends++] = row->nodes.piece_end[p];
  for (int e = 0; e + 1 < n_ends; ++e) {
    double u = ends[e], len = ends[e + 1] - u;
    if (!(len > 0.0)) continue;
    for (int q = 0; q < rule->n; ++q) {
      double t = u + len * rule->x[q];
      double radius = sf_ray_radius_at(row->r, row->mu, t);
      double h = radius - atm->bottom_radius_km;
      double density[SF_MAX_CONSTITUENTS], depth[SF_MAX_CONSTITUENTS], wt[SF_MAX_CHANNELS];
      for (int i = 0; i < nc; ++i) density[i] = sf_constituent_density(&atm->constituents[i], h);
      sf_ray_nodes_depth_at(&row->nodes, rule, p, t, depth);
      sf_setup_transmittance(s, depth, wt);
      for (int ch = 0; ch < nch; ++ch) wt[ch] *= len * rule->w[q];
      sf_depth_grid_radius at;
      sf_depth_grid_at_radius(&s->sun_depth, radius, &at);
      double tau = add_node(acc, sum, t, 1.0 / radius, &at, wt, density);
      if (tau >= 0.0) {
        *tau_lo = fmin(*tau_lo, tau);
        *tau_hi = fmax(*tau_hi, tau);
      }
    }
  }
}

/* Piece p integrated in parts over which the sun's optical depth changes by
 * about SF_SUN_SPLIT_TAU (variation: its change over the piece), merged with
 * the sun's cuts inside the piece (cuts[0..n-1]). */
static void add_split_piece(const sun_sum *acc, double *sum, const sf_view_row *row, int p, double variation,
                            const double *cuts, int n) {
  double a = row->nodes.piece_start[p], b = row->nodes.piece_end[p];
  /* capped before the conversion (a huge coefficient's variation overflowed int) */
  int parts = (int)fmin(ceil(variation / SF_SUN_SPLIT_TAU), (double)SF_SUN_SPLIT_MAX);
  double split[SF_SUN_SPLIT_MAX + 2 * (SF_MAX_KINKS + 1)];
  int n_split = 0, c = 0;
  for (int j = 1; j <= parts; ++j) {
    double t = j < parts ? a + (b - a) * j / parts : b;
    while (c < n && cuts[c] <= t) {
      if (n_split == 0 || cuts[c] > split[n_split - 1]) split[n_split++] = cuts[c];
      ++c;
    }
    if (j < parts && (n_split == 0 || t > split[n_split - 1])) split[n_split++] = t;
  }
  double lo = INFINITY, hi = 0.0;
  add_cut_piece(acc, sum, row, p, split, n_split, &lo, &hi);
}

void sf_single_scattering_in_row(const sf_scattering_setup *s, const sf_view_row *row, double mu_s,
                                 double nu, double *out) {
  const sf_atmosphere *atm = s->atm;
  int nch = atm->n_channels, nc = atm->n_constituents, ns = s->n_scattering;
  for (int k = 0; k < ns * nch; ++k) out[k] = 0.0;
  const sf_ray_nodes *nodes = &row->nodes;
  if (nodes->n == 0) return;
  nu = sf_clamp_nu(row->mu, mu_s, nu);
  sun_sum acc;
  acc.s = s;
  acc.ground = sf_sun_line_make(row->r, row->mu, mu_s, nu, atm->bottom_radius_km);
  for (int i = 0; i < nc; ++i) {
    acc.beta_max[i] = 0.0;
    for (int ch = 0; ch < nch; ++ch) acc.beta_max[i] = fmax(acc.beta_max[i], s->extinction[ch][i]);
  }
  double sum[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];   /* only ns * nch used: */
  for (int k = 0; k < ns * nch; ++k) sum[k] = 0.0;    /* no memset of the whole */

  /* The sun's cuts inside the ray, sorted (a handful: insertion sort). */
  double cuts[2 * (SF_MAX_KINKS + 1)];
  int n_all = sf_sun_tangent_points(atm, row->r, row->mu, mu_s, nu, cuts), n_cuts = 0;
  for (int k = 0; k < n_all; ++k) {
    double t = cuts[k];
    if (!(t > 0.0 && t < row->length)) continue;
    int j = n_cuts++;
    while (j > 0 && cuts[j - 1] > t) {
      cuts[j] = cuts[j - 1];
      --j;
    }
    cuts[j] = t;
  }

  int k_rule = s->rule.n, next_cut = 0, nv = ns * nch;
  double wt[SF_MAX_CHANNELS], piece_sum[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  /* Pieces over which the sun's optical depth changes a lot (its light
   * grazes the planet: sunset, thick air) are integrated again in parts,
   * but only those that matter: a second pass redoes a piece whose first
   * estimate is at least SF_SUN_SPLIT_SIGNIFICANCE of the entry's total. */
  int flagged[SF_SUN_SPLIT_PIECES], n_flagged = 0;
  double flagged_split[SF_SUN_SPLIT_PIECES];
  double flagged_sum[SF_SUN_SPLIT_PIECES][SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  int flagged_cut_first[SF_SUN_SPLIT_PIECES], flagged_cut_count[SF_SUN_SPLIT_PIECES];
  for (int p = 0; p < nodes->n_pieces; ++p) {
    double a = nodes->piece_start[p], b = nodes->piece_end[p];
    while (next_cut < n_cuts && cuts[next_cut] <= a) ++next_cut;
    int inside = 0;
    while (next_cut + inside < n_cuts && cuts[next_cut + inside] < b) ++inside;
    for (int k = 0; k < nv; ++k) piece_sum[k] = 0.0;
    double tau_lo = INFINITY, tau_hi = 0.0;
    if (inside > 0) {
      add_cut_piece(&acc, piece_sum, row, p, cuts + next_cut, inside, &tau_lo, &tau_hi);
    } else {
      for (int q = p * k_rule; q < (p + 1) * k_rule; ++q) {
        const double *tv = row->transmittance + (size_t)q * nch;
        for (int ch = 0; ch < nch; ++ch) wt[ch] = nodes->weight[q] * tv[ch];
        double tau = add_node(&acc, piece_sum, nodes->t[q], row->inv_radius[q],
                              &row->sun_at[q], wt, nodes->density + (size_t)q * nc);
        if (tau >= 0.0) {
          tau_lo = fmin(tau_lo, tau);
          tau_hi = fmax(tau_hi, tau);
        }
      }
    }
    if (tau_hi - tau_lo > SF_SUN_SPLIT_TAU && tau_lo < 60.0) {
      double variation = tau_hi - tau_lo;
      if (n_flagged < SF_SUN_SPLIT_PIECES) {
        flagged[n_flagged] = p;
        flagged_split[n_flagged] = variation;
        flagged_cut_first[n_flagged] = next_cut;
        flagged_cut_count[n_flagged] = inside;
        for (int k = 0; k < nv; ++k) flagged_sum[n_flagged][k] = piece_sum[k];
        ++n_flagged;
      } else {   /* no room to defer: refine now */
        for (int k = 0; k < nv; ++k) piece_sum[k] = 0.0;
        add_split_piece(&acc, piece_sum, row, p, variation, cuts + next_cut, inside);
      }
    }
    for (int k = 0; k < nv; ++k) sum[k] += piece_sum[k];
  }
  for (int f = 0; f < n_flagged; ++f) {
    double significance = 0.0;
    for (int k = 0; k < nv; ++k)
      if (sum[k] > 0.0) significance = fmax(significance, flagged_sum[f][k] / sum[k]);
    if (significance < SF_SUN_SPLIT_SIGNIFICANCE) continue;
    for (int k = 0; k < nv; ++k) piece_sum[k] = 0.0;
    add_split_piece(&acc, piece_sum, row, flagged[f], flagged_split[f], cuts + flagged_cut_first[f],
                    flagged_cut_count[f]);
    for (int k = 0; k < nv; ++k) sum[k] += piece_sum[k] - flagged_sum[f][k];
  }
  for (int k = 0; k < ns; ++k) {
    const sf_constituent *con = &atm->constituents[s->scattering[k]];
    for (int ch = 0; ch < nch; ++ch)
      out[k * nch + ch] = atm->sun_irradiance[ch] * con->scattering[ch] * sum[k * nch + ch];
  }
}

void sf_single_scattering_point(const sf_scattering_setup *s, sf_view_row *row,
                                const sf_scattering_coord *c, double *out) {
  sf_view_row_fill(row, s, c->h, c->mu, c->hits_ground);
  sf_single_scattering_in_row(s, row, c->mu_s, c->nu, out);
}

typedef struct single_job {
  const sf_scattering_setup *s;
  const sf_table_params *p;
  sf_table *tables;
  sf_view_row *scratch;   /* one per thread */
} single_job;

/* Row = one (h, mu) pair of the table; the row's entries are every mu_s, nu. */
static void single_row(void *ctx, int thread, long row) {
  const single_job *job = ctx;
  const sf_table_desc *d = &job->tables[0].desc;
  int nch = job->s->atm->n_channels, ns = job->s->n_scattering;
  int bruneton = job->p->kind == SF_PARAM_BRUNETON;
  /* Axis slots: Bruneton (mu_s, mu, nu, h), Leenman (h, mu, mu_s, nu). */
  int slot_h = bruneton ? 3 : 0, slot_mu = 1, slot_mu_s = bruneton ? 0 : 2, slot_nu = bruneton ? 2 : 3;
  int n_mu = d->axes[slot_mu].size;
  int i_h = (int)(row / n_mu), i_mu = (int)(row % n_mu);
  double values[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_view_row *view = &job->scratch[thread];
  int index0[4] = {0, 0, 0, 0};
  index0[slot_h] = i_h;
  index0[slot_mu] = i_mu;
  double pos0[4] = {index0[0], index0[1], index0[2], index0[3]};
  sf_scattering_coord c0;
  sf_params_scattering_coord(job->p, pos0, &c0);
  sf_view_row_fill(view, job->s, c0.h, c0.mu, c0.hits_ground);
  for (int i_s = 0; i_s < d->axes[slot_mu_s].size; ++i_s)
    for (int i_n = 0; i_n < d->axes[slot_nu].size; ++i_n) {
      int index[4];
      index[slot_h] = i_h;
      index[slot_mu] = i_mu;
      index[slot_mu_s] = i_s;
      index[slot_nu] = i_n;
      double pos[4] = {index[0], index[1], index[2], index[3]};
      sf_scattering_coord c;
      sf_params_scattering_coord(job->p, pos, &c);
      sf_single_scattering_in_row(job->s, view, c.mu_s, c.nu, values);
      for (int k = 0; k < ns; ++k) {
        float *out = sf_table_at(&job->tables[k], index);
        for (int ch = 0; ch < nch; ++ch) out[ch] = (float)values[k * nch + ch];
      }
    }
}

int sf_precompute_single(const sf_scattering_setup *s, const sf_table_params *p,
                         const sf_precompute_options *opt, sf_table *tables, sf_error *err) {
  if (s->n_scattering == 0) return SF_OK;
  int threads = sf_parallel_threads(opt);
  sf_view_row *scratch = calloc((size_t)threads, sizeof *scratch);
  if (!scratch) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for single-scattering scratch space");
  int ok = 1;
  for (int t = 0; t < threads; ++t)
    if (sf_view_row_alloc(&scratch[t], s)) ok = 0;
  if (ok) {
    single_job job = {s, p, tables, scratch};
    const sf_table_desc *d = &tables[0].desc;
    int slot_h = p->kind == SF_PARAM_BRUNETON ? 3 : 0;
    long rows = (long)d->axes[slot_h].size * d->axes[1].size;
    sf_parallel_rows(rows, opt, "single scattering", single_row, &job);
  }
  for (int t = 0; t < threads; ++t) sf_view_row_free(&scratch[t]);
  free(scratch);
  return ok ? SF_OK : sf_fail(err, SF_ERR_INTERNAL, "out of memory for single-scattering scratch space");
}
