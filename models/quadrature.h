/* Globally adaptive Gauss-Kronrod (G10/K21) quadrature of a vector-valued
 * integrand (QUADPACK's qag strategy): bisect the panel with the largest
 * error until every component meets its tolerance. */
#ifndef SKYFIT_MODELS_QUADRATURE_H
#define SKYFIT_MODELS_QUADRATURE_H

#define SF_QUAD_MAX_COMPONENTS 256
#define SF_QUAD_MAX_PANELS 512

/* Writes n values of the integrand at t into values. */
typedef void (*sf_integrand)(void *ctx, double t, double *values);

typedef struct sf_quad_result {
  int panels;          /* panels in the final partition */
  int evaluations;     /* integrand calls */
  int converged;       /* 1 if every component met its tolerance */
} sf_quad_result;

/* Adds the integral over [a, b] to sum[0..n-1]. Component i has converged
 * when its error estimate is <= max(rel_tol * |integral_i|, abs_tol[i]) (abs_tol
 * may be NULL for 0). */
sf_quad_result sf_integrate_adaptive(sf_integrand f, void *ctx, double a, double b,
                                     int n, double rel_tol, const double *abs_tol,
                                     double *sum);

/* Nodes and weights of the K21 rule on [-1, 1]: the 21 nodes used above, for
 * callers that need the node positions (the single-scattering integrand
 * integrates the view transmittance between consecutive nodes). */
extern const double sf_kronrod21_nodes[21];

#endif
