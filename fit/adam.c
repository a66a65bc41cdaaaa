#include "fit/adam.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sf_adam_options_default(sf_adam_options *o) {
  o->lr = 0.01;
  o->beta1 = 0.9;
  o->beta2 = 0.999;
  o->eps = 1e-8;
  o->lr_decay_per_epoch = 1.0;
}

int sf_adam_init(sf_adam *a, int n) {
  a->n = n;
  a->step = 0;
  a->m = calloc((size_t)n, sizeof(double));
  a->v = calloc((size_t)n, sizeof(double));
  if (!a->m || !a->v) {
    sf_adam_free(a);
    return -1;
  }
  return 0;
}

void sf_adam_reset(sf_adam *a) {
  a->step = 0;
  memset(a->m, 0, (size_t)a->n * sizeof(double));
  memset(a->v, 0, (size_t)a->n * sizeof(double));
}

void sf_adam_free(sf_adam *a) {
  free(a->m);
  free(a->v);
  a->m = a->v = NULL;
}

void sf_adam_step(sf_adam *a, const sf_adam_options *o, double lr, double *theta, const double *g) {
  a->step += 1;
  /* Bias corrections 1 - beta^t (Algorithm 1). */
  double c1 = 1.0 - pow(o->beta1, (double)a->step);
  double c2 = 1.0 - pow(o->beta2, (double)a->step);
  for (int k = 0; k < a->n; ++k) {
    a->m[k] = o->beta1 * a->m[k] + (1.0 - o->beta1) * g[k];
    a->v[k] = o->beta2 * a->v[k] + (1.0 - o->beta2) * g[k] * g[k];
    double m_hat = a->m[k] / c1, v_hat = a->v[k] / c2;
    theta[k] -= lr * m_hat / (sqrt(v_hat) + o->eps);
  }
}

double sf_adam_lr(const sf_adam_options *o, int epoch) {
  return o->lr * pow(o->lr_decay_per_epoch, (double)epoch);
}
