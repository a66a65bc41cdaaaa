/* How far the reference tables themselves are from the physics, where that
 * can be computed independently: their single scattering (the sum over the
 * scattering constituents of phase x table, data/sky_lookup.h, the part of
 * the reference sky radiance every fitted model is measured against) at
 * given points, against direct integration of the same quantity
 * (models/single_scattering.h, adaptive, double). The tables interpolate
 * over a grid that is coarse where the light changes fastest, at the
 * terminator: a user reading a model's error there needs to know how much
 * of it the reference shares. Multiple scattering has no such independent
 * reference short of the path tracer (tests/test_tables.c and
 * tests/test_sky_vs_path_tracer.c check it at chosen points); its share
 * of the sky is stated beside. */
#ifndef SKYFIT_DATA_SKY_TABLE_CHECK_H
#define SKYFIT_DATA_SKY_TABLE_CHECK_H

#include <stddef.h>

#include "data/precompute_options.h"
#include "data/sky_lookup.h"
#include "util/error.h"

/* Sun elevation bands of the check: above 5.7 deg (mu_s >= 0.1), 0..5.7,
 * 0..-5.7, below -5.7 deg. */
#define SF_SKY_CHECK_BANDS 4

typedef struct sf_sky_table_check_band {
  double mu_s_min, mu_s_max;   /* [min, max) */
  size_t n_points;
  double rel_rmse;             /* the band's RMSE over its own reference RMS (NAN
                                  where that is 0) */
} sf_sky_table_check_band;

typedef struct sf_sky_table_check {
  int present;
  size_t n_points;             /* points inside the atmosphere's reach */
  size_t n_outside;            /* the others: their rays never enter it */
  double rmse, rel_rmse;       /* every channel; rel_rmse = rmse / reference RMS
                                  (NAN where that is 0) */
  double max_abs;              /* and where: */
  double worst_h_km, worst_mu, worst_mu_s, worst_nu;
  int worst_channel;
  char worst_channel_name[16];
  double worst_table, worst_direct;
  double multiple_share;       /* RMS of the tables' multiple scattering over
                                  the RMS of their whole sky radiance */
  sf_sky_table_check_band band[SF_SKY_CHECK_BANDS];
} sf_sky_table_check;

/* The check at the n points inputs[4 i .. 4 i + 3] = (h_km, mu, mu_s, nu)
 * (fit/candidate_metrics.h's domain samples), on run->n_threads threads
 * (the result does not depend on them). Returns SF_OK, or SF_ERR_INTERNAL
 * when out of memory. */
int sf_sky_table_check_points(const sf_sky_tables *sky, const double *inputs, size_t n,
                              const sf_precompute_options *run, sf_sky_table_check *out, sf_error *err);

#endif
