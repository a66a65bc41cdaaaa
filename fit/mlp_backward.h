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
 * p_k > -delta_k: use it with a positive output (exp_neg, sigmoid).
 *
 * Speed. Samples go through the whole network a group of 32 at a time, as
 * 4 vectors of 8 lanes (fit/mlp_lanes.h: one AVX-512 register, two AVX2 or
 * four SSE2 ones), layer by layer, two units at a time with AVX-512 (each
 * input vector loaded once for both), with every accumulator in registers:
 * a unit's weighted sum across its inputs, a delta's sum across the units
 * above, and a gradient entry's 8 lanes, loaded and stored once per group
 * (gradient lanes are accumulated directly, G[p][lane] += d * a, with no
 * per-block fold). The vectors are independent dependency chains through
 * the exponentials (table-driven, fit/mlp_lanes.h; those of a pass
 * evaluated side by side) and divisions (on Intel half of a sigmoid
 * pass's by multiply-adds, fit/mlp_lanes_reciprocal.h: the same bits).
 * Summation order, fixed by the samples alone: sample begin + 8 m + k of a
 * call is added to lane k in the order of m (its loss and its gradient
 * products), and the 8 lanes are added in a fixed tree at the end. So the
 * result does not depend on the vector width the CPU offers (the kernel
 * is compiled for AVX-512, AVX2 with FMA and baseline x86-64 and picked at
 * run time, fit/mlp_kernel.h; every multiply-add of the layers and the
 * exponential is fused, on each of them, and nothing else is) nor on who
 * calls. */
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

/* Shuffled samples whose rows the kernel asks for ahead of the group it
 * computes: two groups. Measured on a Zen 5 (4,8,8,9, 983,040 shuffled
 * packed rows, 186 ns to memory): one group ahead 30.5-31.4 ns per
 * sample, two 27.7-28.0, three 28.2-28.8. */
#define SF_MLP_PREFETCH_AHEAD 64

/* Scratch memory of the group computation for one network shape (one per
 * thread): a group's activations and deltas and the gradient lanes, a few
 * KiB to tens of KiB. block: samples per group (32). */
typedef struct sf_mlp_workspace {
  sf_mlp_shape shape;
  int block;
  double *mem;
} sf_mlp_workspace;

/* -1 when out of memory. */
int sf_mlp_workspace_init(sf_mlp_workspace *ws, const sf_mlp_shape *shape);
void sf_mlp_workspace_free(sf_mlp_workspace *ws);

/* Sum over samples s = index[begin..end-1] (index NULL: s = begin..end-1) of
 * the sample loss; x is row-major n x sizes[0], y n x sizes[n_layers]. If
 * grad is not NULL, adds the gradient of that sum (flat parameter order of
 * models/mlp.h) to grad[0..n_params-1]. The summation order is fixed by the
 * samples alone (see above). ws was made for this shape. */
double sf_mlp_loss_range_ws(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                            const double *x, const double *y, const int *index, long begin, long end,
                            double *grad, sf_mlp_workspace *ws);

/* A data set stored unit-major for passes over contiguous samples without
 * gathering rows (full batches, validation): x holds n_in rows and a row of
 * ones (the biases' input), y n_out rows, each stride long (zero padded past
 * n; 64-byte aligned). The same sums as sf_mlp_loss_range_ws with index
 * NULL. */
typedef struct sf_mlp_columns {
  long n, stride;
  int n_in, n_out;
  double *x, *y;   /* owned */
} sf_mlp_columns;

/* From row-major x (n x n_in) and y (n x n_out); -1 when out of memory. */
int sf_mlp_columns_make(sf_mlp_columns *c, const double *x, const double *y, long n, int n_in, int n_out);
void sf_mlp_columns_free(sf_mlp_columns *c);
/* Samples begin..end-1 of c. */
double sf_mlp_loss_columns_ws(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                              const sf_mlp_columns *c, long begin, long end, double *grad, sf_mlp_workspace *ws);

/* A data set stored packed for shuffled passes: sample i's inputs then its
 * targets at data + i stride, stride a whole number of 64-byte lines (16
 * doubles for 4 inputs and 9 targets: 2 lines, where separate x and y rows
 * cost 3; gathering shuffled rows is bound by the lines fetched), in huge
 * pages where Linux grants them (fewer TLB misses). The same sums as
 * sf_mlp_loss_range_ws. Measured, a shuffled pass with gradient over
 * 967,680 samples of 4-8-8-9 on a 2-core Xeon: 119 ns per sample from x
 * and y, 85 from the packed rows (rows in order: 77). */
typedef struct sf_mlp_rows {
  long n, stride;
  int n_in, n_out;
  double *data;   /* owned; 2 MiB aligned */
} sf_mlp_rows;

/* From row-major x (n x n_in) and y (n x n_out); -1 when out of memory. */
int sf_mlp_rows_make(sf_mlp_rows *r, const double *x, const double *y, long n, int n_in, int n_out);
void sf_mlp_rows_free(sf_mlp_rows *r);
/* Samples index[begin..end-1] (index NULL: begin..end-1) of r. */
double sf_mlp_loss_rows_ws(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                           const sf_mlp_rows *r, const int *index, long begin, long end, double *grad,
                           sf_mlp_workspace *ws);

/* The sums of one of the three above (columns when given and index is
 * NULL, else rows when given, else x and y) over consecutive chunks of
 * `chunk` samples of begin..end-1 (chunk a multiple of 32; the last chunk
 * may be shorter), in one pass: chunk k's loss in chunk_loss[k] and, if
 * grad, its gradient added to grad + k n_params; returns their sum in chunk
 * order. The same bits as a call per chunk. One pass sets up once and keeps
 * the shuffled rows' prefetches running from chunk to chunk, and on to
 * samples index[end..prefetch_end-1], the next pass's first (prefetch_end
 * <= end: none). */
double sf_mlp_loss_chunks_ws(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                             const sf_mlp_columns *columns, const sf_mlp_rows *rows, const double *x,
                             const double *y, const int *index, long begin, long end, long chunk,
                             long prefetch_end, double *chunk_loss, double *grad, sf_mlp_workspace *ws);

/* The same with a workspace of its own (allocated and freed here; NAN when
 * out of memory). */
double sf_mlp_loss_range(const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                         const double *x, const double *y, const int *index, long begin, long end,
                         double *grad);

/* The instruction sets the kernel is compiled for (x86-64 with GCC or
 * Clang: fit/mlp_kernel.h; the baseline elsewhere). AVX512_NEWTON is
 * AVX-512 with half of each sigmoid layer's divisions done by multiply-adds
 * (fit/mlp_lanes_reciprocal.h: the same bits), for Intel's divider. AUTO:
 * the widest the CPU offers, what every function above runs: on an Intel
 * CPU with AVX-512, AVX512_NEWTON (measured on a Xeon, one core: 2,4,3 full
 * batch with gradient 7.8 -> 7.3 ns per sample, 4,8,8,9 shuffled 46.7-48.2
 * -> 43.0); on others AVX512 (AMD's Zen 4 and 5 divide 8 lanes in 8.6 and 3.8
 * cycles, and their multiply-add ports are the kernel's bound). */
typedef enum sf_mlp_isa {
  SF_MLP_ISA_AUTO = 0,
  SF_MLP_ISA_BASELINE,
  SF_MLP_ISA_AVX2_FMA,
  SF_MLP_ISA_AVX512,
  SF_MLP_ISA_AVX512_NEWTON,
  SF_MLP_ISA_COUNT   /* not a build: BASELINE..COUNT-1 are every build */
} sf_mlp_isa;
/* "baseline x86-64", "AVX2+FMA", "AVX-512F", "AVX-512F+Newton" ("auto"). */
const char *sf_mlp_isa_name(sf_mlp_isa isa);
/* Whether this build and this CPU can run isa. */
int sf_mlp_isa_available(sf_mlp_isa isa);
/* What AUTO runs on this CPU. */
sf_mlp_isa sf_mlp_isa_auto(void);
/* out[i] = 1 / d[i], i < n (1 <= d[i] <= 2^1020), by AVX512_NEWTON's
 * multiply-adds (tests: the bits of the division); 0, writing nothing,
 * where AVX512_NEWTON is not available, else 1. */
int sf_mlp_reciprocals_newton(const double *d, double *out, long n);
/* out[i] = e^x[i], i < n, x clamped to [-708, cap] (cap <= 709), by the
 * exponential of the kernel compiled for isa (fit/mlp_lanes.h's
 * sf_lanes_exp_n_capped; tests: the same bits on every build); 0, writing
 * nothing, where isa is not available, else 1. */
int sf_mlp_exp_isa(sf_mlp_isa isa, const double *x, double *out, long n, double cap);
/* sf_mlp_loss_range on the kernel compiled for isa (tests: the same bits on
 * each); NAN if it is not available. */
double sf_mlp_loss_range_isa(sf_mlp_isa isa, const sf_mlp_shape *shape, const double *params,
                             const sf_mlp_loss *loss, const double *x, const double *y, const int *index,
                             long begin, long end, double *grad);
/* sf_mlp_loss_rows_ws likewise (the packed rows' gather and transposes). */
double sf_mlp_loss_rows_isa(sf_mlp_isa isa, const sf_mlp_shape *shape, const double *params, const sf_mlp_loss *loss,
                            const sf_mlp_rows *rows, const int *index, long begin, long end, double *grad);

#endif
