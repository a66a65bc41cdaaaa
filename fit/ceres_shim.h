/* A thin C interface over Ceres Solver (SPEC §2): nonlinear least squares
 * with residuals and analytic Jacobians written in C, per-parameter bounds,
 * constant blocks, an optional robust loss per residual block, solver
 * options and the solve summary. Plain C: the fit drivers include this and
 * never a C++ header (the implementation is fit/ceres_shim.cc).
 *
 * Cost (as Ceres and SciPy define it): 1/2 sum_blocks rho(|r_block|^2), with
 * rho(s) = s without a loss. Determinism: the solver runs on the threads
 * given in the options (1 by default), so a fit is reproducible bit for bit. */
#ifndef SKYFIT_FIT_CERES_SHIM_H
#define SKYFIT_FIT_CERES_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

/* Computes n_residuals residuals from the parameter blocks of the residual
 * block (params[b] has the size the block was added with). jacobians is
 * NULL when only residuals are wanted; otherwise jacobians[b] is NULL (block
 * held constant) or a row-major n_residuals x size(b) array to fill with
 * d residual[i] / d params[b][k] at [i * size(b) + k]. Returns 1 on
 * success, 0 if the residuals cannot be computed at these parameters (the
 * solver then takes a smaller step). */
typedef int (*sf_lsq_residual_fn)(void *user, const double *const *params, double *residuals,
                                  double **jacobians);

/* A tall residual block given by its Gram matrix instead of its rows. With
 * J the n x p Jacobian of the block's n residuals r over its parameter
 * blocks (in the order they were added to the residual block, p their total
 * size, constant blocks included), the callback writes
 * *sum_squares = |r|^2 and, when gram is not NULL, the (p+1) x (p+1)
 * row-major matrix [J r]^T [J r] (the upper triangle is read; its last
 * diagonal entry is |r|^2 again). Returns 1 on success, 0 if the block
 * cannot be evaluated at these parameters (the solver takes a smaller
 * step). */
typedef int (*sf_lsq_gram_fn)(void *user, const double *const *params, double *sum_squares,
                              double *gram);

typedef enum sf_lsq_loss {
  SF_LSQ_LOSS_NONE = 0,   /* rho(s) = s */
  SF_LSQ_LOSS_HUBER,      /* rho(s) = s for s <= a^2, 2 a sqrt(s) - a^2 beyond */
  SF_LSQ_LOSS_SOFT_L1,    /* rho(s) = 2 a^2 (sqrt(1 + s/a^2) - 1) */
  SF_LSQ_LOSS_CAUCHY      /* rho(s) = a^2 log(1 + s/a^2) */
} sf_lsq_loss;

typedef struct sf_lsq_options {
  int max_iterations;          /* default 200 */
  double function_tolerance;   /* default 1e-12: |d cost| / cost */
  double gradient_tolerance;   /* default 1e-14: max-norm of the projected gradient */
  double parameter_tolerance;  /* default 1e-12: |dx| / (|x| + tol) */
  int n_threads;               /* default 1 */
  int normal_equations;        /* 0 (default): dense QR of the Jacobian; 1: dense
                                  Cholesky of J^T J, faster for tall problems,
                                  squares the condition number */
  double initial_trust_region_radius;  /* default 1e4 (Ceres'); a small one (1..100)
                                  makes the first steps short, as MINPACK's
                                  step bound does, which can keep a non-convex
                                  fit in the basin of its start */
  int dogleg;                  /* 0 (default): Levenberg-Marquardt; 1: Powell's dogleg */
  int nonmonotonic_steps;      /* 0 (default); 1: accept steps that raise the cost
                                  within Ceres' window (escapes narrow valleys) */
  int jacobi_scaling;          /* 1 (default): scale columns of J to unit norm */
} sf_lsq_options;

typedef enum sf_lsq_termination {
  SF_LSQ_CONVERGENCE = 0,      /* a tolerance was met */
  SF_LSQ_NO_CONVERGENCE,       /* iteration limit; the parameters are still usable */
  SF_LSQ_FAILURE               /* the solver could not proceed; parameters not usable */
} sf_lsq_termination;

typedef struct sf_lsq_summary {
  double initial_cost, final_cost;
  int iterations;              /* minimizer iterations, successful or not */
  int successful_steps;
  sf_lsq_termination termination;
  int usable;                  /* 1 if the parameters are a valid result */
  double seconds;              /* wall time of the solve */
  int n_residuals, n_parameters;
  char message[256];           /* Ceres' own words on why it stopped */
} sf_lsq_summary;

typedef struct sf_lsq_problem sf_lsq_problem;

void sf_lsq_options_default(sf_lsq_options *o);
const char *sf_lsq_termination_name(sf_lsq_termination t);

/* NULL when out of memory. */
sf_lsq_problem *sf_lsq_problem_new(void);
void sf_lsq_problem_free(sf_lsq_problem *p);

/* Registers values[0..size) (caller-owned; solved in place) as a parameter
 * block. Returns its index (>= 0), or -1 for a bad size. */
int sf_lsq_add_block(sf_lsq_problem *p, double *values, int size);
/* Bounds on one parameter of a block; -INFINITY / INFINITY for none. The
 * starting value must lie within them. Returns 0, or -1 for a bad index or
 * lower > upper. */
int sf_lsq_set_bounds(sf_lsq_problem *p, int block, int index, double lower, double upper);
/* Holds a whole block at its current values. */
int sf_lsq_set_constant(sf_lsq_problem *p, int block);

/* Adds a residual block of n_residuals residuals depending on the parameter
 * blocks blocks[0..n_blocks). fn is called with user. loss_scale is a
 * (ignored for SF_LSQ_LOSS_NONE). Returns 0, or -1 for bad arguments. */
int sf_lsq_add_residuals(sf_lsq_problem *p, sf_lsq_residual_fn fn, void *user, int n_residuals,
                         int n_blocks, const int *blocks, sf_lsq_loss loss, double loss_scale);

/* Adds a residual block of many residuals over few parameters through its
 * Gram matrix (sf_lsq_gram_fn). Ceres sees p + 1 residuals: the rows of R,
 * the upper-triangular factor of [J r]^T [J r] = R^T R, split as [J' r'].
 * J'^T J' = J^T J, J'^T r' = J^T r and |r'|^2 = |r|^2, and a trust-region
 * step depends on J and r through nothing else, so Levenberg-Marquardt and
 * dogleg take the steps they would take on the n rows (up to rounding),
 * while Ceres' work per iteration no longer grows with n. Columns that are
 * linear combinations of earlier ones (to rounding) get zero rows in R. No
 * robust loss. Returns 0, or -1 for bad arguments. */
int sf_lsq_add_gram_residuals(sf_lsq_problem *p, sf_lsq_gram_fn fn, void *user, int n_blocks,
                              const int *blocks);

/* Solves with a dense trust-region method (the options say which). Returns 0
 * when the result is usable (summary->usable), 1 otherwise; the summary is
 * always filled. */
int sf_lsq_solve(sf_lsq_problem *p, const sf_lsq_options *o, sf_lsq_summary *summary);

/* Cost 1/2 sum rho(|r|^2) at the blocks' current values, without solving.
 * Returns 0, or 1 if a residual callback failed. */
int sf_lsq_cost(sf_lsq_problem *p, double *cost);

#ifdef __cplusplus
}
#endif

#endif
