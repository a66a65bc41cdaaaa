/* Single-scattering tables (SPEC §6), Bruneton's convention: one table per
 * scattering constituent, named "single_<constituent>", holding per channel
 *   E_sun * beta_s * integral of density(p) T(viewer -> p) T(p -> sun) dt
 * along the entry's ray, without the phase function (applied at lookup).
 * The sun is a point; T(p -> sun) = 0 in the planet's shadow.
 *
 * Method: the ray is cut at the density kinks, its closest approach, the
 * edge of the shadow and where the sun ray grazes a kink sphere, graded and
 * integrated with SF_SCATTERING_NODES-point Gauss-Legendre pieces
 * (data/ray_quadrature.h); T(viewer -> p) comes from the same density
 * samples (partial Gauss weights), T(p -> sun) from the optical-depth grid
 * (data/depth_grid.h). The error against the adaptive reference
 * (models/single_scattering.h) is printed by bench/bench_tables.c and
 * bounded in tests/test_tables.c. */
#ifndef SKYFIT_DATA_PRECOMPUTE_SINGLE_H
#define SKYFIT_DATA_PRECOMPUTE_SINGLE_H

#include "data/precompute_options.h"
#include "data/scattering_setup.h"
#include "data/table.h"
#include "data/table_params.h"
#include "util/error.h"

/* A piece of the view ray over which the sun's optical depth (in the most
 * opaque channel) changes by more than this is integrated again in parts. */
#define SF_SUN_SPLIT_TAU 6.0
#define SF_SUN_SPLIT_MAX 32

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
