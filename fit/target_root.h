/* A transmittance network trained on T^(1/k) instead of T, and turned
 * exactly into one for T.
 *
 * Why: a ray that ends on the ground gets its transmittance as the ratio of
 * two reversed rays' (seed 000 eq. 43), T(p -> top) / T(x -> top), both
 * small near the horizon. MSE on T leaves small values a large relative
 * error, and the ratio turns it into a large absolute one: random full
 * rays' max abs error was 0.087-0.214 (`skyfit fit mlp-transmittance
 * --epochs 50`, seeds 1-4). On T^(1/k) a change dT weighs T^(1/k - 1) / k,
 * more where T is small: with k = 4 the same runs gave 0.0125-0.0176, and
 * their full-ray RMSE fell too (0.00094-0.00261 -> 0.00054-0.00083; the
 * grid points' RMSE rose, 0.00025-0.00067 -> 0.00079-0.00112).
 *
 * The conversion is exact in real arithmetic: with the output e^(-e^(-z)),
 * T = (e^(-e^(-z)))^k = e^(-e^(-(z - ln k))), the output biases less ln k;
 * with e^(-z), T = e^(-k z), the output layer's weights and biases times k
 * (exact in floating point too when k is a power of 2). */
#ifndef SKYFIT_FIT_TARGET_ROOT_H
#define SKYFIT_FIT_TARGET_ROOT_H

#include <stddef.h>

#include "fit/dataset.h"
#include "models/mlp.h"
#include "util/error.h"

#define SF_TARGET_ROOT_MAX 16

/* SF_OK when k (1..SF_TARGET_ROOT_MAX) can be used with shape's output
 * (k > 1: exp_neg or exp_neg_exp); else SF_ERR_INPUT saying why. */
int sf_target_root_check(int k, const sf_mlp_shape *shape, sf_error *err);

/* y -> y^(1/k) for every target of d; SF_ERR_INPUT (naming the sample and
 * the target) on a negative or non-finite one, d unchanged. k = 1: nothing. */
int sf_dataset_targets_root(sf_dataset *d, int k, sf_error *err);

/* y -> y^k, back to the targets' units (to measure the converted network
 * on a set the root was taken of). */
void sf_dataset_targets_power(sf_dataset *d, int k);

/* "raw" for k = 1, else "root_<k>": the units of the training losses
 * (fit/train_losses_json.h). */
void sf_target_root_label(int k, char *out, size_t out_len);

/* params, of a network of shape trained on the targets' k-th roots,
 * changed into the network of the targets themselves (above). k = 1:
 * nothing. shape's output must pass sf_target_root_check. */
void sf_mlp_from_target_root(const sf_mlp_shape *shape, double *params, int k);

#endif
