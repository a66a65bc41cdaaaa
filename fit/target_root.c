#include "fit/target_root.h"

#include <math.h>
#include <stdio.h>

int sf_target_root_check(int k, const sf_mlp_shape *shape, sf_error *err) {
  if (k < 1 || k > SF_TARGET_ROOT_MAX)
    return sf_fail(err, SF_ERR_INPUT, "target root %d: expected 1..%d", k, SF_TARGET_ROOT_MAX);
  if (k > 1 && shape->output != SF_ACT_EXP_NEG && shape->output != SF_ACT_EXP_NEG_EXP)
    return sf_fail(err, SF_ERR_INPUT,
                   "target root %d needs the output exp_neg or exp_neg_exp, whose k-th power is a network of "
                   "the same form; this network's output is %s", k, sf_mlp_activation_name(shape->output));
  return SF_OK;
}

int sf_dataset_targets_root(sf_dataset *d, int k, sf_error *err) {
  if (k == 1) return SF_OK;
  long n_values = d->n * d->n_out;
  for (long i = 0; i < n_values; ++i)
    if (!(d->y[i] >= 0.0) || !isfinite(d->y[i]))
      return sf_fail(err, SF_ERR_INPUT, "sample %ld, target %s: %g has no real root %d (needs >= 0)",
                     i / d->n_out, d->names[d->n_in + i % d->n_out], d->y[i], k);
  /* the square roots of the square root for k = 4: within an ulp, and the
   * same on every libm */
  for (long i = 0; i < n_values; ++i) d->y[i] = k == 4 ? sqrt(sqrt(d->y[i])) : pow(d->y[i], 1.0 / k);
  return SF_OK;
}

void sf_dataset_targets_power(sf_dataset *d, int k) {
  if (k == 1) return;
  long n_values = d->n * d->n_out;
  for (long i = 0; i < n_values; ++i) {
    double y = d->y[i], p = y;
    for (int j = 1; j < k; ++j) p *= y;
    d->y[i] = p;
  }
}

void sf_mlp_from_target_root(const sf_mlp_shape *shape, double *params, int k) {
  if (k == 1) return;
  int last = shape->n_layers - 1, n_out = shape->sizes[shape->n_layers], n_in = shape->sizes[last];
  double *W = params + sf_mlp_weight_offset(shape, last), *b = params + sf_mlp_bias_offset(shape, last);
  if (shape->output == SF_ACT_EXP_NEG_EXP) {
    const double ln_k = log((double)k);
    for (int r = 0; r < n_out; ++r) b[r] -= ln_k;
  } else {
    for (int r = 0; r < n_out; ++r) {
      for (int j = 0; j < n_in; ++j) W[(long)r * n_in + j] *= k;
      b[r] *= k;
    }
  }
}

void sf_target_root_label(int k, char *out, size_t out_len) {
  if (k == 1) snprintf(out, out_len, "raw");
  else snprintf(out, out_len, "root_%d", k);
}
