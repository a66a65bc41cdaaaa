#include "models/sky_raymarched.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "models/emitted_float.h"
#include "models/optical_depth.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "models/sun_shadow.h"
#include "models/view_ray.h"

static double clamp1(double x) { return fmin(fmax(x, -1.0), 1.0); }

void sf_sky_raymarched_make(const sf_atmosphere *atm, int steps, sf_raymarched_depths depths,
                            sf_sky_raymarched *out) {
  out->atm = atm;
  out->steps = steps;
  out->depths = depths;
  sf_flat_model_make(atm, SF_FLAT_DESCENT_CLOSEST, &out->flat);
}

double sf_exp_mean_between(double a, double b) {
  double lo = fmin(a, b), d = fabs(b - a);
  /* e^-lo (1 - e^-d) / d, seed 000 eq. 47 */
  return exp(-lo) * (d > 0.0 ? -expm1(-d) / d : 1.0);
}

/* Density integral (km) of each constituent over [t0, t1] along (r, mu). */
static void columns(const sf_sky_raymarched *m, double r, double mu, double t0, double t1, double *out) {
  if (m->depths == SF_RAYMARCHED_DEPTHS_EXACT) sf_optical_depth_segment(m->atm, r, mu, t0, t1, out);
  else sf_optical_depth_flat_segment(m->atm, r, mu, t0, t1, &m->flat, out);
}

/* The sun's optical depth per channel from radius r along its cosine mu_s
 * to the top. Where the planet hides the sun (a point in the shadow, or on
 * its edge rounded into it) the sun ray is taken as grazing the ground, the
 * limit from the lit side; the flat model's column is taken along the
 * line, the planet ignored, so that it is continuous across the edge
 * wherever rounding puts it (the emitted code's too). */
static void sun_depth(const sf_sky_raymarched *m, double r, double mu_s, double *tau) {
  const sf_atmosphere *atm = m->atm;
  double R = atm->bottom_radius_km, col[SF_MAX_CONSTITUENTS];
  if (sf_ray_hits_sphere_from_above(r, mu_s, R)) mu_s = sf_horizon_mu(r, R);
  if (m->depths == SF_RAYMARCHED_DEPTHS_EXACT) {
    /* the reference's quadrature must not pass below the ground */
    for (int i = 0; i < 8 && sf_ray_hits_sphere_from_above(r, mu_s, R); ++i) mu_s = nextafter(mu_s, 1.0);
    double t_near, t_far;
    for (int i = 0; i < atm->n_constituents; ++i) col[i] = 0.0;
    if (sf_ray_sphere_intersections(r, mu_s, atm->top_radius_km, &t_near, &t_far) && t_far > 0.0)
      sf_optical_depth_segment(atm, r, mu_s, 0.0, t_far, col);
  } else {
    sf_optical_depth_flat_line_segment(atm, r, mu_s, 0.0, INFINITY, &m->flat, col);
  }
  for (int k = 0; k < atm->n_channels; ++k) {
    tau[k] = 0.0;
    for (int i = 0; i < atm->n_constituents; ++i) tau[k] += sf_extinction(atm, i, k) * col[i];
  }
}

/* What the march carries from one end of a piece to the next: the column
 * from the viewer per constituent, and the optical depth viewer -> point
 * -> sun per channel. */
typedef struct march_point {
  double t;
  double view[SF_MAX_CONSTITUENTS];
  double depth[SF_MAX_CHANNELS];
} march_point;

typedef struct march {
  const sf_sky_raymarched *m;
  const sf_view_ray *ray;
  double mu_s, nu;
  sf_sun_line shadow;
  double scatter_phase[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];   /* beta_s,i,k P_i(nu) */
} march;

/* The point at distance t, from the point a before it. */
static void advance(const march *w, const march_point *a, double t, march_point *b, double *col) {
  const sf_atmosphere *atm = w->m->atm;
  const sf_view_ray *ray = w->ray;
  columns(w->m, ray->r, ray->mu, a->t, t, col);
  b->t = t;
  for (int i = 0; i < atm->n_constituents; ++i) b->view[i] = a->view[i] + col[i];
  double r = sf_ray_radius_at(ray->r, ray->mu, t);
  double sun[SF_MAX_CHANNELS];
  sun_depth(w->m, r, clamp1((ray->r * w->mu_s + t * w->nu) / r), sun);
  for (int k = 0; k < atm->n_channels; ++k) {
    b->depth[k] = sun[k];
    for (int i = 0; i < atm->n_constituents; ++i) b->depth[k] += sf_extinction(atm, i, k) * b->view[i];
  }
}

/* The piece from a to t (seed 000 eq. 55), added to L; *a becomes its end. */
static void piece(const march *w, march_point *a, double t, double *L) {
  const sf_atmosphere *atm = w->m->atm;
  march_point b;
  double col[SF_MAX_CONSTITUENTS];
  advance(w, a, t, &b, col);
  if (!sf_sun_line_hidden(&w->shadow, 0.5 * (a->t + t)))
    for (int k = 0; k < atm->n_channels; ++k) {
      double scatter = 0.0;
      for (int i = 0; i < atm->n_constituents; ++i) scatter += w->scatter_phase[i][k] * col[i];
      L[k] += scatter * sf_exp_mean_between(a->depth[k], b.depth[k]);
    }
  *a = b;
}

void sf_sky_raymarched_radiance(const sf_sky_raymarched *m, double h_km, double mu, double mu_s, double nu,
                                double *L) {
  const sf_atmosphere *atm = m->atm;
  for (int k = 0; k < atm->n_channels; ++k) L[k] = 0.0;
  mu = clamp1(mu);   /* the cosines clamped as the emitted code clamps them */
  mu_s = clamp1(mu_s);
  nu = sf_clamp_nu(mu, mu_s, nu);
  sf_view_ray ray;
  march w = {.m = m, .ray = &ray, .nu = nu};
  const char *why = NULL;
  if (sf_view_ray_make_at_entry(atm, fmax(h_km, 0.0), mu, mu_s, nu, SF_RAY_END_NEAREST, -1.0, &ray, &w.mu_s,
                                &why) != 0 ||
      !(ray.t1 > ray.t0))
    return;
  w.shadow = sf_sun_line_make(ray.r, ray.mu, w.mu_s, nu, atm->bottom_radius_km);
  for (int i = 0; i < atm->n_constituents; ++i) {
    double p = sf_phase_value(&atm->constituents[i].phase, nu);
    for (int k = 0; k < atm->n_channels; ++k) w.scatter_phase[i][k] = atm->constituents[i].scattering[k] * p;
  }
  /* the shadow's edges on the ray: where the sun ray grazes the ground
   * ahead of the point (p.s < 0), inside the stretch; and where the sun
   * line passes closest to the ground (the clearance's vertex), whence
   * the edges grow as the sun sets: with a sample there the radiance is
   * continuous as the shadow appears (a jump of 14 % without it) */
  double edge[3], tangent[2];
  int n_edges = 0, n_tangent = sf_sun_line_tangent_distances(&w.shadow, tangent);
  for (int e = 0; e < n_tangent; ++e)
    if (tangent[e] > ray.t0 && tangent[e] < ray.t1 && w.shadow.r_mu_s + tangent[e] * nu < 0.0)
      edge[n_edges++] = tangent[e];
  if (w.shadow.a > 0.0) {
    double vertex = -w.shadow.b / (2.0 * w.shadow.a);
    if (vertex > ray.t0 && vertex < ray.t1) edge[n_edges++] = vertex;
  }
  for (int i = 1; i < n_edges; ++i)
    for (int j = i; j > 0 && edge[j] < edge[j - 1]; --j) {
      double swap = edge[j];
      edge[j] = edge[j - 1];
      edge[j - 1] = swap;
    }
  /* the viewer's end: no column yet, the sun's depth from there */
  march_point a = {.t = ray.t0};
  double sun[SF_MAX_CHANNELS];
  double r0 = sf_ray_radius_at(ray.r, ray.mu, ray.t0);
  sun_depth(m, r0, clamp1((ray.r * w.mu_s + ray.t0 * nu) / r0), sun);
  for (int k = 0; k < atm->n_channels; ++k) a.depth[k] = sun[k];
  int next_edge = 0;
  double dt = (ray.t1 - ray.t0) / m->steps;
  for (int s = 1; s <= m->steps; ++s) {
    double t = s == m->steps ? ray.t1 : ray.t0 + s * dt;
    while (next_edge < n_edges && edge[next_edge] < t) piece(&w, &a, edge[next_edge++], L);
    piece(&w, &a, t, L);
  }
  for (int k = 0; k < atm->n_channels; ++k) L[k] *= atm->sun_irradiance[k];
}

/* ---- float32 ---------------------------------------------------------------- */

int sf_sky_raymarched_f_make(const sf_sky_raymarched *m, sf_sky_raymarched_f *out) {
  const sf_atmosphere *atm = m->atm;
  memset(out, 0, sizeof *out);
  if (atm->n_constituents > 4 || m->depths != SF_RAYMARCHED_DEPTHS_FLAT || m->steps < 1 ||
      sf_sky_constants_f_make(atm, &out->sky) != 0)
    return -1;
  out->steps = m->steps;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    out->is_shell[i] = m->flat.is_shell[i];
    if (!out->is_shell[i] && sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      out->scale_height[i] = (float)H;
      out->density[i] = (float)d0;
    }
    out->shell_lo[i] = (float)m->flat.shell_bottom_km[i];
    out->shell_hi[i] = (float)m->flat.shell_top_km[i];
  }
  return 0;
}

/* skyfit_raymarched_line_columns: the flat model's column of every
 * constituent over the piece seg of the line (h, mu), descent CLOSEST
 * (codegen/baselines.h sf_emit_flat_columns_closest). */
static void line_columns_f(const sf_sky_raymarched_f *m, float h, float mu, const float seg[4], float *col) {
  const float R = m->sky.bottom;
  for (int i = 0; i < m->sky.n_constituents; ++i) col[i] = 0.0f;
  if (!(seg[1] > seg[0])) return;
  float r = R + h, s0 = seg[0] + r * mu, s1 = seg[1] + r * mu;
  float d = r * sqrtf((1.0f - mu) * (1.0f + mu));
  float dd_bb = h * (r + R) - (r * mu) * (r * mu);
  int shape = s0 >= 0.0f ? 0 : (s1 <= 0.0f ? 1 : 2);
  float h0 = seg[2], h1 = seg[3], r0 = R + h0, r1 = R + h1;
  float hc = dd_bb / (d + R), ds = seg[1] - seg[0], dh01 = ds * (s1 + s0) / (r1 + r0);
  for (int i = 0; i < m->sky.n_constituents; ++i) {
    if (m->is_shell[i]) {
      col[i] = sf_emitted_shell_chord_f(R, m->shell_lo[i], m->shell_hi[i], h, mu, seg[0], seg[1]);
      continue;
    }
    float H = m->scale_height[i];
    float tau = shape == 0   ? sf_emitted_flat_up_diff_f(H, h0, r0, s0, dh01, ds)
                : shape == 1 ? sf_emitted_flat_up_diff_f(H, h1, r1, -s1, -dh01, ds)
                             : sf_emitted_flat_up_diff_f(H, hc, d, 0.0f, s0 * s0 / (r0 + d), -s0) +
                                   sf_emitted_flat_up_diff_f(H, hc, d, 0.0f, s1 * s1 / (r1 + d), s1);
    col[i] = tau > 0.0f ? m->density[i] * tau : 0.0f;
  }
}

/* skyfit_raymarched_sun_columns */
static void sun_columns_f(const sf_sky_raymarched_f *m, float h, float c, float *col) {
  const float R = m->sky.bottom;
  float rp = R + h, t_near, t_far;
  c = fmaxf(c, -sqrtf(fmaxf(h, 0.0f) * (rp + R)) / rp);
  sf_emitted_sphere_hits_f(rp, c, R + m->sky.thickness, m->sky.thickness - h, &t_near, &t_far);
  float seg[4] = {0.0f, fmaxf(t_far, 0.0f), h, m->sky.thickness};
  line_columns_f(m, h, c, seg, col);
}

/* skyfit_exp_mean */
static float exp_mean_f(float a, float b) {
  float d = fabsf(b - a);
  return expf(-fminf(a, b)) * (d > 0.0f ? -sf_emitted_expm1_f(-d) / d : 1.0f);
}

/* sum_i extinction_i,k (view_i + sun_i) per channel, the emitted order */
static void depths_f(const sf_sky_raymarched_f *m, const float *view, const float *sun, float *depth) {
  for (int k = 0; k < m->sky.n_channels; ++k) {
    depth[k] = 0.0f;
    for (int i = 0; i < m->sky.n_constituents; ++i)
      if (m->sky.extinction[i][k] != 0.0f) depth[k] += m->sky.extinction[i][k] * (view[i] + sun[i]);
  }
}

void sf_sky_raymarched_radiance_f(const sf_sky_raymarched_f *m, float h_km, float mu, float mu_s, float nu,
                                  float *L) {
  const int nc = m->sky.n_constituents, nk = m->sky.n_channels;
  const float R = m->sky.bottom;
  for (int k = 0; k < nk; ++k) L[k] = 0.0f;
  mu = fminf(fmaxf(mu, -1.0f), 1.0f);   /* skyfit_<model>_sky_radiance's clamps */
  mu_s = fminf(fmaxf(mu_s, -1.0f), 1.0f);
  float spread = sqrtf(fmaxf(0.0f, (1.0f - mu * mu) * (1.0f - mu_s * mu_s)));
  nu = fminf(fmaxf(nu, mu * mu_s - spread), mu * mu_s + spread);
  float hv = fmaxf(h_km, 0.0f), seg[4];
  if (!sf_emitted_ray_enter_f(R, m->sky.thickness, &hv, &mu, &mu_s, nu)) return;
  sf_emitted_air_clip_between_f(R, m->sky.thickness, hv, mu, 0.0f, 3.4e38f, seg);
  if (!(seg[1] > seg[0])) return;
  float r = R + hv, rms = r * mu_s;
  float scatter_phase[4][4];
  for (int i = 0; i < nc; ++i) {
    float p = (float)sf_phase_value(&m->sky.phase[i], (double)nu);
    for (int k = 0; k < nk; ++k) scatter_phase[i][k] = m->sky.scattering[i][k] * p;
  }
  /* the shadow's edges and the sun line's closest approach, as emitted */
  float qa = (1.0f - nu) * (1.0f + nu), qb = 2.0f * r * (mu - mu_s * nu), qc = hv * (r + R) - rms * rms;
  float u0 = 3.4e38f, u1 = 3.4e38f, disc = qb * qb - 4.0f * qa * qc;
  if (qa > 0.0f && disc >= 0.0f) {
    float q = -0.5f * (qb + (qb >= 0.0f ? sqrtf(disc) : -sqrtf(disc)));
    u0 = q / qa;
    if (q != 0.0f) u1 = qc / q;
  } else if (qa == 0.0f && qb != 0.0f) {
    u0 = -qc / qb;
  }
  if (!(u0 > seg[0] && u0 < seg[1] && rms + u0 * nu < 0.0f)) u0 = 3.4e38f;
  if (!(u1 > seg[0] && u1 < seg[1] && rms + u1 * nu < 0.0f)) u1 = 3.4e38f;
  float u2 = qa > 0.0f ? -qb / (2.0f * qa) : 3.4e38f;
  if (!(u2 > seg[0] && u2 < seg[1])) u2 = 3.4e38f;
  float edge0 = fminf(fminf(u0, u1), u2), edge2 = fmaxf(fmaxf(u0, u1), u2);
  float edge1 = fmaxf(fminf(u0, u1), fminf(fmaxf(u0, u1), u2));
  float view[4] = {0.0f, 0.0f, 0.0f, 0.0f}, sun[4], da[4], db[4], col[4];
  sun_columns_f(m, seg[2], fminf(fmaxf((rms + seg[0] * nu) / (R + seg[2]), -1.0f), 1.0f), sun);
  depths_f(m, view, sun, da);
  float a = seg[0], dt = (seg[1] - seg[0]) / (float)m->steps, k_step = 1.0f;
  for (int s = 0; s < m->steps + 3; ++s) {
    float b = k_step >= (float)m->steps ? seg[1] : seg[0] + k_step * dt;
    if (edge0 < b) {
      b = edge0;
      edge0 = edge1;
      edge1 = edge2;
      edge2 = 3.4e38f;
    } else {
      k_step += 1.0f;
    }
    if (!(a < seg[1])) continue;
    float piece[4];
    sf_emitted_air_clip_between_f(R, m->sky.thickness, hv, mu, a, b, piece);
    line_columns_f(m, hv, mu, piece, col);
    for (int i = 0; i < nc; ++i) view[i] += col[i];
    float hb = sf_ray_altitude_at_f(R, hv, mu, b);
    sun_columns_f(m, hb, fminf(fmaxf((rms + b * nu) / (R + hb), -1.0f), 1.0f), sun);
    depths_f(m, view, sun, db);
    float tm = 0.5f * (a + b);
    if (!(rms + tm * nu < 0.0f && (qa * tm + qb) * tm + qc < 0.0f))
      for (int k = 0; k < nk; ++k) {
        float scatter = 0.0f;
        for (int i = 0; i < nc; ++i)
          if (scatter_phase[i][k] != 0.0f) scatter += scatter_phase[i][k] * col[i];
        L[k] += scatter * exp_mean_f(da[k], db[k]);
      }
    for (int k = 0; k < nk; ++k) da[k] = db[k];
    a = b;
  }
  for (int k = 0; k < nk; ++k) L[k] *= m->sky.sun[k];
}
