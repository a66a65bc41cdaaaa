/* Single-scattering tables (SPEC §6), Bruneton's convention: one table per
 * scattering constituent, named "single_<constituent>", holding per channel
 *   E_sun * beta_s * integral of density(p) T(viewer -> p) T(p -> sun) dt
 * along the entry's ray, without the phase function (applied at lookup).
 * The sun is a point; T(p -> sun) = 0 in the planet's shadow.
 *
 * Method: the view ray of each (h, mu) row is cut and graded once
 * (data/ray_quadrature.h: density kinks, closest approach, altitude and
 * extinction grading) and its SF_SCATTERING_NODES-point Gauss-Legendre
 * nodes, with T(viewer -> p) from the same density samples, are shared by
 * all (mu_s, nu) entries of the row. Per entry, the pieces that contain a
 * point where the sun ray grazes the ground (the shadow's edge) or a kink
 * sphere are integrated again in parts, the optical depth at the new nodes
 * coming from the piece's interpolating polynomial; so are significant
 * pieces over which the sun's optical depth changes a lot. T(p -> sun)
 * comes from the optical-depth grid (data/depth_grid.h). Measured against
 * the adaptive reference (models/single_scattering.h, 1e-7) at 2000 random
 * default-resolution entries of the default atmosphere: max relative error
 * 1.7e-4, mean 5e-7 (bench/bench_tables.c); bounds per atmosphere in
 * tests/test_tables.c. */
#ifndef SKYFIT_DATA_PRECOMPUTE_SINGLE_H
#define SKYFIT_DATA_PRECOMPUTE_SINGLE_H

#include "data/precompute_options.h"
#include "data/scattering_setup.h"
#include "data/table.h"
#include "data/table_params.h"
#include "util/error.h"

/* A piece of the view ray over which the sun's optical depth (in the most
 * opaque channel) changes by more than SF_SUN_SPLIT_TAU, and whose share of
 * the entry is at least SF_SUN_SPLIT_SIGNIFICANCE, is integrated again in up
 * to SF_SUN_SPLIT_MAX parts (at most SF_SUN_SPLIT_PIECES pieces per entry
 * wait for the significance test; further ones are refined at once). */
#define SF_SUN_SPLIT_TAU 6.0
#define SF_SUN_SPLIT_SIGNIFICANCE 1e-3
#define SF_SUN_SPLIT_MAX 32
#define SF_SUN_SPLIT_PIECES 8

/* "single_<name>" for scattering constituent c; SF_ERR_INPUT if the name
 * does not fit a table name (SF_TABLE_NAME_LEN, characters [A-Za-z0-9_.-]). */
int sf_single_table_name(const sf_constituent *c, char name[SF_TABLE_NAME_LEN], sf_error *err);

/* Single scattering of every scattering constituent along the view ray of
 * row (sf_view_row_fill) for the sun at (mu_s, nu): out[k * n_channels + ch]
 * for the k-th scattering constituent of s. nu is clamped to what mu and
 * mu_s allow. */
void sf_single_scattering_in_row(const sf_scattering_setup *s, const sf_view_row *row, double mu_s,
                                 double nu, double *out);

/* The same at one point (fills row, which is scratch space). */
void sf_single_scattering_point(const sf_scattering_setup *s, sf_view_row *row,
                                const sf_scattering_coord *c, double *out);

/* Fills tables[k] for the k-th scattering constituent of s; each must be
 * initialised with sf_params_scattering_desc(p, atm, <its name>, ...). */
int sf_precompute_single(const sf_scattering_setup *s, const sf_table_params *p,
                         const sf_precompute_options *opt, sf_table *tables, sf_error *err);

#endif
