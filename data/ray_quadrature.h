/* Fixed-order quadrature along a ray for the precomputed tables: graded
 * Gauss-Legendre pieces instead of the adaptive reference integrator
 * (models/optical_depth.h), so that a table entry costs a few hundred density
 * evaluations and every entry uses the same, deterministic rule.
 *
 * A segment is cut where a density is not smooth (the kinks, the ray's
 * closest approach to the centre: models/ray_pieces.h) and at any extra
 * points the caller needs (the edge of the planet's shadow), and the smooth
 * pieces are graded in altitude: a sub-piece that starts z km above the
 * lowest point of the segment spans at most K/kappa + z km of altitude,
 * where kappa is the steepest exponential decay rate of the densities and K
 * = SF_RAY_QUAD_GRADING. From the lowest point that is the geometric
 * sequence K/kappa (1, 2, 4, ...): every sub-piece sees its fastest density
 * vary by at most a factor exp(K 2^j) while carrying a weight
 * exp(-K (2^j - 1)) of the first, so a short rule converges on all of them
 * (Gauss-Legendre with n points on exp over an exponent range A errs by
 * about (A/2)^(2n) (n!)^4 / ((2n+1) ((2n)!)^3): 1e-10 for n = 6, A = 6).
 * Densities growing with altitude are graded the same way down from the
 * highest point. */
#ifndef SKYFIT_DATA_RAY_QUADRATURE_H
#define SKYFIT_DATA_RAY_QUADRATURE_H

#include "data/gauss_rule.h"
#include "models/atmosphere.h"

#define SF_RAY_QUAD_MAX_BREAKS 1024
/* Exponent range of the first graded sub-piece (see above). */
#define SF_RAY_QUAD_GRADING 4.0
/* Optical thickness of the first sub-piece of the extinction grading of
 * sf_ray_nodes_fill (below). */
#define SF_RAY_QUAD_OPTICAL_GRADING 8.0
#define SF_RAY_QUAD_OPTICAL_GROWTH 1.0

/* Cut points of [t0, t1] along the ray (r, mu): t0, the sorted interior
 * cuts, t1; returns their count (>= 2, <= max_breaks). extra (n_extra
 * points, may be NULL) are added cuts; those outside (t0, t1) are ignored.
 * The segment must lie in the air (not below the ground). */
int sf_ray_quad_breaks(const sf_atmosphere *atm, double r, double mu, double t0, double t1,
                       const double *extra, int n_extra, double *breaks, int max_breaks);

/* Optical depth (density integral, km) of every constituent over [t0, t1];
 * the parts above the top radius count for nothing. out has
 * atm->n_constituents entries. */
void sf_ray_quad_optical_depth(const sf_atmosphere *atm, const sf_gauss_rule *rule, double r,
                               double mu, double t0, double t1, double *out);

/* The quadrature nodes of a segment with what the scattering integrals need
 * at each: distance, weight (km), radius, every constituent's density, and
 * every constituent's optical depth from t0 to the node. The nodes come in
 * pieces of rule->n; each piece also keeps its densities' interpolating
 * polynomial so that the optical depth is known anywhere inside it
 * (sf_ray_nodes_depth_at), which lets a caller cut a piece further (at the
 * edge of the planet's shadow) without integrating it again. */
typedef struct sf_ray_nodes {
  int n, capacity, n_constituents;
  double *t, *weight, *radius;
  double *density;   /* [node * n_constituents + i] */
  double *depth;     /* [node * n_constituents + i] */
  double total_depth[SF_MAX_CONSTITUENTS];   /* over the whole segment */
  int n_pieces;      /* piece p holds nodes p*rule->n .. (p+1)*rule->n - 1 */
  double *piece_start, *piece_end;
  double *piece_depth;   /* [p * n_constituents + i]: depth from t0 to piece_start */
  double *piece_coef;    /* [(p * n_constituents + i) * rule->n + m]: Legendre
                            coefficients of density i over the piece */
} sf_ray_nodes;

/* Room for the largest node list of rule (SF_RAY_QUAD_MAX_BREAKS pieces).
 * Returns 0, or -1 when out of memory (nodes then empty). */
int sf_ray_nodes_alloc(sf_ray_nodes *nodes, const sf_gauss_rule *rule, int n_constituents);
void sf_ray_nodes_free(sf_ray_nodes *nodes);

/* Fills nodes for [t0, t1] along (r, mu) (inside the top sphere and not
 * below the ground), cut as sf_ray_quad_breaks does and then graded in
 * optical depth from t0: a sub-piece that starts at optical depth tau
 * (estimated from the largest extinction at its ends) is at most
 * SF_RAY_QUAD_OPTICAL_GRADING + SF_RAY_QUAD_OPTICAL_GROWTH tau thick, because
 * the scattering integrands carry
 * exp(-tau), which in a thick atmosphere varies faster than any density. */
void sf_ray_nodes_fill(sf_ray_nodes *nodes, const sf_atmosphere *atm, const sf_gauss_rule *rule,
                       double r, double mu, double t0, double t1, const double *extra, int n_extra);

/* Optical depth of every constituent from t0 to t, for t inside piece p,
 * from the piece's interpolating polynomial. */
void sf_ray_nodes_depth_at(const sf_ray_nodes *nodes, const sf_gauss_rule *rule, int piece, double t,
                           double *depth);

#endif
