/* Adam (Kingma & Ba 2015, Algorithm 1), written by hand as SPEC §2 asks:
 *   m <- b1 m + (1 - b1) g,   v <- b2 v + (1 - b2) g^2,   t <- t + 1,
 *   theta <- theta - lr_t * (m / (1 - b1^t)) / (sqrt(v / (1 - b2^t)) + eps)
 * with the bias corrections of the paper and an optional learning-rate decay
 * lr_t = lr * decay^epoch (decay 1: none; seed 000 §9.6 uses lr 0.01). The
 * state is a plain value so that a checkpoint can store it exactly. */
#ifndef SKYFIT_FIT_ADAM_H
#define SKYFIT_FIT_ADAM_H

typedef struct sf_adam_options {
  double lr, beta1, beta2, eps;
  double lr_decay_per_epoch;   /* multiplies lr once per epoch; 1 = constant */
} sf_adam_options;

/* lr 0.01, beta1 0.9, beta2 0.999, eps 1e-8, no decay (PyTorch's defaults
 * with the seed's learning rate). */
void sf_adam_options_default(sf_adam_options *o);

typedef struct sf_adam {
  int n;
  long step;       /* t: updates made */
  double *m, *v;   /* first and second moment estimates, owned */
} sf_adam;

/* Zero moments; -1 when out of memory. */
int sf_adam_init(sf_adam *a, int n);
void sf_adam_reset(sf_adam *a);
void sf_adam_free(sf_adam *a);

/* One update of theta[0..n-1] from the gradient g at learning rate lr. */
void sf_adam_step(sf_adam *a, const sf_adam_options *o, double lr, double *theta, const double *g);

/* The learning rate of an epoch (0-based). */
double sf_adam_lr(const sf_adam_options *o, int epoch);

#endif
