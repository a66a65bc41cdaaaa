#include "data/precompute_multiple.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/density_mu.h"
#include "data/gauss_rule.h"
#include "data/parallel_rows.h"
#include "data/precompute_transmittance.h"
#include "data/table_interp.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "util/constants.h"
#include "util/target_clones.h"

#define N_DIRS_MU (SF_DENSITY_DIRS_UP + SF_DENSITY_DIRS_DOWN)
#define N_HALF_PHI (SF_DENSITY_DIRS_PHI / 2)
#define N_DIRS (N_DIRS_MU * N_HALF_PHI)

void sf_multiple_internal_params(const sf_table_params *p, sf_table_params *internal) {
  *internal = *p;
  internal->kind = SF_PARAM_BRUNETON;
  /* down to the output's lowest sun where that is below cos 102 deg: a
   * night scene's suns (-18 deg) had been read at the grid's edge, the sky
   * no darker at -18 deg than at -12 */
  internal->mu_s_min = fmin(SF_BRUNETON_MU_S_MIN, p->mu_s_min);
  /* the full domain: light reaches a restricted output's entries from
   * every altitude, direction and sun angle */
  internal->h_min_km = 0.0;
  internal->h_max_km = p->top_radius_km - p->bottom_radius_km;
  internal->mu_min = -1.0;
  internal->mu_s_max = 1.0;
  internal->sky_only = 0;
  internal->restricted = 0;
  if (internal->res.scattering_mu % 2) internal->res.scattering_mu += 1;
  if (internal->res.scattering_mu < 4) internal->res.scattering_mu = 4;
}

/* Directions of step 1 at one altitude: mu split at the horizon. */
typedef struct direction_set {
  double mu[N_DIRS_MU], weight[N_DIRS_MU];   /* weight includes 2 pi / n_phi */
  double dist_ground[SF_DENSITY_DIRS_DOWN];  /* to the ground, km */
  double *t_ground;                          /* [d * n_channels + ch] */
  double *opacity;                           /* [d * n_channels + ch]: 1 - T to the ray's end */
} direction_set;

typedef struct thread_scratch {
  sf_view_row row;
  double *node_coef;     /* [q * ns * nch + k * nch + ch] */
  double *node_pos;      /* [q * 8]: lookup corners in (mu, h) of node q */
  double *incoming;      /* [N_DIRS * nch] */
} thread_scratch;

typedef struct multiple_run {
  const sf_scattering_setup *s;
  const sf_atmosphere *atm;
  sf_table_params pi;              /* internal grid */
  int nch, ns;
  int n_mus, n_mu, n_nu, n_h;      /* internal sizes */
  int order;                       /* being computed: k */
  sf_grid_view single[SF_MAX_CONSTITUENTS];
  sf_grid_view previous;           /* L_{k-1} for k >= 3 */
  float *previous_data, *current_data;
  float *g_data, *g_sum_data;      /* [entry * ns * nch] */
  sf_grid_view g_view;             /* of g (step 3) or g_sum (final gather) */
  double *l_sum;                   /* [entry * nch] */
  double *ground_prev, *ground_new;   /* E_{k-2}, E_{k-1} at the ground samples */
  double *irradiance_sum;          /* [irradiance entry * nch] */
  direction_set *dirs;             /* one per internal altitude */
  double *opacity;                 /* [(i_h * n_mu + i_mu) * nch + ch]: 1 - T along the grid's rays */
  sf_gauss_rule irradiance_rule;   /* mu over the upper hemisphere */
  thread_scratch *scratch;
  /* gather target */
  const sf_table_params *target_p;
  float *target;                   /* [entry * nch] in the target's layout */
  double *row_total;               /* [row * nch + ch]: sum of the target row's values */
  double *row_single;              /* [row * nch + ch]: sum of single scattering with phases */
} multiple_run;

/* ---- lookups ------------------------------------------------------------ */

/* The lower sample of a position on an axis of n >= 2 samples, as
 * sf_grid_corners takes it. */
static int lower_sample(double pos, int n) {
  if (!(pos > 0.0)) pos = 0.0;
  if (pos > n - 1) pos = n - 1;
  int i = (int)pos;
  return i > n - 2 ? n - 2 : i;
}

/* Radiance of order j (1 or the previous order) along direction (mu, nu) at
 * internal position (pos_mu_s, pos_h); opacity: the direction's own 1 - T
 * per channel (NULL: the plain interpolation). */
static void radiance_of_order(const multiple_run *m, int j, double pos_mu_s, double h, double mu,
                              int hits_ground, double nu, double pos_h, const double *opacity,
                              double *out) {
  sf_scattering_coord c = {h, mu, 0.0, nu, hits_ground};
  double pos[4];
  sf_params_scattering_pos(&m->pi, &c, pos);
  pos[0] = pos_mu_s;
  pos[3] = pos_h;
  int nch = m->nch;
  for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
  long offsets[16];
  double weights[16];
  sf_grid_corners(j >= 2 ? &m->previous : &m->single[0], pos, offsets, weights);
  int lo_mu = lower_sample(pos[1], m->n_mu), lo_h = lower_sample(pos[3], m->n_h);
  double phase[SF_MAX_CONSTITUENTS];
  for (int k = 0; j < 2 && k < m->ns; ++k)
    phase[k] = sf_phase_value(&m->atm->constituents[m->s->scattering[k]].phase, nu);
  for (int c4 = 0; c4 < 16; ++c4) {
    if (weights[c4] == 0.0) continue;
    /* L = J (1 - T) for a source J uniform along the ray: interpolating
     * L / (1 - T) and multiplying by the direction's own 1 - T is exact
     * there, where L itself, saturating in the ray's length, is concave in
     * the grid's distance coordinate and its linear interpolation is low */
    double scale[SF_MAX_CHANNELS];
    long o = offsets[c4];
    /* the corner's mu and h samples: bits 1 and 3 of c4 (sf_grid_corners) */
    const double *oc = m->opacity + ((size_t)(lo_h + ((c4 >> 3) & 1)) * m->n_mu + lo_mu + ((c4 >> 1) & 1)) * nch;
    for (int ch = 0; ch < nch; ++ch)
      scale[ch] = opacity && oc[ch] > 1e-6 && opacity[ch] > 1e-6 ? weights[c4] * opacity[ch] / oc[ch] : weights[c4];
    if (j >= 2) {
      const float *v = m->previous.data + o * nch;
      for (int ch = 0; ch < nch; ++ch) out[ch] += scale[ch] * v[ch];
      continue;
    }
    for (int k = 0; k < m->ns; ++k) {
      const float *v = m->single[k].data + o * nch;
      for (int ch = 0; ch < nch; ++ch) out[ch] += scale[ch] * phase[k] * v[ch];
    }
  }
}

/* Irradiance on the ground of order k-2 for a ground point whose sun cosine
 * is mu_s: the sun's direct irradiance for k = 2, else the ground samples. */
static void ground_irradiance(const multiple_run *m, double mu_s, double *out) {
  int nch = m->nch;
  if (m->order == 2) {
    double depth[SF_MAX_CONSTITUENTS];
    if (mu_s <= 0.0 || !sf_sun_depth(m->s, m->atm->bottom_radius_km, mu_s, depth)) {
      for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
      return;
    }
    sf_setup_transmittance(m->s, depth, out);
    for (int ch = 0; ch < nch; ++ch) out[ch] *= m->atm->sun_irradiance[ch] * mu_s;
    return;
  }
  double pos = 0.5 * (mu_s + 1.0) * (SF_GROUND_IRRADIANCE_SAMPLES - 1);
  if (!(pos > 0.0)) pos = 0.0;
  if (pos > SF_GROUND_IRRADIANCE_SAMPLES - 1) pos = SF_GROUND_IRRADIANCE_SAMPLES - 1;
  int i = (int)pos;
  if (i > SF_GROUND_IRRADIANCE_SAMPLES - 2) i = SF_GROUND_IRRADIANCE_SAMPLES - 2;
  double f = pos - i;
  const double *a = m->ground_prev + (size_t)i * nch, *b = a + nch;
  for (int ch = 0; ch < nch; ++ch) out[ch] = (1.0 - f) * a[ch] + f * b[ch];
}

/* The phase functions of models/phase.h, inlined for the inner loop of
 * step 1 (the same formulas; the dispatch there is a function call). */
static inline double hg_fast(double g, double c) {
  double k = 1.0 + g * g - 2.0 * g * c;
  return (1.0 - g * g) / (4.0 * SF_PI * k * sqrt(k));
}

static inline double cs_fast(double g, double c) {
  double k = 1.0 + g * g - 2.0 * g * c;
  return 3.0 / (8.0 * SF_PI) * (1.0 - g * g) * (1.0 + c * c) / ((2.0 + g * g) * k * sqrt(k));
}

static inline double phase_fast(const sf_phase *p, double c) {
  switch (p->kind) {
    case SF_PHASE_HENYEY_GREENSTEIN: return hg_fast(p->g, c);
    case SF_PHASE_CORNETTE_SHANKS: return cs_fast(p->g, c);
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: return (1.0 - p->f) * hg_fast(p->g1, c) + p->f * hg_fast(p->g2, c);
    default: return sf_phase_value(p, c);
  }
}

/* ---- step 1: scattering density (phase-convolved incoming radiance) ------ */

/* wp[idx] = dw[idx] (p(cos1) + p(cos2)) for every direction, cos1 and cos2
 * the cosines to the view direction (ex, ey, ez) of the direction and its
 * mirror image y -> -y: the same operations as the scalar loop had, lane by
 * lane (exactly rounded sqrt and division, nothing fused), so the same bits,
 * computed apart from the sums so that they vectorise. */
#define PHASE_WEIGHT_LOOP(PHASE)                                            \
  for (int idx = 0; idx < n; ++idx) {                                       \
    double common = ex * dx[idx] + ez * dz[idx], side = ey * dy[idx];       \
    double cos1 = common + side, cos2 = common - side;                      \
    cos1 = cos1 > 1.0 ? 1.0 : (cos1 < -1.0 ? -1.0 : cos1);                  \
    cos2 = cos2 > 1.0 ? 1.0 : (cos2 < -1.0 ? -1.0 : cos2);                  \
    wp[idx] = dw[idx] * (PHASE(cos1) + PHASE(cos2));                        \
  }

SF_X86_CLONES
static void phase_weights(const sf_phase *p, int n, const double *restrict dx, const double *restrict dy,
                          const double *restrict dz, const double *restrict dw, double ex, double ey,
                          double ez, double *restrict wp) {
  double g = p->g, g1 = p->g1, g2 = p->g2, f = p->f;
  switch (p->kind) {
    case SF_PHASE_HENYEY_GREENSTEIN: {
#define PW_HG(c) hg_fast(g, c)
      PHASE_WEIGHT_LOOP(PW_HG)
#undef PW_HG
      return;
    }
    case SF_PHASE_CORNETTE_SHANKS: {
#define PW_CS(c) cs_fast(g, c)
      PHASE_WEIGHT_LOOP(PW_CS)
#undef PW_CS
      return;
    }
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
#define PW_DHG(c) ((1.0 - f) * hg_fast(g1, c) + f * hg_fast(g2, c))
      PHASE_WEIGHT_LOOP(PW_DHG)
#undef PW_DHG
      return;
    }
    default: {
#define PW_ANY(c) phase_fast(p, c)
      PHASE_WEIGHT_LOOP(PW_ANY)
#undef PW_ANY
      return;
    }
  }
}
#undef PHASE_WEIGHT_LOOP

static void density_row(void *ctx, int thread, long row) {
  multiple_run *m = ctx;
  const sf_atmosphere *atm = m->atm;
  int nch = m->nch, ns = m->ns;
  int i_h = (int)(row / m->n_mus), i_s = (int)(row % m->n_mus);
  double pos0[4] = {i_s, 0.0, 0.0, i_h};
  sf_scattering_coord c0;
  sf_params_scattering_coord(&m->pi, pos0, &c0);
  double h = c0.h, mu_s = c0.mu_s, r = atm->bottom_radius_km + h;
  double sin_s = sqrt(fmax(0.0, (1.0 - mu_s) * (1.0 + mu_s)));
  const direction_set *ds = &m->dirs[i_h];
  double *incoming = m->scratch[thread].incoming;
  double dx[N_DIRS], dy[N_DIRS], dz[N_DIRS], dw[N_DIRS];
  double albedo_pi[SF_MAX_CHANNELS];
  for (int ch = 0; ch < nch; ++ch) albedo_pi[ch] = atm->ground_albedo[ch] / SF_PI;

  for (int d = 0; d < N_DIRS_MU; ++d) {
    double mu = ds->mu[d], st = sqrt(fmax(0.0, (1.0 - mu) * (1.0 + mu)));
    int ground = d >= SF_DENSITY_DIRS_UP;
    for (int a = 0; a < N_HALF_PHI; ++a) {
      int idx = d * N_HALF_PHI + a;
      double phi = (a + 0.5) * (2.0 * SF_PI / SF_DENSITY_DIRS_PHI);
      dx[idx] = st * cos(phi);
      dy[idx] = st * sin(phi);
      dz[idx] = mu;
      dw[idx] = ds->weight[d];
      double nu = dx[idx] * sin_s + mu * mu_s;
      double *in = incoming + (size_t)idx * nch;
      radiance_of_order(m, m->order - 1, i_s, h, mu, ground, nu, i_h, ds->opacity + (size_t)d * nch, in);
      if (ground) {
        int g = d - SF_DENSITY_DIRS_UP;
        double dist = ds->dist_ground[g];
        double mu_s_ground = (r * mu_s + dist * nu) / atm->bottom_radius_km;
        mu_s_ground = mu_s_ground > 1.0 ? 1.0 : (mu_s_ground < -1.0 ? -1.0 : mu_s_ground);
        double e[SF_MAX_CHANNELS];
        ground_irradiance(m, mu_s_ground, e);
        const double *t = ds->t_ground + (size_t)g * nch;
        for (int ch = 0; ch < nch; ++ch) in[ch] += t[ch] * albedo_pi[ch] * e[ch];
      }
    }
  }

  /* Rayleigh and isotropic phase functions are polynomials of degree <= 2
   * in cos = w . w_i, so their sums over the directions reduce to the
   * zeroth and second moments of the incoming radiance (and, for the
   * normalisation, of the quadrature weights): the same numbers as the
   * direct sum, at a cost independent of the number of directions. The
   * field is symmetric under y -> -y, so the xy and yz moments vanish. */
  double m_l[5][SF_MAX_CHANNELS], m_w[5] = {0};   /* 1, xx, yy, zz, xz */
  for (int ch = 0; ch < nch; ++ch) m_l[0][ch] = m_l[1][ch] = m_l[2][ch] = m_l[3][ch] = m_l[4][ch] = 0.0;
  for (int idx = 0; idx < N_DIRS; ++idx) {
    /* both azimuths +-phi: the y terms double, the odd ones cancel */
    double w2 = 2.0 * dw[idx];
    double mono[5] = {w2, w2 * dx[idx] * dx[idx], w2 * dy[idx] * dy[idx], w2 * dz[idx] * dz[idx],
                      w2 * dx[idx] * dz[idx]};
    const double *in = incoming + (size_t)idx * nch;
    for (int j = 0; j < 5; ++j) {
      m_w[j] += mono[j];
      for (int ch = 0; ch < nch; ++ch) m_l[j][ch] += mono[j] * in[ch];
    }
  }
  int direct[SF_MAX_CONSTITUENTS], n_direct = 0, half = m->n_mu / 2;
  for (int k = 0; k < ns; ++k) {
    sf_phase_kind kind = atm->constituents[m->s->scattering[k]].phase.kind;
    if (kind != SF_PHASE_RAYLEIGH && kind != SF_PHASE_ISOTROPIC) direct[n_direct++] = k;
  }

  for (int i_mu = 0; i_mu < m->n_mu; ++i_mu)
    for (int i_n = 0; i_n < m->n_nu; ++i_n) {
      double pos[4] = {i_s, i_mu, i_n, i_h};
      sf_scattering_coord c;
      sf_params_scattering_coord(&m->pi, pos, &c);
      /* G's ground half is linear in mu (data/density_mu.h) */
      if (c.hits_ground)
        c.mu = sf_density_mu_ground_from_x(atm->bottom_radius_km, h, 1.0 - (double)i_mu / (half - 1));
      double nu = sf_clamp_nu(c.mu, mu_s, c.nu);
      double sin_v = sqrt(fmax(0.0, (1.0 - c.mu) * (1.0 + c.mu)));
      double cos_phi = sin_v * sin_s > 0.0 ? (nu - c.mu * mu_s) / (sin_v * sin_s) : 1.0;
      cos_phi = cos_phi > 1.0 ? 1.0 : (cos_phi < -1.0 ? -1.0 : cos_phi);
      double ex = sin_v * cos_phi, ey = sin_v * sqrt(fmax(0.0, 1.0 - cos_phi * cos_phi)), ez = c.mu;
      double acc[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS], norm[SF_MAX_CONSTITUENTS] = {0};
      for (int k = 0; k < ns * nch; ++k) acc[k] = 0.0;
      /* per constituent, the sums over the directions in the same order
       * as before (each sum on its own), held in registers */
      for (int j = 0; j < n_direct; ++j) {
        int k = direct[j];
        double wp[N_DIRS];
        phase_weights(&atm->constituents[m->s->scattering[k]].phase, N_DIRS, dx, dy, dz, dw, ex, ey, ez, wp);
        double *ak = acc + k * nch, nk = 0.0;
        if (nch == 3) {
          double a0 = 0.0, a1 = 0.0, a2 = 0.0;
          for (int idx = 0; idx < N_DIRS; ++idx) {
            const double *in = incoming + (size_t)idx * 3;
            nk += wp[idx];
            a0 += wp[idx] * in[0];
            a1 += wp[idx] * in[1];
            a2 += wp[idx] * in[2];
          }
          ak[0] = a0;
          ak[1] = a1;
          ak[2] = a2;
        } else {
          for (int idx = 0; idx < N_DIRS; ++idx) nk += wp[idx];
          for (int ch = 0; ch < nch; ++ch) {
            double a = 0.0;
            for (int idx = 0; idx < N_DIRS; ++idx) a += wp[idx] * incoming[(size_t)idx * nch + ch];
            ak[ch] = a;
          }
        }
        norm[k] = nk;
      }
      /* (w . w_i)^2 summed = ex^2 Mxx + ey^2 Myy + ez^2 Mzz + 2 ex ez Mxz */
      double quad[5] = {1.0, ex * ex, ey * ey, ez * ez, 2.0 * ex * ez};
      for (int k = 0; k < ns; ++k) {
        sf_phase_kind kind = atm->constituents[m->s->scattering[k]].phase.kind;
        if (kind != SF_PHASE_RAYLEIGH && kind != SF_PHASE_ISOTROPIC) continue;
        /* Rayleigh: 3/(16 pi) (1 + cos^2); isotropic: 1/(4 pi). The
         * constant factors cancel in the normalised ratio. */
        double second = kind == SF_PHASE_RAYLEIGH ? 1.0 : 0.0;
        double wsum = m_w[0];
        for (int j = 1; j < 5; ++j) wsum += second * quad[j] * m_w[j];
        norm[k] = wsum;
        for (int ch = 0; ch < nch; ++ch) {
          double v = m_l[0][ch];
          for (int j = 1; j < 5; ++j) v += second * quad[j] * m_l[j][ch];
          acc[k * nch + ch] = v;
        }
      }
      int index[4] = {i_s, i_mu, i_n, i_h};
      size_t entry = ((size_t)index[3] * m->n_nu + index[2]) * m->n_mu + index[1];
      entry = entry * m->n_mus + index[0];
      float *g = m->g_data + entry * (size_t)(ns * nch);
      for (int k = 0; k < ns; ++k)
        for (int ch = 0; ch < nch; ++ch)
          g[k * nch + ch] = norm[k] > 0.0 ? (float)(acc[k * nch + ch] / norm[k]) : 0.0f;
    }
}

/* ---- step 2: irradiance -------------------------------------------------- */

static void ray_opacity(const multiple_run *m, double h, double mu, int hits_ground, double *out);

/* Irradiance of order k-1 on a horizontal surface at altitude h for the
 * sun at mu_s. The sky rays' radiance is looked up normalised by their
 * opacity, as step 1's: the rays near the horizon are the long, saturated
 * ones whose linear interpolation falls low. */
static void irradiance_at(const multiple_run *m, double h, double mu_s, double *out) {
  int nch = m->nch;
  sf_scattering_coord c = {h, 1.0, mu_s, 0.0, 0};
  double pos[4];
  sf_params_scattering_pos(&m->pi, &c, pos);
  double sin_s = sqrt(fmax(0.0, (1.0 - mu_s) * (1.0 + mu_s)));
  const sf_gauss_rule *rule = &m->irradiance_rule;
  for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
  double dphi = 2.0 * SF_PI / SF_IRRADIANCE_DIRS_PHI;
  for (int q = 0; q < rule->n; ++q) {
    double mu = rule->x[q], st = sqrt(fmax(0.0, (1.0 - mu) * (1.0 + mu)));
    double opacity[SF_MAX_CHANNELS];
    ray_opacity(m, h, mu, 0, opacity);
    for (int a = 0; a < SF_IRRADIANCE_DIRS_PHI / 2; ++a) {
      double nu = st * cos((a + 0.5) * dphi) * sin_s + mu * mu_s;
      double l[SF_MAX_CHANNELS];
      radiance_of_order(m, m->order - 1, pos[0], h, mu, 0, nu, pos[3], opacity, l);
      /* both azimuths +-phi see the same radiance */
      double w = 2.0 * rule->w[q] * dphi * mu;
      for (int ch = 0; ch < nch; ++ch) out[ch] += w * l[ch];
    }
  }
}

static void ground_irradiance_row(void *ctx, int thread, long row) {
  (void)thread;
  multiple_run *m = ctx;
  double mu_s = -1.0 + 2.0 * (double)row / (SF_GROUND_IRRADIANCE_SAMPLES - 1);
  irradiance_at(m, 0.0, mu_s, m->ground_new + (size_t)row * m->nch);
}

static void irradiance_table_row(void *ctx, int thread, long row) {
  (void)thread;
  multiple_run *m = ctx;
  int n_mus = m->pi.res.irradiance_mu_s;
  for (int i = 0; i < n_mus; ++i) {
    double pos[2] = {i, (double)row}, h, mu_s, e[SF_MAX_CHANNELS];
    sf_params_irradiance_coord(&m->pi, pos, &h, &mu_s);
    irradiance_at(m, h, mu_s, e);
    double *sum = m->irradiance_sum + ((size_t)row * n_mus + i) * m->nch;
    for (int ch = 0; ch < m->nch; ++ch) sum[ch] += e[ch];
  }
}

/* ---- step 3: gather along view rays -------------------------------------- */

/* Bruneton's mu_s mapping (data/table_params.h) with its constants
 * precomputed: it runs at every node of every gathered entry. */
typedef struct mu_s_map {
  double R, H2, d_min, inv_span, inv_A;
  int n;
  int n_below;   /* intervals [j, j + 1] with the sun below the horizon at j + 1 */
} mu_s_map;

static mu_s_map make_mu_s_map(const multiple_run *m) {
  double R = m->atm->bottom_radius_km, Rt = m->atm->top_radius_km;
  mu_s_map f;
  f.R = R;
  f.H2 = (Rt - R) * (Rt + R);
  f.d_min = Rt - R;
  f.inv_span = 1.0 / (sqrt(f.H2) - f.d_min);
  double root = sqrt(f.H2 + R * R * m->pi.mu_s_min * m->pi.mu_s_min);
  double mu = m->pi.mu_s_min;
  double d = mu > 0.0 ? f.H2 / (R * mu + root) : root - R * mu;
  f.inv_A = 1.0 / ((d - f.d_min) * f.inv_span);
  f.n = m->n_mus;
  f.n_below = 0;
  for (int j = 1; j < f.n; ++j) {
    double pos[4] = {j, 0.0, 0.0, 0.0};
    sf_scattering_coord c;
    sf_params_scattering_coord(&m->pi, pos, &c);
    if (c.mu_s <= 0.0) f.n_below = j;
  }
  return f;
}

static inline double mu_s_position(const mu_s_map *f, double mu_s) {
  double root = sqrt(f->H2 + f->R * f->R * mu_s * mu_s);
  double d = mu_s > 0.0 ? f->H2 / (f->R * mu_s + root) : root - f->R * mu_s;
  double a = (d - f->d_min) * f->inv_span;
  double x = 1.0 - a * f->inv_A;
  x = x > 0.0 ? x / (1.0 + a) : 0.0;
  return (x > 1.0 ? 1.0 : x) * (f->n - 1);
}

/* Lower sample and fraction of a position on an axis of n >= 2 samples. */
static inline int split_position(double pos, int n, double *frac) {
  if (!(pos > 0.0)) pos = 0.0;
  if (pos > n - 1) pos = n - 1;
  int i = (int)pos;
  if (i > n - 2) i = n - 2;
  *frac = pos - i;
  return i;
}

/* One node's contribution to an entry of step 3: the lookup of G at the
 * node (8 corner pairs of the multilinear interpolation) times the node's
 * coefficients, added to l. Inlined with constant sizes for the usual
 * case; the same operations in the same order either way. */
static inline __attribute__((always_inline)) void gather_node(const double *corner, const double *coef,
                                                              const float *g, const long *nu_off,
                                                              const double *nu_w, int j_s, double f_s, int geometric, int nv,
                                                              int ns, int nch, double *l) {
  double v_lo[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS], v_hi[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  for (int k = 0; k < nv; ++k) v_lo[k] = v_hi[k] = 0.0;
  for (int a = 0; a < 4; ++a) {
    if (corner[4 + a] == 0.0) continue;
    for (int b = 0; b < 2; ++b) {
      double w = corner[4 + a] * nu_w[b];
      if (w == 0.0) continue;
      const float *lo = g + ((long)corner[a] + nu_off[b] + j_s) * nv, *hi = lo + nv;
      for (int k = 0; k < nv; ++k) {
        v_lo[k] += w * lo[k];
        v_hi[k] += w * hi[k];
      }
    }
  }
  /* Below the horizon (geometric): G falls exponentially with the sun's
   * depression, and linear interpolation between samples 1.2 deg apart
   * had overestimated every order's light in the planet's shadow (ground,
   * sun -5 deg: multiple scattering +4.8 %, 20 km, sun -8 deg: +19 %
   * against the path tracer). Linear above, where G is smooth (and pow
   * would cost). */
  for (int k = 0; k < ns; ++k)
    for (int ch = 0; ch < nch; ++ch) {
      double a = v_lo[k * nch + ch], b = v_hi[k * nch + ch];
      double v = geometric && a > 0.0 && b > 0.0 && f_s > 0.0 ? a * pow(b / a, f_s) : (1.0 - f_s) * a + f_s * b;
      l[ch] += coef[k * nch + ch] * v;
    }
}

static void gather_row(void *ctx, int thread, long row) {
  multiple_run *m = ctx;
  const sf_scattering_setup *s = m->s;
  const sf_atmosphere *atm = m->atm;
  const sf_table_params *tp = m->target_p;
  thread_scratch *sc = &m->scratch[thread];
  int nch = m->nch, ns = m->ns, nc = atm->n_constituents, nv = ns * nch;
  int bruneton = tp->kind == SF_PARAM_BRUNETON;
  int slot_h = bruneton ? 3 : 0, slot_mu = 1, slot_mu_s = bruneton ? 0 : 2, slot_nu = bruneton ? 2 : 3;
  int size[4];
  size[slot_h] = tp->res.scattering_h;
  size[slot_mu] = tp->res.scattering_mu;
  size[slot_mu_s] = tp->res.scattering_mu_s;
  size[slot_nu] = tp->res.scattering_nu;
  int i_h = (int)(row / size[slot_mu]), i_mu = (int)(row % size[slot_mu]);
  int index[4] = {0, 0, 0, 0};
  index[slot_h] = i_h;
  index[slot_mu] = i_mu;
  double pos0[4] = {index[0], index[1], index[2], index[3]};
  sf_scattering_coord c0;
  sf_params_scattering_coord(tp, pos0, &c0);
  sf_view_row *view = &sc->row;
  sf_view_row_fill(view, s, c0.h, c0.mu, c0.hits_ground);
  const sf_ray_nodes *nodes = &view->nodes;
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  /* internal grid strides, in samples: mu_s, mu, nu, h */
  long stride_mu = m->n_mus, stride_nu = stride_mu * m->n_mu, stride_h = stride_nu * m->n_nu;
  int half = m->pi.res.scattering_mu / 2;
  /* Per node, everything that does not depend on the sun: what it
   * contributes per unit of G (w T(viewer -> p) beta_s density), and the
   * corners of the lookup in mu and h (4 offsets and weights). */
  for (int q = 0; q < nodes->n; ++q) {
    double rp = nodes->radius[q], hp = rp - R;
    double mu_p = (view->r * view->mu + nodes->t[q]) * view->inv_radius[q];
    mu_p = mu_p > 1.0 ? 1.0 : (mu_p < -1.0 ? -1.0 : mu_p);
    double *coef = sc->node_coef + (size_t)q * nv;
    const double *tv = view->transmittance + (size_t)q * nch;
    for (int k = 0; k < ns; ++k) {
      const sf_constituent *con = &atm->constituents[s->scattering[k]];
      double rho = nodes->density[(size_t)q * nc + s->scattering[k]];
      for (int ch = 0; ch < nch; ++ch) coef[k * nch + ch] = nodes->weight[q] * tv[ch] * con->scattering[ch] * rho;
    }
    /* G's mu mapping: linear in mu on the ground half (data/density_mu.h) */
    double pm = c0.hits_ground ? (half - 1) * (1.0 - sf_density_x_from_mu_ground(R, hp, mu_p))
                               : half + (half - 1) * sf_bruneton_x_from_mu_top(R, Rt, hp, mu_p);
    double ph = sf_bruneton_x_from_h(R, Rt, hp) * (m->n_h - 1), f_mu, f_h;
    int j_mu = split_position(pm, m->n_mu, &f_mu), j_h = split_position(ph, m->n_h, &f_h);
    double *corner = sc->node_pos + (size_t)q * 8;   /* 4 offsets, 4 weights */
    for (int a = 0; a < 4; ++a) {
      int up_mu = a & 1, up_h = a >> 1;
      corner[a] = (double)((j_mu + up_mu) * stride_mu + (j_h + up_h) * stride_h);
      corner[4 + a] = (up_mu ? f_mu : 1.0 - f_mu) * (up_h ? f_h : 1.0 - f_h);
    }
  }
  mu_s_map map = make_mu_s_map(m);
  const float *g = m->g_view.data;
  double row_total[SF_MAX_CHANNELS] = {0}, row_single[SF_MAX_CHANNELS] = {0};
  for (int i_s = 0; i_s < size[slot_mu_s]; ++i_s)
    for (int i_n = 0; i_n < size[slot_nu]; ++i_n) {
      index[slot_mu_s] = i_s;
      index[slot_nu] = i_n;
      double pos[4] = {index[0], index[1], index[2], index[3]};
      sf_scattering_coord c;
      sf_params_scattering_coord(tp, pos, &c);
      double mu_s = c.mu_s, nu = sf_clamp_nu(c.mu, c.mu_s, c.nu);
      double f_nu;
      int j_nu = split_position(0.5 * (nu + 1.0) * (m->n_nu - 1), m->n_nu, &f_nu);
      long nu_off[2] = {j_nu * stride_nu, (j_nu + 1) * stride_nu};
      double nu_w[2] = {1.0 - f_nu, f_nu};
      double l[SF_MAX_CHANNELS];
      for (int ch = 0; ch < nch; ++ch) l[ch] = 0.0;
      for (int q = 0; q < nodes->n; ++q) {
        double mu_s_p = (view->r * mu_s + nodes->t[q] * nu) * view->inv_radius[q];
        mu_s_p = mu_s_p > 1.0 ? 1.0 : (mu_s_p < -1.0 ? -1.0 : mu_s_p);
        double f_s;
        int j_s = split_position(mu_s_position(&map, mu_s_p), m->n_mus, &f_s);
        const double *corner = sc->node_pos + (size_t)q * 8;
        const double *coef = sc->node_coef + (size_t)q * nv;
        if (nv == 6 && nch == 3)   /* two scattering constituents, RGB: unrolled */
          gather_node(corner, coef, g, nu_off, nu_w, j_s, f_s, j_s < map.n_below, 6, 2, 3, l);
        else
          gather_node(corner, coef, g, nu_off, nu_w, j_s, f_s, j_s < map.n_below, nv, ns, nch, l);
      }
      size_t off = 0;
      for (int k = 3; k >= 0; --k) off = off * (size_t)size[k] + (size_t)index[k];
      float *out = m->target + off * nch;
      for (int ch = 0; ch < nch; ++ch) {
        out[ch] = (float)l[ch];
        row_total[ch] += l[ch];
      }
      if (m->row_single) {
        /* the single-scattering sky radiance of the same entry, for the
         * stopping rule (the target is then the internal grid) */
        for (int k = 0; k < ns; ++k) {
          double phase = sf_phase_value(&atm->constituents[s->scattering[k]].phase, nu);
          const float *sv = m->single[k].data + off * nch;
          for (int ch = 0; ch < nch; ++ch) row_single[ch] += phase * sv[ch];
        }
      }
    }
  for (int ch = 0; ch < nch; ++ch) {
    m->row_total[row * nch + ch] = row_total[ch];
    if (m->row_single) m->row_single[row * nch + ch] = row_single[ch];
  }
}

/* ---- driver -------------------------------------------------------------- */

/* 1 - T along the ray from altitude h in direction mu to its end. */
static void ray_opacity(const multiple_run *m, double h, double mu, int hits_ground, double *out) {
  double depth[SF_MAX_CONSTITUENTS];
  sf_transmittance_ray_depth(m->atm, h, mu, hits_ground, depth);
  sf_setup_transmittance(m->s, depth, out);
  for (int ch = 0; ch < m->nch; ++ch) out[ch] = 1.0 - out[ch];
}

static int make_directions(multiple_run *m, sf_error *err) {
  const sf_atmosphere *atm = m->atm;
  /* above the horizon two Gauss panels (data/precompute_multiple.h): the
   * band just over the horizon, then the rest of the sky */
  sf_gauss_rule band, sky, down;
  sf_gauss_rule_init(&band, SF_DENSITY_DIRS_HORIZON);
  sf_gauss_rule_init(&sky, SF_DENSITY_DIRS_UP - SF_DENSITY_DIRS_HORIZON);
  sf_gauss_rule_init(&down, SF_DENSITY_DIRS_DOWN);
  m->dirs = calloc((size_t)m->n_h, sizeof *m->dirs);
  if (!m->dirs) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the scattering directions");
  double dphi = 2.0 * SF_PI / SF_DENSITY_DIRS_PHI;
  for (int i = 0; i < m->n_h; ++i) {
    direction_set *ds = &m->dirs[i];
    ds->t_ground = malloc(sizeof(double) * SF_DENSITY_DIRS_DOWN * (size_t)m->nch);
    ds->opacity = malloc(sizeof(double) * N_DIRS_MU * (size_t)m->nch);
    if (!ds->t_ground || !ds->opacity) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the scattering directions");
    double pos[4] = {0, 0, 0, i};
    sf_scattering_coord c;
    sf_params_scattering_coord(&m->pi, pos, &c);
    double r = atm->bottom_radius_km + c.h;
    double mu_h = sf_horizon_mu(r, atm->bottom_radius_km);
    double mu_band = mu_h + SF_DENSITY_HORIZON_BAND;   /* < 1: mu_h <= 0 */
    for (int q = 0; q < SF_DENSITY_DIRS_UP; ++q) {
      int in_band = q < SF_DENSITY_DIRS_HORIZON;
      double lo = in_band ? mu_h : mu_band, span = in_band ? mu_band - mu_h : 1.0 - mu_band;
      const sf_gauss_rule *rule = in_band ? &band : &sky;
      int k = in_band ? q : q - SF_DENSITY_DIRS_HORIZON;
      ds->mu[q] = lo + span * rule->x[k];
      ds->weight[q] = span * rule->w[k] * dphi;
      ray_opacity(m, c.h, ds->mu[q], 0, ds->opacity + (size_t)q * m->nch);
    }
    for (int q = 0; q < SF_DENSITY_DIRS_DOWN; ++q) {
      double mu = -1.0 + (mu_h + 1.0) * down.x[q];
      ds->mu[SF_DENSITY_DIRS_UP + q] = mu;
      ds->weight[SF_DENSITY_DIRS_UP + q] = (mu_h + 1.0) * down.w[q] * dphi;
      ds->dist_ground[q] = sf_ray_end_distance(atm, r, mu, 1);
      double depth[SF_MAX_CONSTITUENTS];
      sf_transmittance_ray_depth(atm, c.h, mu, 1, depth);
      sf_setup_transmittance(m->s, depth, ds->t_ground + (size_t)q * m->nch);
      for (int ch = 0; ch < m->nch; ++ch)
        ds->opacity[(size_t)(SF_DENSITY_DIRS_UP + q) * m->nch + ch] = 1.0 - ds->t_ground[(size_t)q * m->nch + ch];
    }
  }
  m->opacity = malloc(sizeof(double) * (size_t)m->n_h * m->n_mu * m->nch);
  if (!m->opacity) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the scattering directions");
  for (int i = 0; i < m->n_h; ++i)
    for (int k = 0; k < m->n_mu; ++k) {
      double pos[4] = {0, k, 0, i};
      sf_scattering_coord c;
      sf_params_scattering_coord(&m->pi, pos, &c);
      ray_opacity(m, c.h, c.mu, c.hits_ground, m->opacity + ((size_t)i * m->n_mu + k) * m->nch);
    }
  return SF_OK;
}

static void free_run(multiple_run *m, int threads) {
  if (m->dirs)
    for (int i = 0; i < m->n_h; ++i) {
      free(m->dirs[i].t_ground);
      free(m->dirs[i].opacity);
    }
  free(m->dirs);
  free(m->opacity);
  if (m->scratch)
    for (int t = 0; t < threads; ++t) {
      sf_view_row_free(&m->scratch[t].row);
      free(m->scratch[t].node_coef);
      free(m->scratch[t].node_pos);
      free(m->scratch[t].incoming);
    }
  free(m->scratch);
  free(m->previous_data);
  free(m->current_data);
  free(m->g_data);
  free(m->g_sum_data);
  free(m->l_sum);
  free(m->ground_prev);
  free(m->ground_new);
  free(m->irradiance_sum);
  free(m->row_total);
  free(m->row_single);
}

/* The orders after the last one computed, N, as a geometric series of
 * ratio r (per channel, L_N / L_{N-1} summed over the grid): L_N r / (1 -
 * r) added to the radiance, G_N r / (1 - r) to the summed G of a separate
 * output, and E_N / (1 - r) to the irradiance (which holds E_1..E_{N-1};
 * E_N is step 2 on L_N). Late orders converge to the scattering operator's
 * leading eigenfunction, whose eigenvalue r is; in an optically thick
 * atmosphere with little absorption r -> 1 and the orders past any cap
 * carry much of the light: 100 times as thick, no absorption, white
 * ground, coarse tables, the blue flux leaving the top was 0.74 of what
 * enters after 64 orders, 0.80 after 160, 0.85 with this tail
 * (tests/test_multiple_energy.c). Only where the orders shrink (r < 1).
 * -1: out of memory (the tables are then not to be used). */
static int add_geometric_tail(multiple_run *m, const double *ratio, int separate_output,
                              const sf_precompute_options *opt, size_t entries) {
  int nch = m->nch, any = 0;
  double f[SF_MAX_CHANNELS], g[SF_MAX_CHANNELS];
  for (int ch = 0; ch < nch; ++ch) {
    int shrinks = ratio[ch] > 0.0 && ratio[ch] < 1.0;
    f[ch] = shrinks ? ratio[ch] / (1.0 - ratio[ch]) : 0.0;
    g[ch] = shrinks ? 1.0 / (1.0 - ratio[ch]) : 0.0;
    any |= shrinks;
  }
  if (!any) return 0;
  for (size_t i = 0; i < entries * nch; ++i) m->l_sum[i] += f[i % nch] * m->previous_data[i];
  if (separate_output)
    for (size_t i = 0; i < entries * m->ns * nch; ++i) m->g_sum_data[i] += f[i % nch] * m->g_data[i];
  /* step 2 on L_N (previous_data): radiance_of_order reads order - 1 */
  size_t n_irr = (size_t)m->pi.res.irradiance_h * m->pi.res.irradiance_mu_s * nch;
  double *before = malloc(sizeof(double) * n_irr);
  if (!before) return -1;
  memcpy(before, m->irradiance_sum, sizeof(double) * n_irr);
  m->order += 1;
  sf_parallel_rows(m->pi.res.irradiance_h, opt, "multiple scattering: the orders' tail", irradiance_table_row, m);
  m->order -= 1;
  for (size_t i = 0; i < n_irr; ++i) m->irradiance_sum[i] = before[i] + g[i % nch] * (m->irradiance_sum[i] - before[i]);
  free(before);
  return 0;
}

static void run_gather(multiple_run *m, const sf_table_params *tp, float *target, const float *g,
                       const sf_precompute_options *opt, const char *stage) {
  m->target_p = tp;
  m->target = target;
  m->g_view.data = g;
  long rows = (long)tp->res.scattering_h * tp->res.scattering_mu;
  sf_parallel_rows(rows, opt, stage, gather_row, m);
}

int sf_precompute_multiple(const sf_scattering_setup *s, const sf_table_params *p,
                           const sf_table *single, const sf_multiple_options *mo,
                           const sf_precompute_options *opt, sf_table *multiple, sf_table *irradiance,
                           sf_multiple_report *report, sf_error *err) {
  multiple_run m;
  memset(&m, 0, sizeof m);
  sf_multiple_report local_report;
  if (!report) report = &local_report;
  memset(report, 0, sizeof *report);
  report->highest_order = 1;
  m.s = s;
  m.atm = s->atm;
  sf_multiple_internal_params(p, &m.pi);
  m.nch = s->atm->n_channels;
  m.ns = s->n_scattering;
  m.n_mus = m.pi.res.scattering_mu_s;
  m.n_mu = m.pi.res.scattering_mu;
  m.n_nu = m.pi.res.scattering_nu;
  m.n_h = m.pi.res.scattering_h;
  sf_gauss_rule_init(&m.irradiance_rule, SF_IRRADIANCE_DIRS_MU);
  int orders = mo->orders < 1 ? 1 : (mo->orders > SF_MULTIPLE_MAX_ORDERS ? SF_MULTIPLE_MAX_ORDERS : mo->orders);
  size_t n_out = sf_table_desc_points(&multiple->desc) * (size_t)m.nch;
  size_t n_irr = sf_table_desc_points(&irradiance->desc) * (size_t)m.nch;
  memset(multiple->data, 0, sizeof(float) * n_out);
  memset(irradiance->data, 0, sizeof(float) * n_irr);
  if (orders < 2 || m.ns == 0) return SF_OK;

  int threads = sf_parallel_threads(opt);
  size_t entries = (size_t)m.n_mus * m.n_mu * m.n_nu * m.n_h;
  /* an output other than the internal grid is gathered at the end from the
   * sum of the orders' G (step 3 is linear) */
  int separate_output = p->kind != SF_PARAM_BRUNETON || p->restricted;
  size_t rows_internal = (size_t)m.n_h * m.n_mu;
  m.previous_data = malloc(sizeof(float) * entries * m.nch);
  m.current_data = malloc(sizeof(float) * entries * m.nch);
  m.g_data = malloc(sizeof(float) * entries * m.ns * m.nch);
  m.g_sum_data = separate_output ? calloc(entries * m.ns * m.nch, sizeof(float)) : NULL;
  m.l_sum = calloc(entries * m.nch, sizeof(double));
  m.ground_prev = calloc((size_t)SF_GROUND_IRRADIANCE_SAMPLES * m.nch, sizeof(double));
  m.ground_new = calloc((size_t)SF_GROUND_IRRADIANCE_SAMPLES * m.nch, sizeof(double));
  m.irradiance_sum = calloc(n_irr, sizeof(double));
  m.row_total = calloc((rows_internal > (size_t)p->res.scattering_h * p->res.scattering_mu
                            ? rows_internal : (size_t)p->res.scattering_h * p->res.scattering_mu) * m.nch,
                       sizeof(double));
  m.row_single = calloc(rows_internal * m.nch, sizeof(double));
  m.scratch = calloc((size_t)threads, sizeof *m.scratch);
  int ok = m.previous_data && m.current_data && m.g_data && (!separate_output || m.g_sum_data) && m.l_sum &&
           m.ground_prev && m.ground_new && m.irradiance_sum && m.row_total && m.row_single && m.scratch;
  for (int t = 0; ok && t < threads; ++t) {
    thread_scratch *sc = &m.scratch[t];
    if (sf_view_row_alloc(&sc->row, s)) { ok = 0; break; }
    size_t cap = (size_t)sc->row.nodes.capacity;
    sc->node_coef = malloc(sizeof(double) * cap * m.ns * m.nch);
    sc->node_pos = malloc(sizeof(double) * cap * 8);
    sc->incoming = malloc(sizeof(double) * N_DIRS * m.nch);
    if (!sc->node_coef || !sc->node_pos || !sc->incoming) ok = 0;
  }
  if (!ok || make_directions(&m, err) != SF_OK) {
    free_run(&m, threads);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for multiple scattering (%zu table entries)", entries);
  }
  for (int k = 0; k < m.ns; ++k) m.single[k] = sf_grid_view_of(&single[k]);
  m.previous.data = m.previous_data;
  m.previous.n_values = m.nch;
  m.g_view.n_values = m.ns * m.nch;
  int sizes[4] = {m.n_mus, m.n_mu, m.n_nu, m.n_h};
  for (int a = 0; a < 4; ++a) m.previous.size[a] = m.g_view.size[a] = sizes[a];

  double sky_so_far[SF_MAX_CHANNELS] = {0}, previous_total[SF_MAX_CHANNELS] = {0};
  double ratio[SF_MAX_CHANNELS] = {0};   /* L_k / L_{k-1} summed over the grid, k the last order */
  double *row_single_buffer = m.row_single;
  char stage[96];
  for (int order = 2; order <= orders; ++order) {
    m.order = order;
    snprintf(stage, sizeof stage, "multiple scattering order %d: density", order);
    sf_parallel_rows((long)m.n_h * m.n_mus, opt, stage, density_row, &m);
    /* E_{k-1}: from the radiance of order k-1, like the density above. */
    snprintf(stage, sizeof stage, "multiple scattering order %d: irradiance", order);
    sf_parallel_rows(SF_GROUND_IRRADIANCE_SAMPLES, opt, stage, ground_irradiance_row, &m);
    /* the irradiance table sums orders 1..N-1, as Bruneton's */
    sf_parallel_rows(m.pi.res.irradiance_h, opt, stage, irradiance_table_row, &m);
    double e_total = 0.0;
    for (size_t i = 0; i < (size_t)SF_GROUND_IRRADIANCE_SAMPLES * m.nch; ++i) e_total += m.ground_new[i];
    report->ground_irradiance_total[order - 1] = e_total;
    double *swap = m.ground_prev;
    m.ground_prev = m.ground_new;
    m.ground_new = swap;

    snprintf(stage, sizeof stage, "multiple scattering order %d: gather", order);
    /* the single-scattering sky is summed once, with order 2 */
    m.row_single = order == 2 ? row_single_buffer : NULL;
    double *row_single = m.row_single;
    run_gather(&m, &m.pi, m.current_data, m.g_data, opt, stage);
    double total[SF_MAX_CHANNELS] = {0};
    for (size_t row = 0; row < rows_internal; ++row)
      for (int ch = 0; ch < m.nch; ++ch) {
        total[ch] += m.row_total[row * m.nch + ch];
        if (row_single) sky_so_far[ch] += row_single[row * m.nch + ch];
      }
    if (row_single)
      for (int ch = 0; ch < m.nch; ++ch) report->single_total += sky_so_far[ch];
    for (size_t i = 0; i < entries * m.nch; ++i) m.l_sum[i] += m.current_data[i];
    if (separate_output)
      for (size_t i = 0; i < entries * m.ns * m.nch; ++i) m.g_sum_data[i] += m.g_data[i];
    /* Per channel (the blue sky converges slowest: 4 orders had left it
     * 2-6 % short of the path tracer's, the sum over channels 1 %), what
     * this order added and what the orders left would add: the geometric
     * tail of the last two, L_k r / (1 - r) with r = L_k / L_{k-1} (about
     * 0.3 for Earth, so the tail is 0.43 L_k; 0.98 in a sky 120 times as
     * thick, where the last order's share said little of what was left). */
    report->order_total[order] = 0.0;
    report->added_fraction[order] = 0.0;
    report->remaining_fraction[order] = 0.0;
    for (int ch = 0; ch < m.nch; ++ch) {
      sky_so_far[ch] += total[ch];
      report->order_total[order] += total[ch];
      if (!(sky_so_far[ch] > 0.0) || total[ch] == 0.0) continue;
      double added = total[ch] / sky_so_far[ch];
      double r = order > 2 && previous_total[ch] > 0.0 ? total[ch] / previous_total[ch] : 1.0;
      ratio[ch] = order > 2 ? r : 0.0;
      double remaining = r < 1.0 ? added * r / (1.0 - r) : INFINITY;
      if (added > report->added_fraction[order]) report->added_fraction[order] = added;
      if (remaining > report->remaining_fraction[order]) report->remaining_fraction[order] = remaining;
      previous_total[ch] = total[ch];
    }
    report->highest_order = order;
    float *swap_f = m.previous_data;
    m.previous_data = m.current_data;
    m.current_data = swap_f;
    m.previous.data = m.previous_data;
    if (mo->stop_fraction > 0.0 && report->remaining_fraction[order] < mo->stop_fraction) break;
  }
  m.row_single = row_single_buffer;
  if (mo->stop_fraction > 0.0 && add_geometric_tail(&m, ratio, separate_output, opt, entries)) {
    free_run(&m, threads);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the multiple scattering's tail");
  }
  if (separate_output) {
    run_gather(&m, p, multiple->data, m.g_sum_data, opt, "multiple scattering: output");
  } else {
    for (size_t i = 0; i < entries * m.nch; ++i) multiple->data[i] = (float)m.l_sum[i];
  }
  for (size_t i = 0; i < n_irr; ++i) irradiance->data[i] = (float)m.irradiance_sum[i];
  free_run(&m, threads);
  return SF_OK;
}
