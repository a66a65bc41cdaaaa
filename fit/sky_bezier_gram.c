#include "fit/sky_bezier_gram.h"

#include <string.h>

int sf_sky_bezier_gram_init(sf_sky_bezier_gram *g, sf_sky_form form, int n_elevations,
                            const sf_sky_fit_data *data,
                            const double (*bernstein)[SF_BEZIER_POINTS]) {
  memset(g, 0, sizeof *g);
  if (n_elevations < 1 || n_elevations > SF_SKY_BEZIER_MAX_ELEVATIONS) return -1;
  g->form = form;
  g->n_elevations = n_elevations;
  for (int e = 0; e < n_elevations; ++e) {
    memcpy(g->bernstein[e], bernstein[e], sizeof g->bernstein[e]);
    g->elevation[e] = sf_sky_fit_prepare(&data[e]);
    if (!g->elevation[e]) {
      sf_sky_bezier_gram_free(g);
      return -1;
    }
  }
  return 0;
}

void sf_sky_bezier_gram_free(sf_sky_bezier_gram *g) {
  for (int e = 0; e < g->n_elevations; ++e) sf_sky_fit_prepared_free(g->elevation[e]);
  memset(g, 0, sizeof *g);
}

/* The one-sky coefficients and scale at elevation e's Bernstein weights. */
static void elevation_state(const sf_sky_bezier_gram *g, int e, const double *P, const double *Q,
                            double *coeffs, double *scale) {
  const int nc = sf_sky_form_n_coeffs(g->form);
  const double *b = g->bernstein[e];
  *scale = 0.0;
  for (int i = 0; i < nc; ++i) coeffs[i] = 0.0;
  for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
    for (int i = 0; i < nc; ++i) coeffs[i] += b[j] * P[j * nc + i];
    *scale += b[j] * Q[j];
  }
}

void sf_sky_bezier_gram_eval(const sf_sky_bezier_gram *g, const double *P, const double *Q,
                             double *sum_squares, double *gram) {
  const int nc = sf_sky_form_n_coeffs(g->form), k1 = nc + 2;   /* one-sky Gram: c, s, r */
  const int p = SF_BEZIER_POINTS * (nc + 1), m = p + 1;
  /* global column a: Bernstein index j(a) (-1: the residual) and one-sky column k(a) */
  int bj[SF_SKY_BEZIER_MAX_PARAMS + 1], ok[SF_SKY_BEZIER_MAX_PARAMS + 1];
  for (int a = 0; a < m; ++a) {
    if (a < SF_BEZIER_POINTS * nc) {
      bj[a] = a / nc;
      ok[a] = a % nc;
    } else if (a < p) {
      bj[a] = a - SF_BEZIER_POINTS * nc;
      ok[a] = nc;
    } else {
      bj[a] = -1;
      ok[a] = nc + 1;
    }
  }
  if (gram) memset(gram, 0, sizeof(double) * (size_t)m * (size_t)m);
  double total = 0.0;
  for (int e = 0; e < g->n_elevations; ++e) {
    double coeffs[SF_HOSEK_N_COEFFS], scale, ss;
    double one[(SF_HOSEK_N_COEFFS + 2) * (SF_HOSEK_N_COEFFS + 2)];
    elevation_state(g, e, P, Q, coeffs, &scale);
    sf_sky_fit_prepared_gram(g->elevation[e], coeffs, scale, &ss, gram ? one : NULL);
    total += ss;
    if (!gram) continue;
    const double *b = g->bernstein[e];
    for (int a = 0; a < m; ++a) {
      const double ua = bj[a] < 0 ? 1.0 : b[bj[a]];
      for (int c = a; c < m; ++c) {
        const double uc = bj[c] < 0 ? 1.0 : b[bj[c]];
        gram[a * m + c] += (ua * uc) * one[ok[a] * k1 + ok[c]];
      }
    }
  }
  if (gram)
    for (int a = 0; a < m; ++a)
      for (int c = 0; c < a; ++c) gram[a * m + c] = gram[c * m + a];
  *sum_squares = total;
}
