/* Gałaj's spline transmittance (seed 002 §IV.E, Table 3; SPEC §7.6) as an
 * optical-depth model. For an exponential constituent d0*exp(-h/H) the
 * integrand of seed 002 eq. 12 is tabulated on two rectangular meshes and
 * interpolated by a tensor-product cubic Hermite spline (values, both first
 * derivatives and the mixed one, all exact at the nodes):
 * - region I, lines that miss the ground (r <= d <= R): (t, d) over
 *   [0, sqrt(R^2 - r^2)] x [r, R], integrand exp(-(sqrt(d^2 + t^2) - r)/H),
 *   t the distance from the line's closest approach P_O;
 * - region II, lines that hit the ground (0 <= d < r): (h, d) over
 *   [0, R - r] x [0, r], the integrand after the paper's substitution
 *   h = sqrt(d^2 + t^2) - r: exp(-h/H) (h + r) / sqrt((h + r)^2 - d^2).
 * r is the bottom radius, R the top radius, d the line's distance from the
 * planet centre. For a ray, d selects a 1-D Hermite spline (interpolation
 * across the d nodes), which is integrated exactly between the segment's ends
 * (eq. 13 when P_O lies inside the segment, eq. 14 otherwise; the eq. 14
 * difference of two integrals from 0 is formed as one integral between the
 * ends, the same value without cancellation).
 *
 * Where this differs from the paper, and why:
 * - Region II's integrand is infinite at (h, d) = (0, r): its factor
 *   1/sqrt(h + r - d) is not polynomial-like near d = r. We spline the smooth
 *   remainder s = exp(-h/H) (h + r) / sqrt(h + r + d) instead and integrate
 *   s_spline(h) / sqrt(h + r - d) exactly: with q = sqrt(h + r - d) the
 *   piece is 2 s_spline(q^2 - r + d) dq, a degree-6 polynomial in q, which
 *   4-point Gauss-Legendre integrates exactly. Where r - d >> R - r the
 *   factor 1/sqrt(h + r - d) is nearly constant over [0, R - r] and the
 *   interpolation error is the paper's; near d = r, where a plain spline of
 *   an inverse-square-root peak fails, this one stays accurate.
 * - The paper's region-II d nodes are r j / K, j = 0..K-1, which stop short
 *   of d = r (to avoid the singularity); with the singular factor taken out,
 *   d = r is an ordinary node, so we use r j / (K - 1), j = 0..K-1 and never
 *   extrapolate for d in (r (K-1)/K, r).
 * - A result below 0 (the d interpolation of a thin layer can undershoot,
 *   e.g. Mie, H = 1.2 km, between region-I d nodes 5.3 km apart) is clamped
 *   to 0: a density integral is never negative.
 * Non-exponential constituents (the ozone tent) are replaced, as in the
 * Taylor/flat baselines' emitted code (codegen/baselines.c), by a shell of
 * density 1 (seed 000 §10.5, eq. 59; models/optical_depth_flat.h
 * sf_flat_shell_of) whose optical depth is the exact chord inside it.
 * Segments are first clipped to the air as the reference does
 * (models/air_segment.h). */
#ifndef SKYFIT_MODELS_OPTICAL_DEPTH_SPLINE_H
#define SKYFIT_MODELS_OPTICAL_DEPTH_SPLINE_H

#include "models/atmosphere.h"
#include "models/optical_depth.h"

/* seed 002 Table 3: Hermite splines with 50 height and 20 distance points. */
#define SF_SPLINE_HEIGHT_POINTS 50
#define SF_SPLINE_DISTANCE_POINTS 20

/* One region's mesh: n_x nodes along x (t for region I, h for region II)
 * from 0 with spacing x_step, n_d nodes along d from d_first with spacing
 * d_step. Node (i, j) is at index j * n_x + i of each array. */
typedef struct sf_spline_grid {
  int n_x, n_d;
  double x_step, d_first, d_step;
  double *value;      /* the (region II: factored) integrand */
  double *d_dx;       /* its derivative along x */
  double *d_dd;       /* along d */
  double *d_dxdd;     /* the mixed derivative */
} sf_spline_grid;

typedef struct sf_spline_model {
  double bottom_radius_km, top_radius_km;
  int n_constituents;
  int is_exponential[SF_MAX_CONSTITUENTS];
  double scale_height_km[SF_MAX_CONSTITUENTS];
  double surface_density[SF_MAX_CONSTITUENTS];
  sf_spline_grid miss[SF_MAX_CONSTITUENTS];   /* region I */
  sf_spline_grid hit[SF_MAX_CONSTITUENTS];    /* region II */
  /* The eq. 59 shells of the non-exponential constituents (km above r). */
  double shell_bottom_km[SF_MAX_CONSTITUENTS];
  double shell_top_km[SF_MAX_CONSTITUENTS];
  double *storage;    /* owns every grid array */
} sf_spline_model;

/* Builds the meshes for atm with height_points nodes along t or h and
 * distance_points along d (seed 002: 50 and 20). Returns 0, or -1 (model
 * zeroed, nothing to free) if a count is below 2 or memory runs out. */
int sf_spline_model_make(const sf_atmosphere *atm, int height_points, int distance_points,
                         sf_spline_model *model);
void sf_spline_model_free(sf_spline_model *model);

/* Integral of the spline of one exponential constituent (d0 = 1) over
 * t in [t0, t1] along the ray (r, mu), in km; 0 when nothing is in the air. */
double sf_spline_exponential_segment(const sf_spline_model *model, int constituent,
                                     double r, double mu, double t0, double t1);

/* Density integral (km) of each constituent over t in [t0, t1] along the ray
 * (r, mu); out has model->n_constituents entries (shells for the
 * non-exponential ones). Returns the number of exponential constituents. */
int sf_optical_depth_spline_segment(const sf_spline_model *model, double r, double mu,
                                    double t0, double t1, double *out);

/* From the viewer at altitude h (km above the bottom; may be above the top)
 * along mu to the ray's end, as sf_optical_depth_ray. Returns 0, or -1 if end
 * is SF_RAY_END_TOP and the ray hits the ground first (out zeroed). */
int sf_optical_depth_spline_ray(const sf_spline_model *model, double h_km, double mu,
                                sf_ray_end end, double *out);

/* Transmittance per channel of atm along the same ray (atm must be the
 * atmosphere the model was made from). Returns as sf_optical_depth_spline_ray. */
int sf_transmittance_spline_ray(const sf_spline_model *model, const sf_atmosphere *atm,
                                double h_km, double mu, sf_ray_end end,
                                double *transmittance);

#endif
