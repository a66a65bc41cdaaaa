/* fit/target_root.h: a network trained on the k-th roots of its targets,
 * turned into the network of the targets themselves, computes exactly the
 * k-th power of the first (checked against (f(x))^k on random networks and
 * inputs, both output forms); the roots and powers of a data set, and what
 * is refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/target_root.h"
#include "models/rng.h"
#include "tests/check.h"

/* max over random inputs of |g(x) - f(x)^k| / f(x)^k, g the converted
 * network of f */
static double worst_power_error(const char *layers, sf_mlp_activation output, int k, uint64_t seed) {
  sf_error err = {0};
  sf_mlp_shape shape;
  if (sf_mlp_shape_parse_layers(layers, &shape, &err) != SF_OK) return INFINITY;
  shape.hidden = SF_ACT_SIGMOID;
  shape.output = output;
  int np = sf_mlp_param_count(&shape), n_in = shape.sizes[0], n_out = shape.sizes[shape.n_layers];
  double *f = malloc((size_t)np * sizeof *f), *g = malloc((size_t)np * sizeof *g);
  sf_rng rng;
  sf_rng_seed(&rng, seed, 17, (uint64_t)k);
  for (int p = 0; p < np; ++p) f[p] = 2.0 * sf_rng_uniform(&rng) - 1.0;
  memcpy(g, f, (size_t)np * sizeof *g);
  sf_mlp_from_target_root(&shape, g, k);
  double worst = 0.0, x[8], yf[8], yg[8];
  for (int trial = 0; trial < 200; ++trial) {
    for (int j = 0; j < n_in; ++j) x[j] = 4.0 * sf_rng_uniform(&rng) - 2.0;
    sf_mlp_forward(&shape, f, x, yf);
    sf_mlp_forward(&shape, g, x, yg);
    for (int r = 0; r < n_out; ++r) {
      double want = pow(yf[r], k);
      double e = fabs(yg[r] - want) / want;
      if (!(e <= worst)) worst = e;   /* a NaN becomes the worst */
    }
  }
  free(f);
  free(g);
  return worst;
}

int main(void) {
  /* The identity holds to rounding: e^(-e^(-(z - ln k))) against
   * (e^(-e^(-z)))^k, and e^(-k z) against (e^(-z))^k. */
  static const int ks[] = {2, 3, 4, 7, 16};
  for (size_t i = 0; i < sizeof ks / sizeof ks[0]; ++i) {
    double e1 = worst_power_error("2,5,3", SF_ACT_EXP_NEG_EXP, ks[i], 1);
    double e2 = worst_power_error("3,4,4,2", SF_ACT_EXP_NEG, ks[i], 2);
    printf("k = %2d: exp_neg_exp worst rel. error %.3g, exp_neg %.3g\n", ks[i], e1, e2);
    CHECK(e1 <= 1e-13);
    CHECK(e2 <= 1e-13);
  }
  /* k = 1 leaves the network alone. */
  CHECK(worst_power_error("2,5,3", SF_ACT_EXP_NEG_EXP, 1, 3) == 0.0);

  /* Which roots a network can take. */
  sf_error err = {0};
  sf_mlp_shape shape;
  CHECK(sf_mlp_shape_parse_layers("2,4,3", &shape, &err) == SF_OK);
  shape.hidden = SF_ACT_SIGMOID;
  shape.output = SF_ACT_SIGMOID;
  CHECK(sf_target_root_check(1, &shape, &err) == SF_OK);
  CHECK(sf_target_root_check(4, &shape, &err) == SF_ERR_INPUT && strstr(err.message, "sigmoid"));
  shape.output = SF_ACT_EXP_NEG_EXP;
  CHECK(sf_target_root_check(4, &shape, &err) == SF_OK);
  CHECK(sf_target_root_check(0, &shape, &err) == SF_ERR_INPUT);
  CHECK(sf_target_root_check(SF_TARGET_ROOT_MAX + 1, &shape, &err) == SF_ERR_INPUT);

  /* A data set's roots and powers: y^(1/4) to the ulp, back to y. */
  sf_dataset d;
  CHECK(sf_dataset_init(&d, 3, 1, 2, &err) == SF_OK);
  const double y[6] = {1.0, 0.5, 2.7e-9, 0.0, 0.0625, 0.9999};
  memcpy(d.y, y, sizeof y);
  CHECK(sf_dataset_targets_root(&d, 4, &err) == SF_OK);
  CHECK_REL(d.y[1], pow(0.5, 0.25), 2.3e-16);
  CHECK_REL(d.y[2], pow(2.7e-9, 0.25), 2.3e-16);
  CHECK(d.y[0] == 1.0 && d.y[3] == 0.0 && d.y[4] == 0.5);
  sf_dataset_targets_power(&d, 4);
  for (int i = 0; i < 6; ++i) CHECK_REL(d.y[i], y[i], 1e-15);
  char label[32];
  sf_target_root_label(4, label, sizeof label);
  CHECK(strcmp(label, "root_4") == 0);
  sf_target_root_label(1, label, sizeof label);
  CHECK(strcmp(label, "raw") == 0);
  /* A negative or NaN target has no root: refused, naming it, nothing changed. */
  d.y[3] = -1e-3;
  double before[6];
  memcpy(before, d.y, sizeof before);
  memset(&err, 0, sizeof err);
  int refused = sf_dataset_targets_root(&d, 2, &err) == SF_ERR_INPUT;
  printf("refused: %s\n", err.message);
  CHECK(refused && strstr(err.message, "sample 1, target y1"));
  CHECK(memcmp(before, d.y, sizeof before) == 0);
  d.y[3] = NAN;
  CHECK(sf_dataset_targets_root(&d, 2, &err) == SF_ERR_INPUT);
  sf_dataset_free(&d);
  return check_summary();
}
