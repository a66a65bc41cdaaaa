#include "models/sky_naive.h"

#include <math.h>
#include <string.h>

#include "models/emitted_float.h"
#include "models/optical_depth_chapman.h"
#include "models/optical_depth_flat.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

static double clamp1(double x) { return fmin(fmax(x, -1.0), 1.0); }

void sf_sky_schuler_make(const sf_atmosphere *atm, sf_sky_naive *out) {
  memset(out, 0, sizeof *out);
  out->atm = atm;
  out->view_steps = SF_SKY_SCHULER_VIEW_STEPS;
  out->sun_steps = 1;
  out->sun = SF_SKY_SUN_CHAPMAN;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (!sf_constituent_exponential(&atm->constituents[i], &H, &d0))
      sf_flat_shell_of(atm, i, &out->shell_lo[i], &out->shell_hi[i]);
  }
}

/* Optical depth per constituent (density times km) from altitude h along
 * the sun's cosine mu_s to the top, by a midpoint raymarch or Schuler's
 * approximation; 0 (and returns 0) where the planet hides the sun. */
static int sun_depths(const sf_sky_naive *m, double h, double mu_s, double *depth) {
  const sf_atmosphere *atm = m->atm;
  double R = atm->bottom_radius_km, r = R + h, t_near, t_far;
  if (sf_ray_hits_sphere_from_above(r, mu_s, R)) return 0;
  if (!sf_ray_sphere_intersections(r, mu_s, atm->top_radius_km, &t_near, &t_far)) t_far = 0.0;
  if (m->sun == SF_SKY_SUN_CHAPMAN) {
    /* seed 000 eq. 24 (its second case where the sun ray dips below the
     * point's horizontal); the others as their eq. 59 shells */
    sf_optical_depth_chapman_segment(atm, r, mu_s, 0.0, fmax(t_far, 0.0), depth);
    for (int i = 0; i < atm->n_constituents; ++i)
      if (isnan(depth[i]))
        depth[i] = sf_flat_shell_chord(R + m->shell_lo[i], R + m->shell_hi[i], r, mu_s, 0.0, fmax(t_far, 0.0));
    return 1;
  }
  double ds = fmax(t_far, 0.0) / m->sun_steps;
  for (int j = 0; j < m->sun_steps; ++j) {
    double hj = sf_ray_altitude_at(R, h, mu_s, (j + 0.5) * ds);
    for (int i = 0; i < atm->n_constituents; ++i) depth[i] += sf_constituent_density(&atm->constituents[i], hj);
  }
  for (int i = 0; i < atm->n_constituents; ++i) depth[i] *= ds;
  return 1;
}

void sf_sky_naive_radiance(const sf_sky_naive *m, double h_km, double mu, double mu_s, double nu, double *L) {
  const sf_atmosphere *atm = m->atm;
  const int nc = atm->n_constituents, nk = atm->n_channels;
  for (int k = 0; k < nk; ++k) L[k] = 0.0;
  mu = clamp1(mu);   /* the cosines clamped as the emitted code clamps them */
  mu_s = clamp1(mu_s);
  nu = sf_clamp_nu(mu, mu_s, nu);
  sf_view_ray ray;
  double mu_s_e;
  const char *why = NULL;
  if (sf_view_ray_make_at_entry(atm, fmax(h_km, 0.0), mu, mu_s, nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e,
                                &why) != 0 ||
      !(ray.t1 > ray.t0))
    return;
  double R = atm->bottom_radius_km, h = ray.r - R;
  double phase[SF_MAX_CONSTITUENTS], view[SF_MAX_CONSTITUENTS] = {0};
  for (int i = 0; i < nc; ++i) phase[i] = sf_phase_value(&atm->constituents[i].phase, nu);
  double dt = (ray.t1 - ray.t0) / m->view_steps;
  for (int s = 0; s < m->view_steps; ++s) {
    double t = ray.t0 + (s + 0.5) * dt;
    double hp = sf_ray_altitude_at(R, h, ray.mu, t);
    double mu_s_p = clamp1((ray.r * mu_s_e + t * nu) / (R + hp));
    double rho[SF_MAX_CONSTITUENTS], sun[SF_MAX_CONSTITUENTS] = {0};
    for (int i = 0; i < nc; ++i) rho[i] = sf_constituent_density(&atm->constituents[i], hp);
    if (sun_depths(m, hp, mu_s_p, sun))
      for (int k = 0; k < nk; ++k) {
        double tau = 0.0, scatter = 0.0;
        for (int i = 0; i < nc; ++i) {
          tau += sf_extinction(atm, i, k) * (view[i] + 0.5 * rho[i] * dt + sun[i]);
          scatter += atm->constituents[i].scattering[k] * rho[i] * phase[i];
        }
        L[k] += exp(-tau) * scatter;
      }
    for (int i = 0; i < nc; ++i) view[i] += rho[i] * dt;
  }
  for (int k = 0; k < nk; ++k) L[k] *= dt * atm->sun_irradiance[k];
}

/* ---- float32 ---------------------------------------------------------------- */

int sf_sky_naive_f_make(const sf_sky_naive *m, sf_sky_naive_f *out) {
  const sf_atmosphere *atm = m->atm;
  memset(out, 0, sizeof *out);
  if (sf_sky_constants_f_make(atm, &out->sky) != 0) return -1;
  out->view_steps = m->view_steps;
  out->sun_steps = m->sun_steps;
  out->sun = m->sun;
  /* Schuler's sun columns travel in a vec4 (codegen/emit_sky_naive.h) */
  if (m->sun == SF_SKY_SUN_CHAPMAN &&
      (atm->n_constituents > 4 || sf_atmosphere_exponential_count(atm) == 0 ||
       sf_baseline_f_make(atm, SF_BASELINE_F_CHAPMAN, &out->chapman) != 0))
    return -1;
  for (int i = 0; i < atm->n_constituents; ++i) sf_density_f_make(&atm->constituents[i], &out->density[i]);
  return 0;
}

void sf_sky_naive_radiance_f(const sf_sky_naive_f *m, float h_km, float mu, float mu_s, float nu, float *L) {
  const int nc = m->sky.n_constituents, nk = m->sky.n_channels;
  for (int k = 0; k < nk; ++k) L[k] = 0.0f;
  mu = fminf(fmaxf(mu, -1.0f), 1.0f);   /* skyfit_<model>_sky_radiance's clamps */
  mu_s = fminf(fmaxf(mu_s, -1.0f), 1.0f);
  float spread = sqrtf(fmaxf(0.0f, (1.0f - mu * mu) * (1.0f - mu_s * mu_s)));
  nu = fminf(fmaxf(nu, mu * mu_s - spread), mu * mu_s + spread);
  float R = m->sky.bottom, Rt = m->sky.bottom + m->sky.thickness;
  float h = fmaxf(h_km, 0.0f), t0, t1;
  if (!sf_emitted_ray_enter_f(R, m->sky.thickness, &h, &mu, &mu_s, nu)) return;   /* a viewer above the top */
  float r = R + h;
  sf_emitted_air_clip_f(R, m->sky.thickness, h, mu, &t0, &t1);
  if (!(t1 > t0)) return;
  /* the phase functions once per ray, in double rounded to float, as the
   * networks' float32 evaluation takes them (models/mlp_sky.h) */
  float phase[SF_MAX_CONSTITUENTS], view[SF_MAX_CONSTITUENTS] = {0};
  for (int i = 0; i < nc; ++i) phase[i] = (float)sf_phase_value(&m->sky.phase[i], (double)nu);
  float dt = (t1 - t0) / (float)m->view_steps;
  for (int s = 0; s < m->view_steps; ++s) {
    float t = t0 + ((float)s + 0.5f) * dt;
    float hp = sf_ray_altitude_at_f(R, h, mu, t);
    float mu_s_p = fminf(fmaxf((r * mu_s + t * nu) / (R + hp), -1.0f), 1.0f);
    float rho[SF_MAX_CONSTITUENTS], sun[SF_MAX_CONSTITUENTS] = {0};
    for (int i = 0; i < nc; ++i) rho[i] = sf_density_f_at(&m->density[i], hp);
    float rp = R + hp, g0, g1, t_near, t_far;
    sf_emitted_sphere_hits_f(rp, mu_s_p, R, -hp, &g0, &g1);
    if (!(mu_s_p < 0.0f && g0 <= g1)) {   /* else the planet hides the sun */
      float ds = 1.0f;   /* the sun's columns are sun[i] * ds (Schuler's: km already) */
      if (m->sun == SF_SKY_SUN_CHAPMAN) {   /* skyfit_schuler_sun_columns */
        float seg[4];
        sf_emitted_air_clip_between_f(R, m->sky.thickness, hp, mu_s_p, 0.0f, 3.4e38f, seg);
        sf_baseline_columns_f(&m->chapman, hp, mu_s_p, seg, sun);
      } else {
        sf_emitted_sphere_hits_f(rp, mu_s_p, Rt, m->sky.thickness - hp, &t_near, &t_far);
        ds = fmaxf(t_far, 0.0f) / (float)m->sun_steps;
        for (int j = 0; j < m->sun_steps; ++j) {
          float hj = sf_ray_altitude_at_f(R, hp, mu_s_p, ((float)j + 0.5f) * ds);
          for (int i = 0; i < nc; ++i) sun[i] += sf_density_f_at(&m->density[i], hj);
        }
      }
      for (int k = 0; k < nk; ++k) {
        float tau = 0.0f, scatter = 0.0f;
        for (int i = 0; i < nc; ++i) {
          tau += m->sky.extinction[i][k] * (view[i] + 0.5f * rho[i] * dt + sun[i] * ds);
          scatter += m->sky.scattering[i][k] * rho[i] * phase[i];
        }
        L[k] += expf(-tau) * scatter;
      }
    }
    for (int i = 0; i < nc; ++i) view[i] += rho[i] * dt;
  }
  for (int k = 0; k < nk; ++k) L[k] *= dt * m->sky.sun[k];
}
