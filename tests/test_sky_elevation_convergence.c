/* The fit across sun elevations (fit/fit_sky_elevation.h, step 3) runs to
 * Ceres' convergence where the former 200-iteration cap stopped it in the
 * geometric tail of a fit with a control point on its bound
 * (SF_SKY_ELEVATION_FIT_MAX_ITERATIONS): Hosek with the default options
 * (19 suns, 16 x 24 views) on small tables (2 orders). At 200 iterations
 * a channel stops with NO_CONVERGENCE (blue needs 283 here; red needed
 * 624 when step 3 fitted the fit suns alone); at the default cap every
 * channel converges, and the objective (1/2 sum over step 3's suns, views
 * and channels of the residual divided by the sun's RMS reference
 * radiance, step 1) is recomputed here from the fitted model's radiance, not from the
 * solver's Gram matrices: it must equal the reported one and be at or
 * below the capped fit's. The RMSE and held-out RMSE are printed, not
 * held: the objective weighs each sun by its RMS radiance and they do not,
 * so a lower objective may cost them a little (a scan of small-table
 * configurations found one with RMSE +0.1 %; on the default tables Hosek's
 * RMSE went 0.000974 -> 0.000965). */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/fit_sky_elevation.h"
#include "fit/sky_radiance_samples.h"
#include "models/atmosphere_file.h"
#include "small_sky_tables.h"

/* Step 3's objective of model m at its suns (the fit suns and two between
 * each pair), from the model's radiance: each sun's and channel's
 * residuals divided by the RMS reference radiance of its samples there. */
static double objective(const sf_sky_tables *sky, const sf_sky_elevation_options *o,
                        const sf_sky_elevation_report *rep, const sf_elevation_sky_model *m) {
  double cost = 0.0;
  for (int c = 0; c < rep->n_curve_elevations; ++c) {
    sf_sky_samples s;
    sf_error err = {0};
    double x;
    if (sf_sky_samples_from_tables(sky, sf_sky_curve_elevation(o, c, &x), o->n_theta, o->n_phi, &s, &err) != SF_OK)
      return NAN;
    const int nk = s.n_channels;
    for (int k = 0; k < nk; ++k) {
      double ss = 0.0, sr = 0.0;
      for (int i = 0; i < s.n; ++i) {
        double ref = s.radiance[(size_t)i * nk + k], model[SF_MAX_CHANNELS];
        sf_elevation_sky_radiance(m, s.elevation_rad, s.theta[i], s.gamma[i], model);
        ss += ref * ref;
        sr += (model[k] - ref) * (model[k] - ref);
      }
      cost += 0.5 * sr / (ss / s.n);
    }
    sf_sky_samples_free(&s);
  }
  return cost;
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

  sf_sky_elevation_options o, capped;
  sf_sky_elevation_options_default(&o, SF_SKY_FORM_HOSEK);
  capped = o;
  capped.elevation_fit_max_iterations = 200;
  CHECK(o.elevation_fit_max_iterations == SF_SKY_ELEVATION_FIT_MAX_ITERATIONS);
  CHECK(o.elevation_fit_max_iterations > capped.elevation_fit_max_iterations);

  sf_sky_elevation_report *rep = malloc(sizeof *rep), *rep_c = malloc(sizeof *rep_c);
  sf_elevation_sky_model *m = malloc(sizeof *m), *m_c = malloc(sizeof *m_c);
  CHECK(sf_fit_sky_elevation(&sky, &capped, ds, m_c, rep_c, &err) == SF_OK);
  CHECK(sf_fit_sky_elevation(&sky, &o, ds, m, rep, &err) == SF_OK);
  CHECK(rep->n_curve_elevations == 3 * rep->n_elevations - 2);

  int capped_stops = 0;
  for (int k = 0; k < rep->n_channels; ++k) {
    printf("channel %d: capped %s after %d iterations; default %s after %d\n", k,
           sf_lsq_termination_name(rep_c->global_termination_channel[k]), rep_c->global_iterations_channel[k],
           sf_lsq_termination_name(rep->global_termination_channel[k]), rep->global_iterations_channel[k]);
    capped_stops += rep_c->global_termination_channel[k] == SF_LSQ_NO_CONVERGENCE;
    CHECK(rep->global_termination_channel[k] == SF_LSQ_CONVERGENCE);
    CHECK(rep->global_iterations_channel[k] < o.elevation_fit_max_iterations);
  }
  /* the case is one the former cap stopped short */
  CHECK(capped_stops >= 1 && rep_c->global_channels_at_cap == capped_stops);
  CHECK(rep->global_channels_at_cap == 0 && rep->global_max_iterations == o.elevation_fit_max_iterations);

  double cost = objective(&sky, &o, rep, m), cost_c = objective(&sky, &capped, rep_c, m_c);
  printf("objective from the models: capped %.10g (reported %.10g), converged %.10g (reported %.10g)\n", cost_c,
         rep_c->global_final_cost, cost, rep->global_final_cost);
  printf("rmse: capped %.9g, converged %.9g; held out %.9g, %.9g; max %.6g, %.6g\n", rep_c->rmse, rep->rmse,
         rep_c->held_out_rmse, rep->held_out_rmse, rep_c->max_abs, rep->max_abs);
  CHECK_REL(cost, rep->global_final_cost, 1e-9);
  CHECK_REL(cost_c, rep_c->global_final_cost, 1e-9);
  CHECK(cost <= cost_c);

  sf_table_set_free(&set);
  free(atm);
  free(ds);
  free(rep);
  free(rep_c);
  free(m);
  free(m_c);
  return check_summary();
}
