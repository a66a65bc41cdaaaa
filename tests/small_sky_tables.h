/* Reference tables small enough for a test, for the sky fits' tests: 2
 * orders; transmittance 64 mu x 16 h, scattering 12 h x 48 mu x 16 mu_s x
 * 8 nu, irradiance 16 mu_s x 4 h; and their sky-radiance view. Returns
 * SF_OK or the table set's error (err says why). */
#ifndef SKYFIT_TESTS_SMALL_SKY_TABLES_H
#define SKYFIT_TESTS_SMALL_SKY_TABLES_H

#include "data/sky_lookup.h"
#include "data/table_set.h"

static inline int small_sky_tables(const sf_atmosphere *atm, sf_table_set *set, sf_sky_tables *sky, sf_error *err) {
  sf_table_set_options to;
  sf_table_set_options_default(&to);
  to.orders = 2;
  to.res = (sf_table_resolution){64, 16, 12, 48, 16, 8, 16, 4};
  int status = sf_table_set_make(set, atm, &to, err);
  if (status == SF_OK) sf_sky_tables_of_set(sky, atm, set);
  return status;
}

#endif
