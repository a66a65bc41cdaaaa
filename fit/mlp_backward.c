#include "fit/mlp_backward.h"

#include <math.h>
#include <string.h>

static const char *const loss_names[] = {"mse", "rel", "log"};

const char *sf_mlp_loss_name(sf_mlp_loss_kind k) { return (unsigned)k < 3u ? loss_names[k] : "?"; }

int sf_mlp_loss_parse(const char *name, sf_mlp_loss_kind *out) {
  for (int k = 0; k < 3; ++k)
    if (strcmp(name, loss_names[k]) == 0) {
      *out = (sf_mlp_loss_kind)k;
      return 0;
    }
  return -1;
}

double sf_mlp_sample_loss(const sf_mlp_loss *loss, int n_out, const double *pred, const double *target,
                          double *dloss_dpred) {
  double sum = 0.0, inv_n = 1.0 / n_out;
  for (int k = 0; k < n_out; ++k) {
    double e, de;   /* residual and its derivative with respect to pred[k] */
    switch (loss->kind) {
      case SF_LOSS_REL: {
        double w = 1.0 / (fabs(target[k]) + loss->delta[k]);
        e = (pred[k] - target[k]) * w;
        de = w;
        break;
      }
      case SF_LOSS_LOG: {
        double p = pred[k] + loss->delta[k];
        /* A non-positive p (possible only with an output that can go
         * negative) is held at a tiny value: the loss stays finite and
         * large, and pushes p up. */
        if (p < 1e-300) p = 1e-300;
        e = log(p) - log(target[k] + loss->delta[k]);
        de = 1.0 / p;
        break;
      }
      default:
        e = pred[k] - target[k];
        de = 1.0;
        break;
    }
    sum += e * e;
    if (dloss_dpred) dloss_dpred[k] = 2.0 * e * de * inv_n;
  }
  return sum * inv_n;
}

/* f'(z) from a = f(z). */
static inline double activation_slope(sf_mlp_activation f, double a) {
  switch (f) {
    case SF_ACT_SIGMOID: return a * (1.0 - a);
    case SF_ACT_TANH: return 1.0 - a * a;
    case SF_ACT_RELU: return a > 0.0 ? 1.0 : 0.0;
    case SF_ACT_LINEAR: return 1.0;
    case SF_ACT_EXP_NEG: return -a;
    /* d/dz exp(-exp(-z)) = a exp(-z) = -a log a */
    case SF_ACT_EXP_NEG_EXP: return a > 0.0 ? -a * log(a) : 0.0;
  }
  return 1.0;
}

double sf_mlp_loss_range(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                         const double *x, const double *y, const int *index, long begin, long end,
                         double *grad) {
  const int L = s->n_layers, n_in = s->sizes[0], n_out = s->sizes[L];
  /* Activations of every layer for one sample: act[0] = input. */
  double act[SF_MLP_MAX_LAYERS + 1][SF_MLP_MAX_WIDTH];
  double delta[2][SF_MLP_MAX_WIDTH];
  int w_off[SF_MLP_MAX_LAYERS], b_off[SF_MLP_MAX_LAYERS];
  for (int l = 0; l < L; ++l) {
    w_off[l] = sf_mlp_weight_offset(s, l);
    b_off[l] = sf_mlp_bias_offset(s, l);
  }
  double total = 0.0;
  for (long i = begin; i < end; ++i) {
    long sample = index ? index[i] : i;
    const double *xs = x + sample * n_in, *ys = y + sample * n_out;
    for (int j = 0; j < n_in; ++j) act[0][j] = xs[j];
    for (int l = 0; l < L; ++l) {
      int ni = s->sizes[l], no = s->sizes[l + 1];
      const double *W = params + w_off[l], *b = params + b_off[l];
      sf_mlp_activation f = l + 1 == L ? s->output : s->hidden;
      const double *a = act[l];
      double *z = act[l + 1];
      for (int r = 0; r < no; ++r) {
        double sum = b[r];
        const double *row = W + r * ni;
        for (int j = 0; j < ni; ++j) sum += row[j] * a[j];
        z[r] = sf_mlp_activate(f, sum);
      }
    }
    if (!grad) {
      total += sf_mlp_sample_loss(loss, n_out, act[L], ys, NULL);
      continue;
    }
    double *d = delta[L & 1];
    total += sf_mlp_sample_loss(loss, n_out, act[L], ys, d);
    for (int l = L - 1; l >= 0; --l) {
      /* d holds dLoss/da_{l+1}; turn it into dLoss/dz_l. */
      int ni = s->sizes[l], no = s->sizes[l + 1];
      sf_mlp_activation f = l + 1 == L ? s->output : s->hidden;
      for (int r = 0; r < no; ++r) d[r] *= activation_slope(f, act[l + 1][r]);
      const double *W = params + w_off[l];
      double *gW = grad + w_off[l], *gb = grad + b_off[l];
      const double *a = act[l];
      for (int r = 0; r < no; ++r) {
        double dr = d[r];
        double *grow = gW + r * ni;
        for (int j = 0; j < ni; ++j) grow[j] += dr * a[j];
        gb[r] += dr;
      }
      if (l == 0) break;
      double *dn = delta[l & 1];
      for (int j = 0; j < ni; ++j) dn[j] = 0.0;
      for (int r = 0; r < no; ++r) {
        double dr = d[r];
        const double *row = W + r * ni;
        for (int j = 0; j < ni; ++j) dn[j] += dr * row[j];
      }
      d = dn;
    }
  }
  return total;
}
