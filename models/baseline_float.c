#include "models/baseline_float.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/emitted_float.h"
#include "models/optical_depth_flat.h"
#include "models/optical_depth_taylor.h"

int sf_baseline_f_make(const sf_atmosphere *atm, sf_baseline_f_kind kind, sf_baseline_f *out) {
  memset(out, 0, sizeof *out);
  if (atm->n_channels > 4) return -1;
  out->kind = kind;
  out->n_constituents = atm->n_constituents;
  out->n_channels = atm->n_channels;
  out->bottom = (float)atm->bottom_radius_km;
  out->thickness = (float)(atm->top_radius_km - atm->bottom_radius_km);
  out->top = (float)atm->top_radius_km;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      out->scale_height[i] = (float)H;
      out->factor[i] = (float)(kind == SF_BASELINE_F_CHAPMAN ? H * d0 : d0);
    } else {
      double lo, hi;
      sf_flat_shell_of(atm, i, &lo, &hi);
      out->is_shell[i] = 1;
      out->shell_lo[i] = (float)lo;
      out->shell_hi[i] = (float)hi;
    }
    for (int k = 0; k < atm->n_channels; ++k) out->extinction[i][k] = (float)sf_extinction(atm, i, k);
  }
  return 0;
}

static void grid_f(const sf_spline_grid *g, float (*storage)[4], sf_spline_grid_f *out) {
  out->n_x = g->n_x;
  out->n_d = g->n_d;
  out->x_step = (float)g->x_step;
  out->x_end = (float)(g->x_step * (g->n_x - 1));
  out->d_first = (float)g->d_first;
  out->d_step = (float)g->d_step;
  for (int k = 0; k < g->n_x * g->n_d; ++k) {
    storage[k][0] = (float)g->value[k];
    storage[k][1] = (float)g->d_dx[k];
    storage[k][2] = (float)g->d_dd[k];
    storage[k][3] = (float)g->d_dxdd[k];
  }
  out->node = (const float (*)[4])storage;
}

int sf_baseline_f_make_spline(const sf_atmosphere *atm, const sf_spline_model *model, sf_baseline_f *out) {
  if (sf_baseline_f_make(atm, SF_BASELINE_F_SPLINE, out) != 0) return -1;
  size_t nodes = 0;
  for (int i = 0; i < model->n_constituents; ++i)
    if (model->is_exponential[i])
      nodes += (size_t)model->miss[i].n_x * model->miss[i].n_d + (size_t)model->hit[i].n_x * model->hit[i].n_d;
  out->storage = malloc(sizeof *out->storage * (nodes ? nodes : 1));
  if (!out->storage) return -1;
  float(*next)[4] = out->storage;
  for (int i = 0; i < model->n_constituents; ++i) {
    if (!model->is_exponential[i]) continue;
    out->factor[i] = (float)model->surface_density[i];
    grid_f(&model->miss[i], next, &out->miss[i]);
    next += model->miss[i].n_x * model->miss[i].n_d;
    grid_f(&model->hit[i], next, &out->hit[i]);
    next += model->hit[i].n_x * model->hit[i].n_d;
  }
  return 0;
}

void sf_baseline_f_free(sf_baseline_f *b) {
  free(b->storage);
  b->storage = NULL;
}

/* skyfit_hermite */
static float hermite_f(float u, float p0, float m0, float p1, float m1) {
  float u2 = u * u, u3 = u2 * u;
  return (2.0f * u3 - 3.0f * u2 + 1.0f) * p0 + (u3 - 2.0f * u2 + u) * m0 + (3.0f * u2 - 2.0f * u3) * p1 +
         (u3 - u2) * m1;
}

/* skyfit_spline_miss_<i> (hit 0) and skyfit_spline_hit_<i> (hit 1): the
 * d cell's 1-D spline integrated over [a, b] cell by cell up to b's cell,
 * each node formed once, region I by 2-point Gauss-Legendre, region II in
 * q = sqrt(h + delta) by 4-point (codegen/baseline_spline.c) */
static float spline_integral_f(const sf_spline_grid_f *g, float d, float a, float b, int hit, float delta) {
  float x = (d - g->d_first) / g->d_step;
  int j = 0;
  float fj = 0.0f, fk = 0.0f;
  for (int k = 0; k < g->n_d - 1; ++k) {
    if (x >= fk) {
      j = k;
      fj = fk;
    }
    fk += 1.0f;
  }
  float v = fminf(fmaxf(x - fj, 0.0f), 1.0f), v2 = v * v, v3 = v2 * v;   /* skyfit_hermite_weights */
  float wd[4] = {2.0f * v3 - 3.0f * v2 + 1.0f, v3 - 2.0f * v2 + v, 3.0f * v2 - 2.0f * v3, v3 - v2};
  float ds = g->d_step, xs = g->x_step;
  a = fmaxf(a, 0.0f);
  b = fminf(b, g->x_end);
  float sum = 0.0f, x0 = 0.0f;
  const float *n0 = g->node[j * g->n_x], *n1 = g->node[j * g->n_x + g->n_x];
  float p0 = wd[0] * n0[0] + wd[1] * ds * n0[2] + wd[2] * n1[0] + wd[3] * ds * n1[2];
  float m0 = xs * (wd[0] * n0[1] + wd[1] * ds * n0[3] + wd[2] * n1[1] + wd[3] * ds * n1[3]);
  for (int i = 0; i < g->n_x - 1; ++i) {
    float x1 = x0 + xs;
    n0 += 4;
    n1 += 4;
    float p1 = wd[0] * n0[0] + wd[1] * ds * n0[2] + wd[2] * n1[0] + wd[3] * ds * n1[2];
    float m1 = xs * (wd[0] * n0[1] + wd[1] * ds * n0[3] + wd[2] * n1[1] + wd[3] * ds * n1[3]);
    float lo = fmaxf(a, x0), hi = i == g->n_x - 2 ? b : fminf(b, x1);
    if (hi > lo) {
      if (!hit) {
        float hw = 0.5f * (hi - lo), mid = 0.5f * (hi + lo), gl = hw * 0.57735026918962576f;
        sum += hw * (hermite_f((mid - gl - x0) / xs, p0, m0, p1, m1) + hermite_f((mid + gl - x0) / xs, p0, m0, p1, m1));
      } else {
        float qa = sqrtf(lo + delta), qb = sqrtf(hi + delta), qc = sqrtf(x0 + delta);
        float hw = 0.5f * (hi - lo) / (qa + qb), mid = 0.5f * (qa + qb);
        float q1 = mid - hw * 0.86113631159405258f, q2 = mid - hw * 0.33998104358485626f;
        float q3 = mid + hw * 0.33998104358485626f, q4 = mid + hw * 0.86113631159405258f;
        sum += 2.0f * hw *
               (0.34785484513745386f * (hermite_f((q1 - qc) * (q1 + qc) / xs, p0, m0, p1, m1) +
                                        hermite_f((q4 - qc) * (q4 + qc) / xs, p0, m0, p1, m1)) +
                0.65214515486254614f * (hermite_f((q2 - qc) * (q2 + qc) / xs, p0, m0, p1, m1) +
                                        hermite_f((q3 - qc) * (q3 + qc) / xs, p0, m0, p1, m1)));
      }
    }
    if (b <= x1) break;
    p0 = p1;
    m0 = m1;
    x0 = x1;
  }
  return sum;
}

/* skyfit_chapman_diff */
static float chapman_diff(float H, float h_a, float r_a, float c_a, float dh, float dc) {
  float C_a = sqrtf(r_a / H), C_b = sqrtf((r_a + dh) / H);
  float den_a = 1.0f + C_a * c_a, den_b = 1.0f + C_b * (c_a + dc);
  float dg = (C_a * C_b * dc - dh / (H * (C_a + C_b))) / (den_a * den_b);
  return expf(-h_a / H) * (dg - C_b / den_b * sf_emitted_expm1_f(-dh / H));
}

/* skyfit_taylor_piece; line = (tau_b, h(tau_b), h'(tau_b), a h''(tau_b) / 2) */
static float taylor_piece(const float line[4], float d, float bottom, float H, float u_lo, float u_hi, float len) {
  if (!(len > 0.0f)) return 0.0f;
  if (!(line[2] > 0.0f)) return len * expf(-line[1] / H);
  float x = u_lo - line[0];
  float h_lo = (line[3] * x + line[2]) * x + line[1];
  float rise = len * (line[2] + line[3] * (u_lo + u_hi - 2.0f * line[0]));
  float ratio = H / line[2], f = -sf_emitted_expm1_f(-rise / H);
  float e = -h_lo / H;
  if (e > 80.0f) {
    float log_first = e + logf(ratio), log_piece = log_first + logf(f);
    if (log_first > 709.78f || log_piece > 709.78f) {
      float h_true = ((d - bottom) * (d + bottom) + u_lo * u_lo) / (sqrtf(d * d + u_lo * u_lo) + bottom);
      return len * expf(-h_true / H);
    }
    if (log_piece > 88.0f) return 3.4e38f;
    return expf(log_piece);
  }
  float piece = ratio * expf(e) * f;
  return piece > 0.0f ? piece : 0.0f;
}

/* The ends of the piece seg of the ray (h, mu) (codegen/baselines.c
 * emit_segment_ends and the depths' own preambles). */
typedef struct piece_ends {
  float r, s0, s1, d, dd_bb, h0, h1, r0, r1, ds, dh01;
  int shape;
} piece_ends;

static piece_ends ends_of(const sf_baseline_f *b, float h, float mu, const float seg[4]) {
  const float R = b->bottom;
  piece_ends e;
  e.r = R + h;
  e.s0 = seg[0] + e.r * mu;
  e.s1 = seg[1] + e.r * mu;
  e.d = e.r * sqrtf((1.0f - mu) * (1.0f + mu));
  e.dd_bb = h * (e.r + R) - (e.r * mu) * (e.r * mu);
  e.shape = e.s0 >= 0.0f ? 0 : (e.s1 <= 0.0f ? 1 : 2);
  e.h0 = seg[2];
  e.h1 = seg[3];
  e.r0 = R + e.h0;
  e.r1 = R + e.h1;
  e.ds = seg[1] - seg[0];
  e.dh01 = e.ds * (e.s1 + e.s0) / (e.r1 + e.r0);
  return e;
}

static float chapman_column(const sf_baseline_f *b, const piece_ends *e, float H) {
  float c0 = fminf(fmaxf(e->s0 / e->r0, -1.0f), 1.0f), c1 = fminf(fmaxf(e->s1 / e->r1, -1.0f), 1.0f);
  float hc = e->dd_bb / (e->d + b->bottom);
  float dc01 = (e->ds * e->r0 - e->s0 * e->dh01) / (e->r0 * e->r1);
  if (e->shape == 0) return chapman_diff(H, e->h0, e->r0, c0, e->dh01, dc01);
  if (e->shape == 1) return chapman_diff(H, e->h1, e->r1, -c1, -e->dh01, dc01);
  return chapman_diff(H, hc, e->d, 0.0f, e->s0 * e->s0 / (e->r0 + e->d), -e->s0 / e->r0) +
         chapman_diff(H, hc, e->d, 0.0f, e->s1 * e->s1 / (e->r1 + e->d), e->s1 / e->r1);
}

/* seed 002 eq. 12 and its expansion point (the emitted taylor depths) */
static void taylor_line(const sf_baseline_f *b, float h, float mu, const piece_ends *e, float line[4], float *t_min,
                        float *t_max) {
  const float R = b->bottom;
  *t_min = e->dd_bb < 0.0f ? sqrtf(-e->dd_bb) : 0.0f;
  float tt = (b->thickness - h) * (b->top + e->r) + (e->r * mu) * (e->r * mu);
  *t_max = tt > 0.0f ? sqrtf(tt) : 0.0f;
  if (*t_max < *t_min) *t_max = *t_min;
  float tau = *t_min + (float)SF_TAYLOR_B * (*t_max - *t_min);
  float rho = sqrtf(e->d * e->d + tau * tau);
  line[0] = tau;
  line[1] = (e->dd_bb + tau * tau) / (rho + R);
  line[2] = rho > 0.0f ? tau / rho : 0.0f;
  line[3] = rho > 0.0f ? (float)(0.5 * SF_TAYLOR_A) * e->d * e->d / (rho * rho * rho) : 0.0f;
}

static float taylor_column(const sf_baseline_f *b, const piece_ends *e, const float line[4], float t_min,
                           float t_max, float H) {
  const float R = b->bottom;
  float u0 = fminf(fmaxf(fabsf(e->s0), t_min), t_max), u1 = fminf(fmaxf(fabsf(e->s1), t_min), t_max);
  float len = e->ds;
  if (e->shape == 0) return taylor_piece(line, e->d, R, H, u0, u1, len);
  if (e->shape == 1) return taylor_piece(line, e->d, R, H, u1, u0, len);
  return taylor_piece(line, e->d, R, H, t_min, u0, u0 - t_min) + taylor_piece(line, e->d, R, H, t_min, u1, u1 - t_min);
}

/* eq. 51, and eq. 53 about the closest point c (models/optical_depth_flat.c,
 * descent CLOSEST), as codegen/baselines.c sf_emit_flat_columns_closest
 * regroups them */
static float flat_column(const sf_baseline_f *b, const piece_ends *e, float H) {
  float hc = e->dd_bb / (e->d + b->bottom);
  if (e->shape == 0) return sf_emitted_flat_up_diff_f(H, e->h0, e->r0, e->s0, e->dh01, e->ds);
  if (e->shape == 1) return sf_emitted_flat_up_diff_f(H, e->h1, e->r1, -e->s1, -e->dh01, e->ds);
  return sf_emitted_flat_up_diff_f(H, hc, e->d, 0.0f, e->s0 * e->s0 / (e->r0 + e->d), -e->s0) +
         sf_emitted_flat_up_diff_f(H, hc, e->d, 0.0f, e->s1 * e->s1 / (e->r1 + e->d), e->s1);
}

/* the emitted spline depths (codegen/baseline_spline.c sf_emit_spline_depths):
 * region I in |s| from the closest approach, region II in the altitude;
 * through the closest approach always region I */
static float spline_column(const sf_baseline_f *b, int i, const piece_ends *e) {
  float u0 = fabsf(e->s0), u1 = fabsf(e->s1);
  float delta = -e->dd_bb / (e->d + b->bottom);   /* r - d */
  const sf_spline_grid_f *miss = &b->miss[i], *hit = &b->hit[i];
  if (e->dd_bb >= 0.0f || e->shape == 2) {
    if (e->shape == 2)
      return spline_integral_f(miss, e->d, 0.0f, u0, 0, 0.0f) + spline_integral_f(miss, e->d, 0.0f, u1, 0, 0.0f);
    return spline_integral_f(miss, e->d, fminf(u0, u1), fmaxf(u0, u1), 0, 0.0f);
  }
  if (e->shape == 2)
    return spline_integral_f(hit, e->d, 0.0f, e->h0, 1, delta) + spline_integral_f(hit, e->d, 0.0f, e->h1, 1, delta);
  return spline_integral_f(hit, e->d, fminf(e->h0, e->h1), fmaxf(e->h0, e->h1), 1, delta);
}

void sf_baseline_columns_f(const sf_baseline_f *b, float h, float mu, const float seg[4], float *depth) {
  const float R = b->bottom;
  for (int i = 0; i < b->n_constituents; ++i) depth[i] = 0.0f;
  if (!(seg[1] > seg[0])) return;
  piece_ends e = ends_of(b, h, mu, seg);
  float line[4], t_min = 0.0f, t_max = 0.0f;
  if (b->kind == SF_BASELINE_F_TAYLOR) taylor_line(b, h, mu, &e, line, &t_min, &t_max);
  for (int i = 0; i < b->n_constituents; ++i) {
    if (b->is_shell[i]) {
      depth[i] = sf_emitted_shell_chord_f(R, b->shell_lo[i], b->shell_hi[i], h, mu, seg[0], seg[1]);
      continue;
    }
    float H = b->scale_height[i];
    if (b->kind == SF_BASELINE_F_TAYLOR) {
      depth[i] = fminf(b->factor[i] * taylor_column(b, &e, line, t_min, t_max, H), 3.4e38f);
    } else if (b->kind == SF_BASELINE_F_SPLINE) {
      float tau = spline_column(b, i, &e);
      depth[i] = tau > 0.0f ? b->factor[i] * tau : 0.0f;
    } else {
      float tau = b->kind == SF_BASELINE_F_CHAPMAN ? chapman_column(b, &e, H) : flat_column(b, &e, H);
      depth[i] = tau > 0.0f ? b->factor[i] * tau : 0.0f;
    }
  }
}

void sf_baseline_transmittance_f(const sf_baseline_f *b, float h_km, float mu, float *T) {
  const float R = b->bottom;
  float depth[SF_MAX_CONSTITUENTS] = {0}, seg[4];
  float h = fmaxf(h_km, 0.0f);   /* as emitted (codegen/baselines.c) */
  if (sf_emitted_ray_enter_f(R, b->thickness, &h, &mu, NULL, 0.0f)) {
    sf_emitted_air_clip_between_f(R, b->thickness, h, mu, 0.0f, 3.4e38f, seg);
    sf_baseline_columns_f(b, h, mu, seg, depth);
  }
  for (int k = 0; k < b->n_channels; ++k) {
    float tau = 0.0f;
    int terms = 0;
    for (int i = 0; i < b->n_constituents; ++i) {
      if (b->extinction[i][k] == 0.0f) continue;
      tau = terms ? tau + b->extinction[i][k] * depth[i] : b->extinction[i][k] * depth[i];
      ++terms;
    }
    T[k] = terms ? expf(-tau) : 1.0f;
  }
}
