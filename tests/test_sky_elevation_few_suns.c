/* Hosek fitted across sun elevations at few suns (fit/fit_sky_elevation.h,
 * step 3) holds between the fit suns. Fitted at the 6 or 7 suns of the
 * small tables, Hosek's curves had been fitted to those suns alone and
 * swung between them: RMSE 3.5 and 0.58 on the 16 x 24 view grid, 6e6 on
 * 8 x 12, where the published Hosek errs 0.0042. The fit's own figures
 * are not trusted here: at suns a quarter, a half and three quarters of
 * the way (in x, the Bezier's variable) between the fit suns, none of them
 * fitted (step 3's are at the thirds), the model is evaluated against the
 * reference radiance of the tables, and its RMS error, per sun and channel
 * divided by the reference's RMS there, is compared with the best
 * isotropic sky's (the reference's mean: sqrt(1 - mean^2 / mean square) in
 * those units, a closed form): a fit must beat that trivial sky by far
 * everywhere in its range. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/fit_sky_elevation.h"
#include "fit/sky_radiance_samples.h"
#include "models/atmosphere_file.h"
#include "small_sky_tables.h"
#include "util/constants.h"

/* At sun elevation elev: the model's RMS error over the 16 x 24 view grid
 * and the channels, each channel divided by the reference's RMS there
 * (worst channel), and the best isotropic sky's in the same units. */
static int probe(const sf_sky_tables *sky, const sf_elevation_sky_model *m, double elev, double *model_err,
                 double *trivial_err) {
  sf_sky_samples s;
  sf_error err = {0};
  if (sf_sky_samples_from_tables(sky, elev, 16, 24, &s, &err) != SF_OK) return -1;
  const int nk = s.n_channels;
  *model_err = 0.0;
  *trivial_err = 0.0;
  for (int k = 0; k < nk; ++k) {
    double ss = 0.0, sum = 0.0, se = 0.0;
    for (int i = 0; i < s.n; ++i) {
      double ref = s.radiance[(size_t)i * nk + k], model[SF_MAX_CHANNELS];
      sf_elevation_sky_radiance(m, s.elevation_rad, s.theta[i], s.gamma[i], model);
      ss += ref * ref;
      sum += ref;
      se += (model[k] - ref) * (model[k] - ref);
    }
    double e = sqrt(se / ss), mean = sum / s.n, t = sqrt(1.0 - mean * mean / (ss / s.n));
    if (!(e <= *model_err)) *model_err = e;   /* NaN propagates */
    if (t > *trivial_err) *trivial_err = t;
  }
  sf_sky_samples_free(&s);
  return 0;
}

int main(void) {
  sf_error err = {0};
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_atmosphere_default(atm);
  sf_table_set set;
  sf_sky_tables sky;
  CHECK(small_sky_tables(atm, &set, &sky, &err) == SF_OK);
  sf_hosek_dataset *ds = malloc(sizeof *ds);
  CHECK(sf_hosek_dataset_load_default(ds, &err) == SF_OK);
  sf_sky_elevation_report *rep = malloc(sizeof *rep);
  sf_elevation_sky_model *m = malloc(sizeof *m);

  /* the configurations that swung: suns, view grid */
  static const int cases[][3] = {{6, 16, 24}, {7, 16, 24}, {6, 8, 12}};
  for (size_t q = 0; q < sizeof cases / sizeof cases[0]; ++q) {
    sf_sky_elevation_options o;
    sf_sky_elevation_options_default(&o, SF_SKY_FORM_HOSEK);
    o.n_elevations = cases[q][0];
    o.n_theta = cases[q][1];
    o.n_phi = cases[q][2];
    CHECK(sf_fit_sky_elevation(&sky, &o, ds, m, rep, &err) == SF_OK);
    CHECK(rep->n_curve_elevations == 3 * o.n_elevations - 2);
    double worst = 0.0, worst_ratio = 0.0, worst_elev = 0.0;
    for (int e = 0; e + 1 < o.n_elevations; ++e) {
      double x0, x1;
      sf_sky_fit_elevation(&o, e, &x0);
      sf_sky_fit_elevation(&o, e + 1, &x1);
      for (int f = 1; f <= 3; ++f) {
        double x = x0 + (x1 - x0) * f / 4.0, elev = 0.5 * SF_PI * x * x * x, me = NAN, te = NAN;
        CHECK(probe(&sky, m, elev, &me, &te) == 0);
        CHECK(te > 0.1);   /* the sky is far from isotropic: the comparison means something */
        if (!(me / te <= worst_ratio)) {
          worst_ratio = me / te;
          worst = me;
          worst_elev = elev;
        }
      }
    }
    printf("%d suns, %dx%d views: rmse %.4g (held out %.4g, published Hosek %.4g); between the suns worst "
           "normalised error %.4g at %.2f deg, %.4g of the isotropic sky's\n",
           o.n_elevations, o.n_theta, o.n_phi, rep->rmse, rep->held_out_rmse, rep->hosek_published_rmse, worst,
           worst_elev * 180 / SF_PI, worst_ratio);
    /* a fit: half the trivial sky's error at worst (0.11, 0.12 and 0.18
     * of it here; the curves fitted at the fit suns alone had 1.4e4, 621
     * and 3.5e9 times it) */
    CHECK(worst_ratio < 0.5);
    CHECK(rep->rmse < rep->hosek_published_rmse);
  }

  sf_table_set_free(&set);
  free(atm);
  free(ds);
  free(rep);
  free(m);
  return check_summary();
}
