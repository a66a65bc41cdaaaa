/* The training kernel's inside (fit/mlp_backward.h), shared by its four
 * builds and their caller; no other file includes this.
 *
 * The kernel (fit/mlp_kernel_body.h) is compiled once per instruction set,
 * each in its own file with its own compiler flags (CMakeLists.txt):
 * fit/mlp_kernel_avx512.c (-mavx512f), fit/mlp_kernel_avx2.c (-mavx2
 * -mfma) and fit/mlp_kernel_baseline.c (no flags: any x86-64, its
 * multiply-adds by fit/mlp_lanes_fma.h; any other CPU), and
 * fit/mlp_kernel_avx512_newton.c, AVX-512 with half the sigmoids'
 * divisions by multiply-adds (Intel's slow divider).
 * fit/mlp_backward.c picks one at run time: the binary runs on any x86-64
 * without -march. A whole file per instruction set, not a function
 * attribute, because fit/mlp_lanes.h chooses its representation of 8 lanes
 * by the flags it is compiled with (AVX2: two 4-lane registers, through
 * intrinsics; GCC's generic 8-lane vectors became scalar compares and stack
 * spills there, 7x slower than AVX-512 per sample). */
#ifndef SKYFIT_FIT_MLP_KERNEL_H
#define SKYFIT_FIT_MLP_KERNEL_H

#include <math.h>

#include "fit/mlp_backward.h"

/* Sums over samples end in LANES lanes: sample begin + LANES m + k of a
 * call is added to lane k, in the order of m (fit/mlp_backward.h). */
#define LANES 8
/* Samples go through the network VECS vectors of LANES at a time (a group
 * of GROUP samples): VECS independent dependency chains through the
 * exponentials and divisions keep the floating-point units busy, and each
 * gradient lane is loaded and stored once per group. Vector v of a group
 * holds the group's samples LANES v .. LANES v + LANES - 1, added to the
 * lanes in the order of v: the same sums as one vector at a time. A build
 * may take fewer (SF_MLP_KERNEL_VECS, fit/mlp_kernel_baseline.c): the
 * workspace, laid out by the caller for 4, holds its smaller group. */
#if defined(SF_MLP_KERNEL_VECS)
#define VECS SF_MLP_KERNEL_VECS
#else
#define VECS 4
#endif
_Static_assert(VECS >= 1 && VECS <= 4, "a group of at most 4 vectors: the workspace is laid out for 4");
#define GROUP (VECS * LANES)
/* Rows of a layer computed together (ROWS VECS accumulator chains, each
 * input vector loaded once for them; in propagation, ROWS units of the
 * layer below): two where AVX-512's 32 registers hold them, one on AVX2's
 * 16 (each of its lanes two registers). Measured on a Zen 5, one core,
 * with the output sums in registers too: 4,8,8,9 full batch 33.3-33.9 ->
 * 29.4-30.5 ns per sample (then 26.5-27.8 with the exponentials side by
 * side, fit/mlp_lanes.h). Any ROWS gives the same sums: the order of each
 * lane's operations does not change. */
#if defined(__AVX512F__)
#define ROWS 2
#else
#define ROWS 1
#endif
/* Groups of shuffled rows asked for ahead of the one computing
 * (SF_MLP_PREFETCH_AHEAD, fit/mlp_backward.h). */
#define PREFETCH_GROUPS (SF_MLP_PREFETCH_AHEAD / GROUP)
_Static_assert(SF_MLP_PREFETCH_AHEAD % GROUP == 0, "SF_MLP_PREFETCH_AHEAD is whole groups");

/* Where a workspace's arrays lie in ws->mem, each a multiple of LANES
 * doubles (so 64-byte aligned): act[l] (sizes[l] x GROUP, l = 0..L: the
 * inputs then every layer's outputs), target (n_out x GROUP), two delta
 * arrays (widest layer x GROUP), grad (n_params x LANES: the lanes of every
 * gradient entry, flat parameter order). */
typedef struct group_arrays {
  double *act[SF_MLP_MAX_LAYERS + 1];
  double *target, *delta[2], *grad;
} group_arrays;

/* Doubles of the arrays; fills g (if not NULL) with pointers into mem. */
static inline long group_layout(const sf_mlp_shape *s, double *mem, group_arrays *g) {
  long act[SF_MLP_MAX_LAYERS + 1], at = 0;
  int widest = 1;
  for (int l = 0; l <= s->n_layers; ++l) {
    act[l] = at;
    at += (long)s->sizes[l] * GROUP;
    if (l > 0 && s->sizes[l] > widest) widest = s->sizes[l];
  }
  long target = at;
  at += (long)s->sizes[s->n_layers] * GROUP;
  long delta0 = at;
  at += (long)widest * GROUP;
  long delta1 = at;
  at += (long)widest * GROUP;
  long grad = at;
  at += (long)sf_mlp_param_count(s) * LANES;
  if (g) {
    for (int l = 0; l <= s->n_layers; ++l) g->act[l] = mem + act[l];
    g->target = mem + target;
    g->delta[0] = mem + delta0;
    g->delta[1] = mem + delta1;
    g->grad = mem + grad;
  }
  return at;
}


/* Residual e and de/dpred of one output (fit/mlp_backward.h). */
static inline double residual(sf_mlp_loss_kind kind, double delta, double pred, double target, double *de) {
  switch (kind) {
    case SF_LOSS_REL: {
      double w = 1.0 / (fabs(target) + delta);
      *de = w;
      return (pred - target) * w;
    }
    case SF_LOSS_LOG: {
      double p = pred + delta;
      /* A non-positive p (possible only with an output that can go
       * negative) is held at a tiny value: the loss stays finite and
       * large, and pushes p up. */
      if (p < 1e-300) p = 1e-300;
      *de = 1.0 / p;
      return log(p) - log(target + delta);
    }
    default:
      *de = 1.0;
      return pred - target;
  }
}

/* What one call of the kernel computes: the loss of samples begin..end-1
 * (through index when not NULL) and, when grad is not NULL, its gradient
 * added to grad. Sample i's inputs at x + i xs and targets at y + i ys, or
 * columns (then x, y and index are unused).
 * chunk > 0 (a multiple of GROUP) splits begin..end-1 into consecutive
 * chunks of that many samples (the last may be shorter), each summed as if
 * by a call of its own: chunk k's loss goes to chunk_loss[k] and its
 * gradient is added to grad + k n_params; the call returns their sum in
 * chunk order. One call instead of one per chunk keeps the shuffled rows'
 * prefetches running across chunk boundaries and sets up once.
 * prefetch_end > end (shuffled rows): samples end..prefetch_end-1, the next
 * call's first, are asked for early too. */
typedef struct sf_mlp_kernel_args {
  const sf_mlp_shape *shape;
  const double *params;
  const sf_mlp_loss *loss;
  const double *x, *y;
  long xs, ys;
  const int *index;
  const sf_mlp_columns *columns;
  long begin, end;
  double *grad;
  sf_mlp_workspace *ws;
  long chunk;            /* <= 0: one sum over begin..end-1 */
  double *chunk_loss;    /* with chunk > 0 */
  long prefetch_end;     /* <= end: none past end */
} sf_mlp_kernel_args;

double sf_mlp_kernel_baseline(const sf_mlp_kernel_args *a);
/* Each build's exponential (sf_mlp_exp_isa's work, fit/mlp_kernel_body.h). */
void sf_mlp_kernel_baseline_exp(const double *x, double *out, long n, double cap);
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
double sf_mlp_kernel_avx2(const sf_mlp_kernel_args *a);
double sf_mlp_kernel_avx512(const sf_mlp_kernel_args *a);
double sf_mlp_kernel_avx512_newton(const sf_mlp_kernel_args *a);
void sf_mlp_kernel_avx2_exp(const double *x, double *out, long n, double cap);
void sf_mlp_kernel_avx512_exp(const double *x, double *out, long n, double cap);
void sf_mlp_kernel_avx512_newton_exp(const double *x, double *out, long n, double cap);
/* sf_mlp_reciprocals_newton's work (fit/mlp_kernel_avx512_newton.c). */
void sf_mlp_reciprocals_avx512(const double *d, double *out, long n);
#endif

#endif
