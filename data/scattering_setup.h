/* What every scattering integral of the tables shares: the atmosphere, its
 * scattering constituents, the grid of optical depths to the top that gives
 * the sun's transmittance (data/depth_grid.h), and the quadrature rule along
 * rays (data/ray_quadrature.h). Built once per atmosphere, read-only after. */
#ifndef SKYFIT_DATA_SCATTERING_SETUP_H
#define SKYFIT_DATA_SCATTERING_SETUP_H

#include <math.h>

#include "data/depth_grid.h"
#include "data/ray_quadrature.h"
#include "data/gauss_rule.h"
#include "data/precompute_options.h"
#include "models/atmosphere.h"
#include "util/error.h"

#define SF_SCATTERING_NODES 6

typedef struct sf_scattering_setup {
  const sf_atmosphere *atm;      /* not owned; must outlive the setup */
  int n_scattering;              /* constituents that scatter ... */
  int scattering[SF_MAX_CONSTITUENTS];   /* ... and their indices */
  sf_depth_grid sun_depth;
  sf_gauss_rule rule;
  double extinction[SF_MAX_CHANNELS][SF_MAX_CONSTITUENTS];   /* beta_s + beta_a */
} sf_scattering_setup;

/* Returns 0, or SF_ERR_INTERNAL when out of memory (setup then empty). */
int sf_scattering_setup_init(sf_scattering_setup *s, const sf_atmosphere *atm,
                             const sf_precompute_options *opt, sf_error *err);
void sf_scattering_setup_free(sf_scattering_setup *s);

/* Optical depth of every constituent from radius r towards a sun at zenith
 * cosine mu_sun; returns 0 (depth untouched) when the planet hides the sun
 * (a point sun, as models/single_scattering.h: tangent rays are hidden). */
int sf_sun_depth(const sf_scattering_setup *s, double r, double mu_sun, double *depth);

/* Distance from radius r along mu to the ray's end: the ground if
 * hits_ground (a grazing ray: its tangent point), else the top (r <= top). */
double sf_ray_end_distance(const sf_atmosphere *atm, double r, double mu, int hits_ground);

/* Points along the view ray (r, mu) where the sun ray (mu_s, nu at the
 * viewer) is tangent to the ground or to a kink sphere in front of the
 * point: the edge of the planet's shadow and the corners of the sun's
 * optical depth. Writes at most 2 (1 + n_kinks) points to out (unsorted,
 * possibly outside the ray); returns their count. */
int sf_sun_tangent_points(const sf_atmosphere *atm, double r, double mu, double mu_s, double nu,
                          double *out);

/* Transmittance per channel for optical depths depth[constituent]. */
static inline void sf_setup_transmittance(const sf_scattering_setup *s, const double *depth,
                                          double *transmittance);

/* A view ray of the tables with everything about it that does not depend
 * on the sun: the quadrature nodes (data/ray_quadrature.h, without the
 * sun's cuts), and at each node the view transmittance and the radius part
 * of the sun's optical-depth lookup. Every (mu_s, nu) entry of a (h, mu)
 * row of a scattering table shares it. */
typedef struct sf_view_row {
  sf_ray_nodes nodes;
  double r, mu, length;
  int hits_ground;
  double *transmittance;            /* [node * n_channels + ch], viewer -> node */
  double *inv_radius;               /* 1 / radius of each node */
  sf_depth_grid_radius *sun_at;     /* per node */
} sf_view_row;

/* Returns 0, or -1 when out of memory (row then empty). */
int sf_view_row_alloc(sf_view_row *row, const sf_scattering_setup *s);
void sf_view_row_free(sf_view_row *row);
/* The ray from altitude h along mu to its end (the ground if hits_ground). */
void sf_view_row_fill(sf_view_row *row, const sf_scattering_setup *s, double h, double mu,
                      int hits_ground);

static inline void sf_setup_transmittance(const sf_scattering_setup *s, const double *depth,
                                          double *transmittance) {
  int nc = s->atm->n_constituents;
  for (int ch = 0; ch < s->atm->n_channels; ++ch) {
    double tau = 0.0;
    for (int i = 0; i < nc; ++i) tau += s->extinction[ch][i] * depth[i];
    transmittance[ch] = exp(-tau);
  }
}

#endif
