/* Fits on the built-in atmosphere (SPEC §7.1, §7.2), on small tables:
 * - the refit Hosek model (Bezier over the sun range, default options)
 *   has an RMSE on the ground-level sky radiance of its metric grid at
 *   least 5x lower than the published Preetham model on the same samples
 *   (at its best turbidity and best per-channel scale); both printed; the
 *   RMSE recomputed independently, the stated maximum against a dense
 *   sweep reaching the horizon;
 * - the evaluated model file agrees with the report (the weights round
 *   trip through the SPEC §8 writer and the model loader);
 * - the sigmoid transmittance: its fit RMSE stated, and recomputed on a
 *   held-out grid (cell midpoints) against the exact optical depth; its
 *   stated maximum against a dense sweep through the horizon. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/fit_sigmoid.h"
#include "fit/fit_sky_elevation.h"
#include "models/atmosphere_file.h"
#include "models/hosek_bezier.h"
#include "models/optical_depth.h"
#include "models/rng.h"
#include "small_sky_tables.h"
#include "util/constants.h"

int main(void) {
  sf_error err = {0};
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_atmosphere_default(atm);

  printf("-- eq. 43 / tangent-split rules of models/sigmoid_transmittance.h with exact T_top\n");
  {
    /* The full-ray rules, fed the exact to-top transmittance instead of the
     * sigmoid, must give the exact full-ray transmittance (ground or top). */
    double R = atm->bottom_radius_km, worst = 0;
    const double hs[4] = {0.5, 3.0, 20.0, 80.0}, fr[5] = {-0.999, -0.5, -0.05, 0.02, 0.4};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 5; ++j) {
        double h = hs[i], r = R + h, mu_hor = -sqrt((r - R) * (r + R)) / r;
        double mu = fr[j] < 0 ? fr[j] * (fr[j] < -0.9 ? 1.0 : -mu_hor / 0.5) : mu_hor * (1 - fr[j]);
        if (mu < -1) mu = -1;
        double dep[SF_MAX_CONSTITUENTS], ref[SF_MAX_CHANNELS], a1[SF_MAX_CHANNELS], b1[SF_MAX_CHANNELS];
        sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, dep);
        sf_transmittance_from_depth(atm, dep, ref);
        double disc = (R - r) * (R + r) + (r * mu) * (r * mu), rule[SF_MAX_CHANNELS];
        sf_optical_depth_ray(atm, h, -mu, SF_RAY_END_TOP, dep);
        sf_transmittance_from_depth(atm, dep, b1);
        if (disc >= 0) {
          sf_optical_depth_ray(atm, 0.0, sqrt(disc) / R, SF_RAY_END_TOP, dep);
          sf_transmittance_from_depth(atm, dep, a1);
          for (int k = 0; k < 3; ++k) rule[k] = a1[k] / b1[k];
        } else {
          double h_t = -disc / (sqrt(r * r * (1 - mu) * (1 + mu)) + R);
          sf_optical_depth_ray(atm, h_t, 0.0, SF_RAY_END_TOP, dep);
          sf_transmittance_from_depth(atm, dep, a1);
          for (int k = 0; k < 3; ++k) rule[k] = a1[k] * a1[k] / b1[k];
        }
        for (int k = 0; k < 3; ++k) worst = worst_of(worst, fabs(rule[k] - ref[k]) / fmax(ref[k], 1e-300));
      }
    printf("rules with exact T_top vs exact full rays: max relative difference %.3g\n", worst);
    CHECK(worst < 1e-6);
  }

  printf("-- sigmoid transmittance over the built-in scene's domain\n");
  sf_scene *scene = malloc(sizeof *scene);
  sf_scene_default(scene);
  sf_scene_domain dom;
  CHECK(sf_scene_get_domain(scene, &dom, &err) == SF_OK);
  sf_sigmoid_fit_options so;
  sf_sigmoid_fit_options_default(&so);
  so.n_h = 24;
  so.n_mu = 48;
  sf_sigmoid_model *sm = malloc(sizeof *sm);
  sf_sigmoid_fit_report *srep = malloc(sizeof *srep);
  CHECK(sf_fit_sigmoid(atm, &dom, &so, sm, srep, &err) == SF_OK);
  printf("sigmoid: to-top rays (fitted) rmse %.4g, max %.4g at h %.3g km mu %.3g\n", srep->top.rmse,
         srep->top.max_abs, srep->top.worst_h_km, srep->top.worst_mu);
  printf("sigmoid: full rays rmse %.4g (ground %.4g, sky %.4g), max %.4g at h %.3g km mu %.3g\n", srep->rmse,
         srep->full_ground.rmse, srep->full_sky.rmse, srep->max_abs, srep->worst_h_km, srep->worst_mu);
  double thick = sf_atmosphere_thickness_km(atm), sse = 0;
  int n = 0;
  for (int i = 0; i < so.n_h - 1; ++i)
    for (int j = 0; j < so.n_mu - 1; ++j) {
      double h = dom.h_min_km + (fmin(dom.h_max_km, thick) - dom.h_min_km) * (i + 0.5) / (so.n_h - 1);
      double mu = dom.mu_min + (dom.mu_max - dom.mu_min) * (j + 0.5) / (so.n_mu - 1);
      double depth[SF_MAX_CONSTITUENTS], ref[SF_MAX_CHANNELS], mod[SF_MAX_CHANNELS];
      sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
      sf_transmittance_from_depth(atm, depth, ref);
      sf_sigmoid_model_eval(sm, h, mu, mod);
      for (int k = 0; k < 3; ++k, ++n) sse += (mod[k] - ref[k]) * (mod[k] - ref[k]);
    }
  double holdout = sqrt(sse / n);
  printf("sigmoid: full rays held-out rmse %.4g (fit report %.4g)\n", holdout, srep->rmse);
  CHECK_REL(holdout, srep->rmse, 0.5);
  {
    /* The stated maximum is what a renderer reads in the header: it must
     * not understate the worst error a dense sweep finds. Rows 10 m apart
     * through the lowest 2 km, where the horizon error peaks, then 0.5 km
     * apart; mu at the horizon cosine and 1e-7..1e-3 either side, and 2001
     * columns over the domain (a 96-column grid had stated 0.467 against
     * 0.655 here). */
    double dense_max = 0, dense_h = 0, dense_mu = 0;
    static const double offsets[] = {-1e-3, -1e-5, -1e-7, 0.0, 1e-7, 1e-5, 1e-3};
    for (double h = 0.0; h <= fmin(dom.h_max_km, thick); h += h < 2.0 ? 0.01 : 0.5) {
      double r = atm->bottom_radius_km + h, mu_h = -sqrt(fmax(0.0, 1.0 - (atm->bottom_radius_km / r) *
                                                                             (atm->bottom_radius_km / r)));
      for (int j = 0; j < 2001 + 7; ++j) {
        double mu = j < 2001 ? -1.0 + 2.0 * j / 2000 : mu_h + offsets[j - 2001];
        if (mu < dom.mu_min || mu > dom.mu_max) continue;
        double depth[SF_MAX_CONSTITUENTS], ref[SF_MAX_CHANNELS], mod[SF_MAX_CHANNELS];
        sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
        sf_transmittance_from_depth(atm, depth, ref);
        sf_sigmoid_model_eval(sm, h, mu, mod);
        for (int k = 0; k < 3; ++k)
          if (!(fabs(mod[k] - ref[k]) <= dense_max)) {
            dense_max = fabs(mod[k] - ref[k]);
            dense_h = h;
            dense_mu = mu;
          }
      }
    }
    printf("sigmoid: dense sweep max %.4g at h %.3g km mu %.6g (stated %.4g)\n", dense_max, dense_h, dense_mu,
           srep->max_abs);
    CHECK(srep->max_abs >= 0.98 * dense_max);
  }
  /* one sigmoid per constituent fitted to full rays (ground and top alike)
   * reached 0.15 here; fitted to what it models it must do far better */
  CHECK(srep->rmse < 0.06);
  CHECK(srep->top.rmse < 0.03);
  /* mie is smooth in (h, mu): its fit is far better */
  printf("sigmoid: mie rmse %.4g, rayleigh b rmse %.4g\n", srep->entry[1][0].rmse, srep->entry[0][2].rmse);
  CHECK(srep->entry[1][0].rmse < srep->entry[0][2].rmse);

  printf("-- sky fits on small tables (2 orders)\n");
  sf_table_set set;
  sf_sky_tables sky;
  CHECK(small_sky_tables(atm, &set, &sky, &err) == SF_OK);
  sf_hosek_dataset *ds = malloc(sizeof *ds);
  CHECK(sf_hosek_dataset_load_default(ds, &err) == SF_OK);
  sf_sky_elevation_report *rep = malloc(sizeof *rep);
  sf_elevation_sky_model *m = malloc(sizeof *m);
  sf_sky_elevation_options o;
  sf_sky_elevation_options_default(&o, SF_SKY_FORM_HOSEK);
  int rc = sf_fit_sky_elevation(&sky, &o, ds, m, rep, &err);
  CHECK(rc == SF_OK);
  if (rc) printf("%s\n", err.message);
  printf("hosek refit rmse %.4g (relative %.4g), published Preetham rmse %.4g (T = %g), published "
         "Hosek rmse %.4g (T = %g); ratio Preetham/refit %.2f; %.2f s\n",
         rep->rmse, rep->rel_rmse, rep->preetham_rmse, rep->preetham_turbidity,
         rep->hosek_published_rmse, rep->hosek_published_turbidity, rep->preetham_rmse / rep->rmse,
         rep->seconds);
  CHECK(5.0 * rep->rmse <= rep->preetham_rmse);
  /* independent recomputation of the refit's rmse from the tables: at the
   * fitted suns and halfway between them in x = (el / 90 deg)^(1/3) */
  double sse2 = 0, sse2_held = 0;
  long n2 = 0, n2_held = 0;
  CHECK(rep->n_metric_elevations == 2 * rep->n_elevations - 1);
  for (int e = 0; e < 2 * rep->n_elevations - 1; ++e)
    for (int i = 0; i < 4 * o.n_theta; ++i)
      for (int j = 0; j < o.n_phi; ++j) {
        double x = 0.5 * (sf_bezier_x_of_elevation(rep->elevation_rad[e / 2]) +
                          sf_bezier_x_of_elevation(rep->elevation_rad[(e + 1) / 2]));
        double el = e % 2 ? 0.5 * SF_PI * x * x * x : rep->elevation_rad[e / 2];
        double th = (i + 0.5) / (4 * o.n_theta) * 0.5 * SF_PI, ph = (double)j / (o.n_phi - 1) * SF_PI;
        double cg = cos(th) * sin(el) + sin(th) * cos(el) * cos(ph);
        cg = fmin(1, fmax(-1, cg));
        sf_sky_sample smp;
        sf_sky_lookup(&sky, 0, cos(th), sin(el), cg, &smp);
        double mod[SF_MAX_CHANNELS];
        sf_elevation_sky_radiance(m, el, th, acos(cg), mod);
        for (int k = 0; k < 3; ++k, ++n2) {
          double d2 = (mod[k] - smp.radiance[k]) * (mod[k] - smp.radiance[k]);
          sse2 += d2;
          if (e % 2) sse2_held += d2, ++n2_held;
        }
      }
  CHECK_REL(sqrt(sse2 / n2), rep->rmse, 1e-9);
  CHECK_REL(sqrt(sse2_held / n2_held), rep->held_out_rmse, 1e-9);
  {
    /* The stated RMSE against random suns over the fitted range, on the
     * same view grid: with 10 fit elevations and the metrics at those only,
     * the default build's Hosek fit had stated 0.00096 where random rays
     * found 0.0039 (its curves swung between the fitted suns). */
    sf_rng rng;
    sf_rng_seed(&rng, 7, 0x73756e73ULL, 0);
    double sse3 = 0;
    long n3 = 0;
    for (int e = 0; e < 200; ++e) {
      double el = 0.5 * SF_PI * sf_rng_uniform(&rng);
      for (int i = 0; i < 4 * o.n_theta; ++i)
        for (int j = 0; j < o.n_phi; ++j) {
          double th = (i + 0.5) / (4 * o.n_theta) * 0.5 * SF_PI, ph = (double)j / (o.n_phi - 1) * SF_PI;
          double cg = fmin(1, fmax(-1, cos(th) * sin(el) + sin(th) * cos(el) * cos(ph)));
          sf_sky_sample smp;
          sf_sky_lookup(&sky, 0, cos(th), sin(el), cg, &smp);
          double mod[SF_MAX_CHANNELS];
          sf_elevation_sky_radiance(m, el, th, acos(cg), mod);
          for (int k = 0; k < 3; ++k, ++n3) sse3 += (mod[k] - smp.radiance[k]) * (mod[k] - smp.radiance[k]);
        }
    }
    printf("hosek refit: stated rmse %.4g (held out %.4g), at 200 random suns %.4g\n", rep->rmse,
           rep->held_out_rmse, sqrt(sse3 / n3));
    CHECK(sqrt(sse3 / n3) <= 1.25 * rep->rmse);
  }
  {
    /* The stated maximum against a dense sweep of the domain's view
     * directions at the fitted suns: zenith angles every 0.5 deg, the
     * horizon band at mu 0.05 down to 0, azimuths every 2.5 deg. The fit's
     * own rows stop at 87.2 deg: the default build's Hosek fit had stated
     * 0.0079 on them where a sweep like this one finds 0.145. */
    static const double band[] = {0.05, 0.03, 0.02, 0.01, 0.005, 0.002, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 0.0};
    double dense = 0, dense_th = 0;
    for (int e = 0; e < rep->n_elevations; ++e)
      for (int i = 0; i < 180 + 12; ++i)
        for (int j = 0; j <= 72; ++j) {
          double el = rep->elevation_rad[e];
          double th = i < 180 ? (i + 0.25) / 180 * 0.5 * SF_PI : acos(band[i - 180]), ph = j * 2.5 * SF_PI / 180;
          double cg = fmin(1, fmax(-1, cos(th) * sin(el) + sin(th) * cos(el) * cos(ph)));
          sf_sky_sample smp;
          sf_sky_lookup(&sky, 0, cos(th), sin(el), cg, &smp);
          double mod[SF_MAX_CHANNELS];
          sf_elevation_sky_radiance(m, el, th, acos(cg), mod);
          for (int k = 0; k < 3; ++k)
            if (fabs(mod[k] - smp.radiance[k]) > dense) {
              dense = fabs(mod[k] - smp.radiance[k]);
              dense_th = th;
            }
        }
    printf("hosek refit: stated max %.4g at theta %.4f deg; dense sweep %.4g at theta %.4f deg\n", rep->max_abs,
           rep->worst_theta * 180 / SF_PI, dense, dense_th * 180 / SF_PI);
    CHECK(rep->max_abs >= 0.98 * dense);
  }

  {
    /* The fit across elevations says where it stopped at its cap: with 3
     * iterations allowed every channel does (the weights file's
     * training.elevation_fit_at_iteration_cap); the default fit's channels
     * at the cap are those whose iterations reached it. */
    int at_cap = 0;
    for (int k = 0; k < rep->n_channels; ++k) {
      CHECK(rep->global_at_cap_channel[k] == (rep->global_iterations_channel[k] >= o.elevation_fit_max_iterations));
      at_cap += rep->global_at_cap_channel[k];
    }
    CHECK(rep->global_channels_at_cap == at_cap && rep->global_max_iterations == o.elevation_fit_max_iterations);
    sf_sky_elevation_options capped = o;
    capped.elevation_fit_max_iterations = 3;
    sf_sky_elevation_report *rep3 = malloc(sizeof *rep3);
    sf_elevation_sky_model *m3 = malloc(sizeof *m3);
    CHECK(sf_fit_sky_elevation(&sky, &capped, ds, m3, rep3, &err) == SF_OK);
    printf("hosek refit: %d of %d channels at the %d-iteration cap; capped at 3: %d (iterations %d %d %d)\n", at_cap,
           rep->n_channels, o.elevation_fit_max_iterations, rep3->global_channels_at_cap, rep3->global_iterations_channel[0],
           rep3->global_iterations_channel[1], rep3->global_iterations_channel[2]);
    CHECK(rep3->global_channels_at_cap == rep3->n_channels && rep3->global_max_iterations == 3);
    free(rep3);
    free(m3);
  }

  sf_sky_elevation_options_default(&o, SF_SKY_FORM_PEREZ);
  o.n_elevations = 6;
  o.n_theta = 8;
  o.n_phi = 12;
  CHECK(sf_fit_sky_elevation(&sky, &o, ds, m, rep, &err) == SF_OK);
  printf("perez refit rmse %.4g (relative %.4g) vs published Preetham %.4g; %.2f s\n", rep->rmse,
         rep->rel_rmse, rep->preetham_rmse, rep->seconds);
  CHECK(rep->rmse < rep->preetham_rmse);
  sf_table_set_free(&set);
  free(atm);
  free(scene);
  free(sm);
  free(srep);
  free(ds);
  free(rep);
  free(m);
  return check_summary();
}
