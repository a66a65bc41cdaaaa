/* Back-propagation for the networks of models/mlp.h (SPEC §7.5): the loss of
 * a set of samples and its gradient with respect to every parameter, in
 * double precision.
 *
 * Losses (per sample, averaged over the outputs k; the training loss is the
 * mean over samples):
 *   mse: (p_k - y_k)^2                            (seed 000 §9.6)
 *   rel: ((p_k - y_k) / (|y_k| + delta_k))^2      (radiance spanning orders
 *                                                   of magnitude)
 *   log: (log(p_k + delta_k) - log(y_k + delta_k))^2
 * delta_k > 0 keeps rel and log finite where the target is 0; the fitters
 * take it as a small fraction of the output's RMS (fit/dataset.h). log needs
 * p_k > -delta_k: use it with a positive output (exp_neg, sigmoid). */
#ifndef SKYFIT_FIT_MLP_BACKWARD_H
#define SKYFIT_FIT_MLP_BACKWARD_H

#include "models/mlp.h"

typedef enum sf_mlp_loss_kind { SF_LOSS_MSE = 0, SF_LOSS_REL, SF_LOSS_LOG } sf_mlp_loss_kind;

typedef struct sf_mlp_loss {
  sf_mlp_loss_kind kind;
  const double *delta;   /* per output; unused by mse (may be NULL then) */
} sf_mlp_loss;

/* "mse", "rel", "log". */
const char *sf_mlp_loss_name(sf_mlp_loss_kind k);
int sf_mlp_loss_parse(const char *name, sf_mlp_loss_kind *out);

/* Loss of one sample (mean over the n_out outputs); dloss_dpred[k] (may be
 * NULL) receives its derivative with respect to pred[k]. */
double sf_mlp_sample_loss(const sf_mlp_loss *loss, int n_out, const double *pred, const double *target,
                          double *dloss_dpred);

/* Sum over samples s = index[begin..end-1] (index NULL: s = begin..end-1) of
 * the sample loss; x is row-major n x sizes[0], y n x sizes[n_layers]. If
 * grad is not NULL, adds the gradient of that sum (flat parameter order of
 * models/mlp.h) to grad[0..n_params-1]. The sum runs in sample order, so
 * the result depends only on the samples, never on who calls. */
double sf_mlp_loss_range(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                         const double *x, const double *y, const int *index, long begin, long end,
                         double *grad);

#endif
