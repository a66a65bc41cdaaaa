/* Levenberg-Marquardt polish of a trained network (SPEC §7.4-7.5): after
 * Adam (fit/train.h) has found the basin, a few damped Gauss-Newton steps
 * on the same loss bring a small network to the bottom of it, where Adam's
 * mini-batch noise stalls orders of magnitude above (measured in
 * bench/mlp_accuracy.sh). Written by hand like Adam: the loss is
 *   sum over samples s and outputs k of e_sk^2,
 * e the residual of fit/mlp_backward.h (mse: p - y; rel: (p - y)/(|y| + d_k);
 * log: log(p + d_k) - log(y + d_k)), so minimising it minimises the training
 * loss. Each iteration forms J^T J and J^T e over the samples (the Jacobian
 * by back-propagation of each output, one sample at a time, in sample
 * order, J^T J from its Kronecker form, fit/lm_gram.h: deterministic,
 * independent of threads), solves
 *   (J^T J + lambda diag(J^T J) + lambda_floor I) step = -J^T e
 * by Cholesky, and accepts the step if the loss drops (lambda / 3), else
 * rejects it (lambda * 4). The validation loss, when given, picks the best
 * iterate (early stopping), so polishing cannot over-fit unnoticed. */
#ifndef SKYFIT_FIT_MLP_LM_H
#define SKYFIT_FIT_MLP_LM_H

#include <signal.h>

#include "fit/dataset.h"
#include "fit/mlp_backward.h"
#include "models/mlp.h"
#include "util/error.h"

/* The scattering network's polish, in `skyfit fit mlp-scattering` and in
 * the build alike: 100 steps on 10,000 training samples. Against 30 steps
 * on 20,000 (fit's former default): validation RMSE 0.0027-0.0034 against
 * 0.0034-0.0041, and a geometric mean of the App. B views' RMSE over the
 * seed's of 0.22-0.28 against 0.28-0.32 (fit seeds 1-4), in no more time;
 * on 5,000 samples one seed's orbit-dawn view doubled its error (README). */
#define SF_MLP_SCATTERING_POLISH 100
#define SF_MLP_SCATTERING_POLISH_SAMPLES 10000

/* The transmittance network's shape and polish, in `skyfit fit
 * mlp-transmittance` and in the build alike: two hidden layers of 16, then
 * 400 steps on every training sample. The 2-8-8-3 of before, 50 epochs and
 * 60 steps, left T_top's RMSE over the (x_r, x_mu) square at 0.0026 and the
 * default build's transmittance 2.9x over its 1e-3 budget; 2-16-16-3 after
 * 50 epochs: 6.7e-4-8.2e-4 with 200 steps, 3.4e-4-6.6e-4 with 400 (seeds
 * 1-4, bench_transmittance_error_map). The error left lies on rays whose
 * lowest point is in the ozone layer's kinks (20-50 km). */
#define SF_MLP_TRANSMITTANCE_HIDDEN "16,16"
#define SF_MLP_TRANSMITTANCE_POLISH 400

/* After each step: its number (1..n_steps), the mean training loss and
 * the best validation loss so far (NAN without validation). */
typedef void (*sf_mlp_lm_progress_fn)(void *ctx, int step, int n_steps, double train_loss, double validation_loss);

typedef struct sf_mlp_lm_options {
  int iterations;          /* accepted or rejected steps; 0: nothing */
  long max_samples;        /* samples used to form J^T J (the first ones); <= 0: all */
  double lambda0;          /* initial damping, default 1e-3 */
  int n_threads;           /* <= 0: all cores (default); the result does not depend on it */
  /* set (Ctrl-C): stop before the next step, result->interrupted; may be NULL */
  const volatile sig_atomic_t *interrupt;
  int stop_after_steps;    /* > 0: behave as interrupted after this many steps (tests) */
  sf_mlp_lm_progress_fn progress;   /* may be NULL */
  void *progress_ctx;
} sf_mlp_lm_options;

void sf_mlp_lm_options_default(sf_mlp_lm_options *o);

typedef struct sf_mlp_lm_result {
  double initial_loss, final_loss;          /* mean loss on the training samples used */
  double initial_validation, final_validation;   /* NAN without validation */
  int iterations, accepted;
  int interrupted;         /* stopped by o->interrupt: params are a partial polish */
} sf_mlp_lm_result;

/* The bytes the polish allocates for shape with n_threads threads (0: all
 * cores): its normal equations are P x P (P parameters), three of them and
 * one per thread, so they grow with P^2 (2-128-128-3: 12 GB), and a step's
 * solve with P^3. For a check before the training whose result it
 * polishes. */
size_t sf_mlp_lm_bytes(const sf_mlp_shape *shape, int n_threads);

/* Polishes params (in place; the best iterate by validation loss if
 * validation is given and not empty, else the last accepted one). loss as
 * in training (delta per output for rel and log). SF_ERR_INTERNAL when out
 * of memory. */
int sf_mlp_lm_polish(const sf_mlp_shape *shape, double *params, const sf_mlp_loss *loss, const sf_dataset *train,
                     const sf_dataset *validation, const sf_mlp_lm_options *o, sf_mlp_lm_result *result,
                     sf_error *err);

#endif
