#include "models/sky_naive.h"

#include <math.h>
#include <string.h>

#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

static double clamp1(double x) { return fmin(fmax(x, -1.0), 1.0); }

/* Optical depth per constituent (density times km) from altitude h along
 * the sun's cosine mu_s to the top, by a midpoint raymarch; 0 (and returns
 * 0) where the planet hides the sun. */
static int sun_depths(const sf_sky_naive *m, double h, double mu_s, double *depth) {
  const sf_atmosphere *atm = m->atm;
  double R = atm->bottom_radius_km, r = R + h, t_near, t_far;
  if (sf_ray_hits_sphere_from_above(r, mu_s, R)) return 0;
  if (!sf_ray_sphere_intersections(r, mu_s, atm->top_radius_km, &t_near, &t_far)) t_far = 0.0;
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
  nu = sf_clamp_nu(mu, mu_s, nu);
  sf_view_ray ray;
  double mu_s_e;
  const char *why = NULL;
  if (sf_view_ray_make_at_entry(atm, fmax(h_km, 0.0), clamp1(mu), mu_s, nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e,
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
  if (atm->n_channels > 4) return -1;
  out->view_steps = m->view_steps;
  out->sun_steps = m->sun_steps;
  out->n_constituents = atm->n_constituents;
  out->n_channels = atm->n_channels;
  out->bottom = (float)atm->bottom_radius_km;
  out->thickness = (float)(atm->top_radius_km - atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    double top = 0.0;
    out->n_layers[i] = c->n_layers;
    for (int l = 0; l < c->n_layers; ++l) {
      top += c->layers[l].width_km;
      out->layer_top[i][l] = (float)top;
      out->layer[i][l][0] = (float)c->layers[l].linear_per_km;
      out->layer[i][l][1] = (float)c->layers[l].constant;
      out->layer[i][l][2] = (float)c->layers[l].exp_term;
      out->layer[i][l][3] = (float)c->layers[l].exp_scale_per_km;
    }
    for (int k = 0; k < atm->n_channels; ++k) {
      out->scattering[i][k] = (float)c->scattering[k];
      out->extinction[i][k] = (float)sf_extinction(atm, i, k);
    }
    out->phase[i] = c->phase;
  }
  for (int k = 0; k < atm->n_channels; ++k) out->sun[k] = (float)atm->sun_irradiance[k];
  return 0;
}

/* As the emitted density (codegen/baselines.h): the layer by cumulative
 * width, clamped to [0, 1]. */
static float density_f(const sf_sky_naive_f *m, int i, float h) {
  int l = 0;
  while (l + 1 < m->n_layers[i] && !(h < m->layer_top[i][l])) ++l;
  const float *p = m->layer[i][l];
  float v = m->n_layers[i] > 0 ? p[0] * h + p[1] + p[2] * expf(p[3] * h) : 0.0f;
  return fminf(fmaxf(v, 0.0f), 1.0f);
}

static float phase_f(const sf_phase *p, float nu) {
  const float inv4pi = 0.0795774715f;
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH: return 0.0596831037f * (1.0f + nu * nu);
    case SF_PHASE_ISOTROPIC: return inv4pi;
    case SF_PHASE_HENYEY_GREENSTEIN: {
      float g = (float)p->g, q = 1.0f + g * g - 2.0f * g * nu;
      return inv4pi * (1.0f - g * g) / (q * sqrtf(q));
    }
    case SF_PHASE_CORNETTE_SHANKS: {
      float g = (float)p->g, q = 1.0f + g * g - 2.0f * g * nu;
      return 0.119366207f * (1.0f - g * g) / (2.0f + g * g) * (1.0f + nu * nu) / (q * sqrtf(q));
    }
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
      float g1 = (float)p->g1, g2 = (float)p->g2, f = (float)p->f;
      float q1 = 1.0f + g1 * g1 - 2.0f * g1 * nu, q2 = 1.0f + g2 * g2 - 2.0f * g2 * nu;
      return inv4pi * ((1.0f - f) * (1.0f - g1 * g1) / (q1 * sqrtf(q1)) + f * (1.0f - g2 * g2) / (q2 * sqrtf(q2)));
    }
    case SF_PHASE_NONE: return 0.0f;
  }
  return 0.0f;
}

/* The emitted helpers' geometry (codegen/emit_helpers.c), in float32 as
 * they run it: distances from altitudes, not from radii, whose difference
 * loses a low viewer's altitude (sf_ray_*_f take radii: a viewer 1 m up
 * looking down had come out 2.3 % off the emitted code, 1.7 m up 11 %). */
static void sphere_hits_f(float r, float mu, float R, float R_minus_r, float *near, float *far) {
  float disc = R_minus_r * (R + r) + (r * mu) * (r * mu);
  if (disc < 0.0f) {
    *near = 1.0f;
    *far = -1.0f;
    return;
  }
  float root = sqrtf(disc);
  float q = -(r * mu + (mu >= 0.0f ? root : -root));
  float b = q != 0.0f ? -R_minus_r * (r + R) / q : 0.0f;
  *near = q < b ? q : b;
  *far = q < b ? b : q;
}

/* skyfit_air_clip's [a, b] for the whole ray (t0 = 0, t1 = 3.4e38). */
static void air_clip_f(float bottom, float thickness, float h, float mu, float *a, float *b) {
  float r = bottom + h, s0, s1, g0, g1;
  *a = *b = 0.0f;
  sphere_hits_f(r, mu, bottom + thickness, thickness - h, &s0, &s1);
  if (s0 > s1) return;
  float lo = 0.0f, hi = 3.4e38f;
  if (s0 > lo) lo = s0;
  if (s1 < hi) hi = s1;
  sphere_hits_f(r, mu, bottom, -h, &g0, &g1);
  if (g0 < g1) {
    if (lo <= g0) {
      if (g0 < hi) hi = g0;
    } else if (lo < g1) {
      lo = g1;
    }
  }
  *a = lo;
  *b = hi > lo ? hi : lo;
}

void sf_sky_naive_radiance_f(const sf_sky_naive_f *m, float h_km, float mu, float mu_s, float nu, float *L) {
  const int nc = m->n_constituents, nk = m->n_channels;
  for (int k = 0; k < nk; ++k) L[k] = 0.0f;
  float spread = sqrtf(fmaxf(0.0f, (1.0f - mu * mu) * (1.0f - mu_s * mu_s)));
  nu = fminf(fmaxf(nu, mu * mu_s - spread), mu * mu_s + spread);
  float R = m->bottom, Rt = m->bottom + m->thickness;
  float r = R + fmaxf(h_km, 0.0f), t0, t1;
  float h = fmaxf(h_km, 0.0f);
  if (h > m->thickness) {   /* above the top: from where the ray enters (the emitted skyfit_ray_enter) */
    float disc;
    if (r > 2.0f * Rt) {
      float p = r * sqrtf(fmaxf((1.0f - mu) * (1.0f + mu), 0.0f));
      disc = (Rt - p) * (Rt + p);
    } else {
      disc = (m->thickness - h) * (Rt + r) + (r * mu) * (r * mu);
    }
    if (!(mu < 0.0f) || !(disc > 0.0f)) return;
    float root = sqrtf(disc);
    mu_s = fminf(fmaxf((r * (mu_s - mu * nu) - root * nu) / Rt, -1.0f), 1.0f);
    mu = fminf(fmaxf(-root / Rt, -1.0f), 1.0f);
    r = Rt;
    h = m->thickness;
  }
  air_clip_f(R, m->thickness, h, mu, &t0, &t1);
  if (!(t1 > t0)) return;
  float phase[SF_MAX_CONSTITUENTS], view[SF_MAX_CONSTITUENTS] = {0};
  for (int i = 0; i < nc; ++i) phase[i] = phase_f(&m->phase[i], nu);
  float dt = (t1 - t0) / (float)m->view_steps;
  for (int s = 0; s < m->view_steps; ++s) {
    float t = t0 + ((float)s + 0.5f) * dt;
    float hp = sf_ray_altitude_at_f(R, h, mu, t);
    float mu_s_p = fminf(fmaxf((r * mu_s + t * nu) / (R + hp), -1.0f), 1.0f);
    float rho[SF_MAX_CONSTITUENTS], sun[SF_MAX_CONSTITUENTS] = {0};
    for (int i = 0; i < nc; ++i) rho[i] = density_f(m, i, hp);
    float rp = R + hp, g0, g1, t_near, t_far;
    sphere_hits_f(rp, mu_s_p, R, -hp, &g0, &g1);
    if (!(mu_s_p < 0.0f && g0 <= g1)) {   /* else the planet hides the sun */
      sphere_hits_f(rp, mu_s_p, Rt, m->thickness - hp, &t_near, &t_far);
      float ds = fmaxf(t_far, 0.0f) / (float)m->sun_steps;
      for (int j = 0; j < m->sun_steps; ++j) {
        float hj = sf_ray_altitude_at_f(R, hp, mu_s_p, ((float)j + 0.5f) * ds);
        for (int i = 0; i < nc; ++i) sun[i] += density_f(m, i, hj);
      }
      for (int k = 0; k < nk; ++k) {
        float tau = 0.0f, scatter = 0.0f;
        for (int i = 0; i < nc; ++i) {
          tau += m->extinction[i][k] * (view[i] + 0.5f * rho[i] * dt + sun[i] * ds);
          scatter += m->scattering[i][k] * rho[i] * phase[i];
        }
        L[k] += expf(-tau) * scatter;
      }
    }
    for (int i = 0; i < nc; ++i) view[i] += rho[i] * dt;
  }
  for (int k = 0; k < nk; ++k) L[k] *= dt * m->sun[k];
}
