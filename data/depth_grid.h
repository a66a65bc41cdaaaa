/* Optical depth to the top of the atmosphere, per constituent, over every
 * ray that does not hit the ground: a double-precision grid in Bruneton's
 * transmittance mapping (data/table_params.h) with cubic interpolation. The
 * scattering integrals need the sun's transmittance at every quadrature
 * node; this grid gives it in ~50 ns instead of a ray integral, and at a
 * resolution of its own, so the accuracy of the scattering tables does not
 * depend on the resolution of the stored transmittance table. Its error is
 * measured by tests/test_tables.c and bench/bench_tables.c. */
#ifndef SKYFIT_DATA_DEPTH_GRID_H
#define SKYFIT_DATA_DEPTH_GRID_H

#include "data/precompute_options.h"
#include "models/atmosphere.h"
#include "util/error.h"

#define SF_DEPTH_GRID_MU 384
#define SF_DEPTH_GRID_H 128

typedef struct sf_depth_grid {
  double bottom_radius_km, top_radius_km;
  double horizon_km;   /* sqrt(Rt^2 - R^2) */
  int n_mu, n_h, n_constituents;
  double *depth;   /* [(i_h * n_mu + i_mu) * n_constituents + i] */
} sf_depth_grid;

/* Computes the grid (sf_ray_quad_optical_depth at every sample). Returns 0,
 * or SF_ERR_INTERNAL when out of memory (grid then empty). */
int sf_depth_grid_build(sf_depth_grid *grid, const sf_atmosphere *atm, int n_mu, int n_h,
                        const sf_precompute_options *opt, sf_error *err);
void sf_depth_grid_free(sf_depth_grid *grid);

/* Optical depth of every constituent from radius r (<= top) along mu to the
 * top; mu at or above the horizon (a lower one is treated as the horizon). */
void sf_depth_grid_lookup(const sf_depth_grid *grid, double r, double mu, double *depth);

/* The same in two steps, for many directions from one radius: the part of
 * the lookup that depends on r only, then the direction. */
typedef struct sf_depth_grid_radius {
  double r, r2, inside;     /* r, r^2, Rt^2 - r^2 */
  double d_min, inv_span;   /* Bruneton's d_min and 1 / (d_max - d_min) */
  int i_h;                  /* first row of the cubic stencil ... */
  double w_h[4];            /* ... and its weights */
} sf_depth_grid_radius;
void sf_depth_grid_at_radius(const sf_depth_grid *grid, double r, sf_depth_grid_radius *at);
void sf_depth_grid_lookup_at(const sf_depth_grid *grid, const sf_depth_grid_radius *at, double mu,
                             double *depth);

#endif
