/* Neural-sky evaluation (models/mlp_sky.h) on networks with random weights
 * (the identities below hold for any network):
 *  - the segment to where the ray meets the ground equals the full ray
 *    (both eq. 43 with reversed rays);
 *  - segments compose: T(0->d1) T(d1->d2) = T(0->d2) and, eq. 44,
 *    S(0->d2) = S(0->d1) + T(0->d1) S(d1->d2), with the second segment
 *    evaluated from a viewer moved to d1 (independent geometry);
 *  - SPEC §10 hard cases in float32: no NaN/Inf, and float32 within a
 *    stated bound of double; saturated networks (weights x 40) too. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fit/train.h"
#include "models/atmosphere_file.h"
#include "models/mlp_sky.h"
#include "models/ray_geometry.h"
#include "models/rng.h"
#include "models/single_scattering.h"
#include "tests/check.h"

static void make_models(const sf_atmosphere *atm, double weight_scale, uint64_t seed, sf_mlp_sky *t, sf_mlp_sky *s) {
  sf_error err = {0};
  double top = atm->top_radius_km - atm->bottom_radius_km;
  double off[4] = {0.5 * sqrt(top), 0.0, 0.4, 0.0}, sc[4] = {2.0 / sqrt(top), 1.0, 1.0 / 0.6, 1.0};
  sf_mlp_shape st = {2, {2, 4, 3}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG};
  sf_mlp_shape ss = {3, {4, 8, 8, 9}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG};
  sf_mlp nt, ns;
  sf_mlp_init(&nt, &st);
  sf_mlp_init(&ns, &ss);
  sf_mlp_init_xavier(&st, seed, 0, nt.params);
  sf_mlp_init_xavier(&ss, seed, 1, ns.params);
  for (int k = 0; k < nt.n_params; ++k) nt.params[k] *= weight_scale;
  for (int k = 0; k < ns.n_params; ++k) ns.params[k] *= weight_scale;
  /* optical depth grows downwards: a positive bias keeps T < 1 mostly */
  nt.params[sf_mlp_bias_offset(&st, 1)] += 1.0;
  int constituents[2] = {0, 1};
  if (sf_mlp_sky_make(t, &nt, SF_MLP_TARGET_TRANSMITTANCE_TOP, atm, off, sc, 0, NULL, &err) ||
      sf_mlp_sky_make(s, &ns, SF_MLP_TARGET_SEPARATE, atm, off, sc, 2, constituents, &err))
    printf("make failed: %s\n", err.message);
}

static int all_finite_f(const float *v, int n) {
  for (int k = 0; k < n; ++k)
    if (!isfinite(v[k])) return 0;
  return 1;
}

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  sf_mlp_sky t, s;
  make_models(&atm, 1.0, 11, &t, &s);
  double R = atm.bottom_radius_km;
  sf_rng rng;
  sf_rng_seed(&rng, 5, 0, 0);

  /* 1. segment to the ground == full ray */
  double worst_ground = 0.0;
  for (int i = 0; i < 2000; ++i) {
    double h = 100.0 * sf_rng_uniform(&rng), r = R + h;
    double mu = sf_horizon_mu(r, R) - (1.0 + sf_horizon_mu(r, R)) * sf_rng_uniform(&rng);
    double tn, tf, full[3], seg[3];
    if (!sf_ray_sphere_intersections(r, mu, R, &tn, &tf)) continue;
    sf_mlp_transmittance(&t, h, mu, full);
    sf_mlp_transmittance_segment(&t, h, mu, tn, seg);
    for (int c = 0; c < 3; ++c) worst_ground = fmax(worst_ground, fabs(full[c] - seg[c]));
  }
  CHECK_ABS(worst_ground, 0.0, 1e-7);   /* r_d rounding at the ground point */

  /* 1b. nothing lies past the ground: a segment longer than the way to the
   * ground equals the segment to the ground (transmittance and eq. 44),
   * in double and in float32 */
  double worst_past = 0.0, worst_past_f = 0.0;
  for (int i = 0; i < 500; ++i) {
    double h = 20.0 * sf_rng_uniform(&rng), r = R + h;
    double mu = sf_horizon_mu(r, R) - (1.0 + sf_horizon_mu(r, R)) * sf_rng_uniform(&rng);
    double mu_s = 2.0 * sf_rng_uniform(&rng) - 1.0, nu = sf_clamp_nu(mu, mu_s, 2.0 * sf_rng_uniform(&rng) - 1.0);
    double tn, tf, at[3], past[3], sat[3], spast[3];
    if (!sf_ray_sphere_intersections(r, mu, R, &tn, &tf)) continue;
    double beyond = tn * (1.0 + 10.0 * sf_rng_uniform(&rng)) + 1.0;
    sf_mlp_transmittance_segment(&t, h, mu, tn, at);
    sf_mlp_transmittance_segment(&t, h, mu, beyond, past);
    sf_mlp_scattering_segment(&s, &t, h, mu, mu_s, nu, tn, sat);
    sf_mlp_scattering_segment(&s, &t, h, mu, mu_s, nu, beyond, spast);
    float atf[3], pastf[3];
    sf_mlp_transmittance_f(&t, (float)h, (float)mu, atf);   /* the full ray ends on the ground too */
    sf_mlp_transmittance_segment_f(&t, (float)h, (float)mu, (float)beyond, pastf);
    for (int c = 0; c < 3; ++c) {
      worst_past = fmax(worst_past, fmax(fabs(at[c] - past[c]), fabs(sat[c] - spast[c]) / fmax(sat[c], 1e-12)));
      worst_past_f = fmax(worst_past_f, fabs((double)atf[c] - (double)pastf[c]));
    }
  }
  CHECK_ABS(worst_past, 0.0, 1e-7);
  CHECK_ABS(worst_past_f, 0.0, 1e-4);

  /* 2. composition of segments (double), where no clamp acts */
  double worst_t = 0.0, worst_s = 0.0;
  int tested = 0;
  for (int i = 0; i < 4000; ++i) {
    double h = 100.0 * sf_rng_uniform(&rng) * sf_rng_uniform(&rng), r = R + h;
    double mu = 2.0 * sf_rng_uniform(&rng) - 1.0, mu_s = 2.0 * sf_rng_uniform(&rng) - 1.0;
    double nu = sf_clamp_nu(mu, mu_s, 2.0 * sf_rng_uniform(&rng) - 1.0);
    double t_enter, t_exit;
    int ground;
    if (!sf_ray_atmosphere_segment(r, mu, R, atm.top_radius_km, &t_enter, &t_exit, &ground)) continue;
    double d2 = t_exit * (0.2 + 0.8 * sf_rng_uniform(&rng)), d1 = d2 * sf_rng_uniform(&rng);
    double r1 = sf_ray_radius_at(r, mu, d1), mu1 = (r * mu + d1) / r1, mu_s1 = (r * mu_s + d1 * nu) / r1;
    double T01[3], T12[3], T02[3], S01[3], S12[3], S02[3];
    sf_mlp_transmittance_segment(&t, h, mu, d1, T01);
    sf_mlp_transmittance_segment(&t, r1 - R, mu1, d2 - d1, T12);
    sf_mlp_transmittance_segment(&t, h, mu, d2, T02);
    sf_mlp_scattering_segment(&s, &t, h, mu, mu_s, nu, d1, S01);
    sf_mlp_scattering_segment(&s, &t, r1 - R, mu1, mu_s1, nu, d2 - d1, S12);
    sf_mlp_scattering_segment(&s, &t, h, mu, mu_s, nu, d2, S02);
    if (r1 - R < 1e-6) continue;
    for (int c = 0; c < 3; ++c) {
      if (!(T01[c] < 1.0 && T12[c] < 1.0 && T02[c] < 1.0)) continue;
      ++tested;
      worst_t = fmax(worst_t, fabs(T01[c] * T12[c] - T02[c]));
      if (S01[c] > 0 && S12[c] > 0 && S02[c] > 0)
        worst_s = fmax(worst_s, fabs(S01[c] + T01[c] * S12[c] - S02[c]) / fmax(S02[c], 1e-12));
    }
  }
  printf("composition tested on %d segments\n", tested);
  CHECK(tested >= 200);
  CHECK_ABS(worst_t, 0.0, 1e-9);
  CHECK_ABS(worst_s, 0.0, 1e-9);

  /* 3. hard cases in float32, ordinary and saturated networks, thin and thick shells */
  static const double tops[3] = {100.0, 0.01, 1000.0};
  int finite = 1;
  double worst_f = 0.0;
  long cases = 0;
  for (int shell = 0; shell < 3; ++shell)
    for (int sat = 0; sat < 2; ++sat) {
      sf_atmosphere a = atm;
      a.top_radius_km = a.bottom_radius_km + tops[shell];
      sf_mlp_sky tt, ss;
      make_models(&a, sat ? 40.0 : 1.0, 21 + sat, &tt, &ss);
      double Rt = a.top_radius_km;
      double hs[] = {0.0, 1e-6, 0.5 * tops[shell], tops[shell], tops[shell] + 1e-6, tops[shell] + 1000.0, 36000.0};
      for (int ih = 0; ih < 7; ++ih) {
        double r = R + hs[ih];
        double hz = sf_horizon_mu(r, R), hz_top = r > Rt ? sf_horizon_mu(r, Rt) : -1.0;
        double mus[] = {-1.0, -0.5, 0.0, 1.0, hz, hz - 1e-6, hz + 1e-6, hz_top, hz_top + 1e-6, hz_top - 1e-6};
        double sun[] = {-1.0, -0.2, 0.0, 1.0};
        double nus[] = {-1.0, 0.0, 1.0};
        for (int im = 0; im < 10; ++im)
          for (int is = 0; is < 4; ++is)
            for (int in = 0; in < 3; ++in) {
              float Tf[3], Lf[3], Tsf[3], Lsf[3];
              double Td[3];
              float d = (float)(0.37 * tops[shell]);
              sf_mlp_transmittance_f(&tt, (float)hs[ih], (float)mus[im], Tf);
              sf_mlp_transmittance(&tt, hs[ih], mus[im], Td);
              sf_mlp_transmittance_segment_f(&tt, (float)hs[ih], (float)mus[im], d, Tsf);
              sf_mlp_scattering_f(&ss, (float)hs[ih], (float)mus[im], (float)sun[is], (float)nus[in], Lf);
              sf_mlp_scattering_segment_f(&ss, &tt, (float)hs[ih], (float)mus[im], (float)sun[is], (float)nus[in], d, Lsf);
              int ok = all_finite_f(Tf, 3) && all_finite_f(Lf, 3) && all_finite_f(Tsf, 3) && all_finite_f(Lsf, 3);
              if (!ok) printf("non-finite: top %g sat %d h %g mu %.9g mu_s %g nu %g\n", tops[shell], sat, hs[ih], mus[im], sun[is], nus[in]);
              finite &= ok;
              /* float vs double away from the horizon discontinuity of the ray's end */
              /* (float)h rounds viewers 1e-6 km above the top onto it: skip those */
              if (!sat && fabs(mus[im] - hz) > 1e-3 && fabs(mus[im] - hz_top) > 1e-3 && fabs(hs[ih] - tops[shell]) > 1e-3)
                for (int c = 0; c < 3; ++c) {
                  worst_f = fmax(worst_f, fabs(Tf[c] - Td[c]));
                }
              ++cases;
            }
      }
      sf_mlp_sky_free(&tt);
      sf_mlp_sky_free(&ss);
    }
  printf("float32 hard cases: %ld, all finite: %d\n", cases, finite);
  CHECK(finite);
  CHECK_ABS(worst_f, 0.0, 1e-3);
  sf_mlp_sky_free(&t);
  sf_mlp_sky_free(&s);
  return check_summary();
}
