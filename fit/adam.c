#include "fit/adam.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/target_clones.h"

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

/* A mini-batch epoch takes a step per batch, and the step ran one parameter
 * at a time (1.2 us of a 25 us scattering batch on 2 threads): vectorised
 * (CMakeLists.txt compiles this file with -fno-math-errno, so sqrt need not
 * set errno), and compiled for three instruction sets chosen at run time
 * (util/target_clones.h), all with the same bits. */
SF_X86_CLONES
void sf_adam_step(sf_adam *a, const sf_adam_options *o, double lr, double *theta, const double *g) {
  a->step += 1;
  /* Bias corrections 1 - beta^t (Algorithm 1). */
  double c1 = 1.0 - pow(o->beta1, (double)a->step);
  double c2 = 1.0 - pow(o->beta2, (double)a->step);
  /* Read once: a store to theta, m or v could otherwise alias them, and
   * the loop would not vectorise. */
  const double beta1 = o->beta1, beta2 = o->beta2, eps = o->eps;
  double *m = a->m, *v = a->v;
  for (int k = 0; k < a->n; ++k) {
    m[k] = beta1 * m[k] + (1.0 - beta1) * g[k];
    v[k] = beta2 * v[k] + (1.0 - beta2) * g[k] * g[k];
    double m_hat = m[k] / c1, v_hat = v[k] / c2;
    theta[k] -= lr * m_hat / (sqrt(v_hat) + eps);
  }
}

double sf_adam_lr(const sf_adam_options *o, int epoch) {
  return o->lr * pow(o->lr_decay_per_epoch, (double)epoch);
}
