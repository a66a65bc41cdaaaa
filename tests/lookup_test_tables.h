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
#include "models/atmosphere_file.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "tests/check.h"
#include "tests/exact_single_radiance.h"
#include "util/constants.h"

/* *a: the default atmosphere; kind: the tables' parameterisation; res in
 * --resolution's syntax ("256x64,32x128x16x8"); orders: the highest order
 * (1: single scattering alone; the multiple table then holds orders
 * 2..orders). 0 on success, else 1 with the reason on stderr. */
static inline int lookup_test_tables_of(sf_parameterization kind, const char *res, int orders, sf_atmosphere *a,
                                        sf_table_set *set, sf_sky_tables *sky) {
  sf_atmosphere_default(a);
  sf_atmosphere_finalize(a);
  sf_table_set_options o;
  sf_table_set_options_default(&o);
  sf_error err = {0};
  o.kind = kind;
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

/* lookup_test_tables_of in Bruneton's parameterisation (the default). */
static inline int lookup_test_tables(const char *res, int orders, sf_atmosphere *a, sf_table_set *set,
                                     sf_sky_tables *sky) {
  return lookup_test_tables_of(SF_PARAM_BRUNETON, res, orders, a, set, sky);
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

/* The cosines of a view given in degrees: the sun's elevation, the view's
 * elevation and its azimuth from the sun. */
static inline void view_cosines(double sun_deg, double el_deg, double az_deg, double *mu, double *mu_s, double *nu) {
  double D = SF_PI / 180.0;
  *mu = sin(el_deg * D);
  *mu_s = sin(sun_deg * D);
  *nu = *mu * *mu_s + cos(el_deg * D) * cos(sun_deg * D) * cos(az_deg * D);
}

/* The lookup's single scattering against exact_single_radiance (relative
 * tolerance tol) in every channel, within rel_bound; prints each. */
static inline void check_single_lookup(const sf_sky_tables *sky, const sf_atmosphere *a, const char *name, double h,
                                       double mu, double mu_s, double nu, double tol, double rel_bound) {
  double want[SF_MAX_CHANNELS];
  exact_single_radiance(a, h, mu, mu_s, nu, tol, want);
  for (int ch = 0; ch < a->n_channels; ++ch) {
    double got = lookup_single_with_phase(sky, a, h, mu, mu_s, nu, ch), rel = got / want[ch] - 1.0;
    printf("%-50s ch %d table %.5g exact %.5g %+.3f%%\n", name, ch, got, want[ch], 100.0 * rel);
    check_report(want[ch] > 0.0 && fabs(rel) <= rel_bound, name, __FILE__, __LINE__);
  }
}

#endif
