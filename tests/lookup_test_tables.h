/* What the lookup tests share: the tables they compare against independent
 * references (the default atmosphere's, at a resolution of their own, up
 * to a given order with no stop rule, on 2 threads), and a lookup's single
 * scattering summed over the constituents with each one's phase, as the
 * exact quadrature (tests/exact_single_radiance.h) gives it. */
#ifndef SKYFIT_TESTS_LOOKUP_TEST_TABLES_H
#define SKYFIT_TESTS_LOOKUP_TEST_TABLES_H

#include <stdio.h>

#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/phase.h"
#include "models/single_scattering.h"

/* res in --resolution's syntax ("256x64,32x128x16x8"); orders: the highest
 * order (1: single scattering alone; the multiple table then holds orders
 * 2..orders). 0 on success, else 1 with the reason on stderr. */
static inline int lookup_test_tables(const sf_atmosphere *a, const char *res, int orders, sf_table_set *set,
                                     sf_sky_tables *sky) {
  sf_table_set_options o;
  sf_table_set_options_default(&o);
  sf_error err = {0};
  int status = sf_table_resolution_parse(res, &o.res, &err);
  if (status == 0) {
    o.orders = orders;
    o.stop_fraction = 0.0;
    o.run.n_threads = 2;
    status = sf_table_set_make(set, a, &o, &err);
  }
  if (status != 0) {
    fprintf(stderr, "tables %s: %s\n", res, err.message);
    return 1;
  }
  sf_sky_tables_of_set(sky, a, set);
  return 0;
}

/* The lookup's single scattering in channel ch, each constituent times its
 * phase at nu (clamped as the lookup clamps it). */
static inline double lookup_single_with_phase(const sf_sky_tables *sky, const sf_atmosphere *a, double h, double mu,
                                              double mu_s, double nu, int ch) {
  sf_sky_sample s;
  sf_sky_lookup(sky, h, mu, mu_s, nu, &s);
  nu = sf_clamp_nu(mu, mu_s, nu);
  double sum = 0.0;
  for (int k = 0; k < sky->n_single; ++k)
    sum += sf_phase_value(&a->constituents[sky->single_constituent[k]].phase, nu) * s.single[k][ch];
  return sum;
}

#endif
