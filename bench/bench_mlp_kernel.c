/* Speed of the training kernel (fit/mlp_backward.h) per sample, one core,
 * on each way training reads its data: the full batch (unit-major columns,
 * forward only and with the gradient), rows in order, and shuffled rows as
 * a mini-batch epoch reads them, from separate x and y and from the packed
 * rows training uses, then that last path on each build of the kernel the
 * CPU can run (fit/mlp_kernel.h: the one the CPU picks and those other
 * CPUs would get, with the same sums; AVX-512F+Newton is AVX-512 with half
 * the sigmoids' divisions by multiply-adds, what Intel CPUs get). Random
 * inputs in [-1, 1] and targets in [0.05, 1.05], Xavier weights, MSE;
 * each figure the fastest of several passes (a shared machine is noisy).
 * The loss printed beside is the pass's sum: the same on every path up to
 * the last bits (shuffled samples are added in another order). Last, the
 * full batch and the shuffled packed rows again with
 * linear units: the kernel's cost without its exponentials and divisions.
 *   bench_mlp_kernel [SAMPLES [LAYERS]]   (default 967680 4,8,8,9: the
 *                                          scattering set of the tables) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/dataset.h"
#include "fit/mlp_backward.h"
#include "fit/train.h"
#include "models/mlp.h"
#include "models/rng.h"
#include "util/clock.h"

#define PASSES 5
#define MIN_SECONDS 0.2

enum path {
  FORWARD_COLUMNS,
  GRADIENT_COLUMNS,
  GRADIENT_ROWS,
  GRADIENT_SHUFFLED_XY,
  GRADIENT_SHUFFLED_PACKED,
  N_PATHS,
  GRADIENT_SHUFFLED_PACKED_ISA   /* the training path on the kernel for b->isa */
};

static const char *const path_names[N_PATHS] = {
    "full batch, forward only (columns)", "full batch, with gradient (columns)", "rows in order, with gradient",
    "shuffled rows from x and y", "shuffled packed rows (training)"};

typedef struct bench_data {
  const sf_mlp_shape *shape;
  const double *params, *x, *y;
  const int *order;
  sf_mlp_isa isa;
  sf_mlp_columns columns;
  sf_mlp_rows rows;
  sf_mlp_workspace ws;
  double *grad;
  long n;
} bench_data;

static double one_pass(bench_data *b, enum path p) {
  sf_mlp_loss loss = {SF_LOSS_MSE, NULL};
  switch (p) {
    case FORWARD_COLUMNS: return sf_mlp_loss_columns_ws(b->shape, b->params, &loss, &b->columns, 0, b->n, NULL, &b->ws);
    case GRADIENT_COLUMNS:
      return sf_mlp_loss_columns_ws(b->shape, b->params, &loss, &b->columns, 0, b->n, b->grad, &b->ws);
    case GRADIENT_ROWS:
      return sf_mlp_loss_range_ws(b->shape, b->params, &loss, b->x, b->y, NULL, 0, b->n, b->grad, &b->ws);
    case GRADIENT_SHUFFLED_XY:
      return sf_mlp_loss_range_ws(b->shape, b->params, &loss, b->x, b->y, b->order, 0, b->n, b->grad, &b->ws);
    case GRADIENT_SHUFFLED_PACKED:
      return sf_mlp_loss_rows_ws(b->shape, b->params, &loss, &b->rows, b->order, 0, b->n, b->grad, &b->ws);
    default: return sf_mlp_loss_rows_isa(b->isa, b->shape, b->params, &loss, &b->rows, b->order, 0, b->n, b->grad);
  }
}

/* Fastest nanoseconds per sample over PASSES timings of at least
 * MIN_SECONDS each; *check receives the loss (the same on every path). */
static double ns_per_sample(bench_data *b, enum path p, double *check) {
  double best = 1e300;
  for (int pass = 0; pass < PASSES; ++pass) {
    long reps = 0;
    double t0 = sf_wall_seconds(), t;
    do {
      *check = one_pass(b, p);
      ++reps;
      t = sf_wall_seconds() - t0;
    } while (t < MIN_SECONDS);
    double ns = t / ((double)reps * (double)b->n) * 1e9;
    if (ns < best) best = ns;
  }
  return best;
}

int main(int argc, char **argv) {
  long n = argc > 1 ? atol(argv[1]) : 967680;
  const char *layers = argc > 2 ? argv[2] : "4,8,8,9";
  sf_mlp_shape shape;
  sf_error err = {0};
  if (n < 1 || sf_mlp_shape_parse_layers(layers, &shape, &err)) {
    fprintf(stderr, "usage: bench_mlp_kernel [SAMPLES >= 1 [LAYERS, e.g. 4,8,8,9]] %s\n", err.message);
    return 2;
  }
  shape.hidden = SF_ACT_SIGMOID;
  shape.output = SF_ACT_EXP_NEG;
  int n_in = shape.sizes[0], n_out = shape.sizes[shape.n_layers], np = sf_mlp_param_count(&shape);
  bench_data b;
  memset(&b, 0, sizeof b);
  double *x = malloc(sizeof(double) * (size_t)n * (size_t)n_in), *y = malloc(sizeof(double) * (size_t)n * (size_t)n_out);
  double *params = malloc(sizeof(double) * (size_t)np);
  int *order = malloc(sizeof(int) * (size_t)n);
  b.grad = calloc((size_t)np, sizeof(double));
  if (!x || !y || !params || !order || !b.grad) {
    fprintf(stderr, "bench_mlp_kernel: out of memory\n");
    return 1;
  }
  sf_rng rng;
  sf_rng_seed(&rng, 1, 0x6b65726eull, 0);   /* "kern" */
  for (long k = 0; k < n * n_in; ++k) x[k] = 2.0 * sf_rng_uniform(&rng) - 1.0;
  for (long k = 0; k < n * n_out; ++k) y[k] = 0.05 + sf_rng_uniform(&rng);
  sf_mlp_init_xavier(&shape, 1, 0, params);
  sf_dataset_permutation(order, n, 1, 0x6b65726eull, 1);
  if (sf_mlp_columns_make(&b.columns, x, y, n, n_in, n_out) || sf_mlp_rows_make(&b.rows, x, y, n, n_in, n_out) ||
      sf_mlp_workspace_init(&b.ws, &shape)) {
    fprintf(stderr, "bench_mlp_kernel: out of memory\n");
    return 1;
  }
  b.shape = &shape;
  b.params = params;
  b.x = x;
  b.y = y;
  b.order = order;
  b.n = n;
  printf("training kernel, %s network (%d parameters), %ld samples, one core, kernel for %s\n", layers, np, n,
         sf_mlp_isa_name(sf_mlp_isa_auto()));
  printf("%-40s %12s %22s\n", "path", "ns/sample", "loss sum");
  for (int p = 0; p < N_PATHS; ++p) {
    double check = 0.0, ns = ns_per_sample(&b, (enum path)p, &check);
    printf("%-40s %12.1f %22.17g\n", path_names[p], ns, check);
  }
  /* The training path on each build of the kernel this CPU can run (the
   * CPU picks one, sf_mlp_isa_auto; the others are what other CPUs would
   * get). */
  for (int q = SF_MLP_ISA_BASELINE; q < SF_MLP_ISA_COUNT; ++q) {
    if (!sf_mlp_isa_available((sf_mlp_isa)q)) continue;
    b.isa = (sf_mlp_isa)q;
    char name[64];
    snprintf(name, sizeof name, "  the same, kernel for %s", sf_mlp_isa_name((sf_mlp_isa)q));
    double check = 0.0, ns = ns_per_sample(&b, GRADIENT_SHUFFLED_PACKED_ISA, &check);
    printf("%-40s %12.1f %22.17g\n", name, ns, check);
  }
  /* The same network with linear units: the kernel without its
   * exponentials and divisions, what is left of its cost when they are
   * free (a floor for any exponential). */
  sf_mlp_shape linear = shape;
  linear.hidden = linear.output = SF_ACT_LINEAR;
  b.shape = &linear;
  static const enum path linear_paths[] = {GRADIENT_COLUMNS, GRADIENT_SHUFFLED_PACKED};
  static const char *const linear_names[] = {"linear units, full batch with gradient", "linear units, shuffled packed rows"};
  for (int q = 0; q < 2; ++q) {
    double check = 0.0, ns = ns_per_sample(&b, linear_paths[q], &check);
    printf("%-40s %12.1f %22.17g\n", linear_names[q], ns, check);
  }
  sf_mlp_columns_free(&b.columns);
  sf_mlp_rows_free(&b.rows);
  sf_mlp_workspace_free(&b.ws);
  free(x);
  free(y);
  free(params);
  free(order);
  free(b.grad);
  return 0;
}
