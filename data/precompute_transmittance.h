/* The transmittance table (SPEC §6): per channel, exp(-sum of extinction x
 * optical depth) along the ray of each entry (data/table_params.h: to the
 * top for Bruneton, to the ground or the top for Leenman). Optical depths
 * come from the fixed graded Gauss-Legendre rule of data/ray_quadrature.h
 * with SF_TRANSMITTANCE_NODES points per piece, which agrees with the
 * adaptive reference (models/optical_depth.h) to ~1e-11 in transmittance on
 * the default atmosphere (tests/test_tables.c checks the float entries at
 * 1e-7). */
#ifndef SKYFIT_DATA_PRECOMPUTE_TRANSMITTANCE_H
#define SKYFIT_DATA_PRECOMPUTE_TRANSMITTANCE_H

#include "data/precompute_options.h"
#include "data/table.h"
#include "data/table_params.h"
#include "models/atmosphere.h"
#include "util/error.h"

#define SF_TRANSMITTANCE_NODES 10

/* Fills table, which must have been initialised (sf_table_init) with the
 * description sf_params_transmittance_desc(p, atm, ...). */
int sf_precompute_transmittance(const sf_atmosphere *atm, const sf_table_params *p,
                                const sf_precompute_options *opt, sf_table *table, sf_error *err);

/* One entry's ray: optical depth of every constituent along the ray from
 * altitude h along mu to the top (to_ground = 0) or to the ground
 * (to_ground = 1, the ray must hit it). */
void sf_transmittance_ray_depth(const sf_atmosphere *atm, double h, double mu, int to_ground,
                                double *depth);

#endif
