/* Before any include: madvise (MADV_HUGEPAGE) is a Linux extension. */
#define _DEFAULT_SOURCE
#include "fit/mlp_backward.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "fit/mlp_kernel.h"

/* Columns are padded so that a group may read past the last sample. */
#define COLUMNS_PAD 256
/* Memory alignment of the lane arrays: one 64-byte line per 8 doubles. */
#define ALIGN_BYTES 64
/* A transparent huge page (x86-64 Linux) */
#define HUGE_PAGE ((size_t)2 << 20)

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
    double de, e = residual(loss->kind, loss->delta ? loss->delta[k] : 0.0, pred[k], target[k], &de);
    sum += e * e;
    if (dloss_dpred) dloss_dpred[k] = 2.0 * e * de * inv_n;
  }
  return sum * inv_n;
}

int sf_mlp_workspace_init(sf_mlp_workspace *ws, const sf_mlp_shape *shape) {
  long doubles = group_layout(shape, NULL, NULL);
  ws->shape = *shape;
  ws->block = GROUP;
  /* aligned_alloc wants a size that is a multiple of the alignment: every
   * array is a multiple of LANES doubles = 64 bytes. */
  ws->mem = aligned_alloc(ALIGN_BYTES, (size_t)doubles * sizeof(double));
  return ws->mem ? 0 : -1;
}

void sf_mlp_workspace_free(sf_mlp_workspace *ws) {
  free(ws->mem);
  ws->mem = NULL;
}

int sf_mlp_isa_available(sf_mlp_isa isa) {
  switch (isa) {
    case SF_MLP_ISA_AUTO:
    case SF_MLP_ISA_BASELINE: return 1;
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
    case SF_MLP_ISA_AVX2_FMA: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SF_MLP_ISA_AVX512:
    case SF_MLP_ISA_AVX512_NEWTON: return __builtin_cpu_supports("avx512f");
#endif
    default: return 0;
  }
}

const char *sf_mlp_isa_name(sf_mlp_isa isa) {
  static const char *const names[SF_MLP_ISA_COUNT] = {"auto", "baseline x86-64", "AVX2+FMA", "AVX-512F",
                                                      "AVX-512F+Newton"};
  return (unsigned)isa < SF_MLP_ISA_COUNT ? names[isa] : "?";
}

sf_mlp_isa sf_mlp_isa_auto(void) {
  if (sf_mlp_isa_available(SF_MLP_ISA_AVX512)) {
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
    if (__builtin_cpu_is("intel")) return SF_MLP_ISA_AVX512_NEWTON;
#endif
    return SF_MLP_ISA_AVX512;
  }
  return sf_mlp_isa_available(SF_MLP_ISA_AVX2_FMA) ? SF_MLP_ISA_AVX2_FMA : SF_MLP_ISA_BASELINE;
}

int sf_mlp_reciprocals_newton(const double *d, double *out, long n) {
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
  if (sf_mlp_isa_available(SF_MLP_ISA_AVX512_NEWTON)) {
    sf_mlp_reciprocals_avx512(d, out, n);
    return 1;
  }
#endif
  (void)d, (void)out, (void)n;
  return 0;
}

int sf_mlp_exp_isa(sf_mlp_isa isa, const double *x, double *out, long n, double cap) {
  if (isa == SF_MLP_ISA_AUTO) isa = sf_mlp_isa_auto();
  if (!sf_mlp_isa_available(isa)) return 0;
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
  if (isa == SF_MLP_ISA_AVX512) sf_mlp_kernel_avx512_exp(x, out, n, cap);
  if (isa == SF_MLP_ISA_AVX512_NEWTON) sf_mlp_kernel_avx512_newton_exp(x, out, n, cap);
  if (isa == SF_MLP_ISA_AVX2_FMA) sf_mlp_kernel_avx2_exp(x, out, n, cap);
#endif
  if (isa == SF_MLP_ISA_BASELINE) sf_mlp_kernel_baseline_exp(x, out, n, cap);
  return 1;
}

static double loss_groups_isa(sf_mlp_isa isa, const sf_mlp_kernel_args *a) {
  if (isa == SF_MLP_ISA_AUTO) isa = sf_mlp_isa_auto();
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
  if (isa == SF_MLP_ISA_AVX512) return sf_mlp_kernel_avx512(a);
  if (isa == SF_MLP_ISA_AVX512_NEWTON) return sf_mlp_kernel_avx512_newton(a);
  if (isa == SF_MLP_ISA_AVX2_FMA) return sf_mlp_kernel_avx2(a);
#endif
  return sf_mlp_kernel_baseline(a);
}

static double loss_groups(const sf_mlp_kernel_args *a) { return loss_groups_isa(SF_MLP_ISA_AUTO, a); }

double sf_mlp_loss_range_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                            const double *x, const double *y, const int *index, long begin, long end,
                            double *grad, sf_mlp_workspace *ws) {
  sf_mlp_kernel_args a = {s, params, loss, x, y, s->sizes[0], s->sizes[s->n_layers], index, NULL, begin, end, grad, ws, 0, NULL, 0};
  return loss_groups(&a);
}

/* 64-byte aligned, zeroed (NULL when out of memory). */
static double *aligned_zeros(long n) {
  size_t bytes = ((size_t)n * sizeof(double) + ALIGN_BYTES - 1) / ALIGN_BYTES * ALIGN_BYTES;
  double *p = aligned_alloc(ALIGN_BYTES, bytes);
  if (p) memset(p, 0, bytes);
  return p;
}

int sf_mlp_columns_make(sf_mlp_columns *c, const double *x, const double *y, long n, int n_in, int n_out) {
  /* A group may read up to GROUP - 1 samples past the last one. */
  c->n = n;
  c->stride = (n + COLUMNS_PAD - 1) / COLUMNS_PAD * COLUMNS_PAD + COLUMNS_PAD;
  c->n_in = n_in;
  c->n_out = n_out;
  c->x = aligned_zeros((n_in + 1) * c->stride);
  c->y = aligned_zeros(n_out * c->stride);
  if (!c->x || !c->y) {
    sf_mlp_columns_free(c);
    return -1;
  }
  for (long i = 0; i < n; ++i) {
    for (int j = 0; j < n_in; ++j) c->x[j * c->stride + i] = x[i * n_in + j];
    for (int k = 0; k < n_out; ++k) c->y[k * c->stride + i] = y[i * n_out + k];
  }
  for (long i = 0; i < c->stride; ++i) c->x[n_in * c->stride + i] = 1.0;
  return 0;
}

void sf_mlp_columns_free(sf_mlp_columns *c) {
  free(c->x);
  free(c->y);
  c->x = c->y = NULL;
}

int sf_mlp_rows_make(sf_mlp_rows *r, const double *x, const double *y, long n, int n_in, int n_out) {
  r->n = n;
  r->n_in = n_in;
  r->n_out = n_out;
  r->stride = (n_in + n_out + LANES - 1) / LANES * LANES;
  /* Shuffled rows of a large set miss the TLB too: in 2 MiB pages where
   * the system grants them (Linux transparent huge pages on request). */
  size_t bytes = ((size_t)n * (size_t)r->stride * sizeof(double) + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
  r->data = aligned_alloc(HUGE_PAGE, bytes);
  if (!r->data) return -1;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  madvise(r->data, bytes, MADV_HUGEPAGE);   /* a hint: without it, 4 KiB pages */
#endif
  memset(r->data, 0, bytes);
  for (long i = 0; i < n; ++i) {
    memcpy(r->data + i * r->stride, x + i * n_in, (size_t)n_in * sizeof(double));
    memcpy(r->data + i * r->stride + n_in, y + i * n_out, (size_t)n_out * sizeof(double));
  }
  return 0;
}

void sf_mlp_rows_free(sf_mlp_rows *r) {
  free(r->data);
  r->data = NULL;
}

double sf_mlp_loss_rows_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss, const sf_mlp_rows *r,
                           const int *index, long begin, long end, double *grad, sf_mlp_workspace *ws) {
  sf_mlp_kernel_args a = {s, params, loss, r->data, r->data + r->n_in, r->stride, r->stride, index, NULL, begin, end,
                          grad, ws, 0, NULL, 0};
  return loss_groups(&a);
}

double sf_mlp_loss_columns_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                              const sf_mlp_columns *c, long begin, long end, double *grad, sf_mlp_workspace *ws) {
  sf_mlp_kernel_args a = {s, params, loss, NULL, NULL, 0, 0, NULL, c, begin, end, grad, ws, 0, NULL, 0};
  return loss_groups(&a);
}

double sf_mlp_loss_chunks_ws(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                             const sf_mlp_columns *columns, const sf_mlp_rows *rows, const double *x,
                             const double *y, const int *index, long begin, long end, long chunk,
                             long prefetch_end, double *chunk_loss, double *grad, sf_mlp_workspace *ws) {
  sf_mlp_kernel_args a = {s,     params, loss, x,  y,     s->sizes[0], s->sizes[s->n_layers], index, NULL,
                          begin, end,    grad, ws, chunk, chunk_loss,  prefetch_end};
  if (columns && columns->x && !index) {
    a.columns = columns;
    a.x = a.y = NULL;
  } else if (rows && rows->data) {
    a.x = rows->data;
    a.y = rows->data + rows->n_in;
    a.xs = a.ys = rows->stride;
  }
  return loss_groups(&a);
}

/* The kernel for isa on a, with a workspace of its own. */
static double loss_isa_own_workspace(sf_mlp_isa isa, sf_mlp_kernel_args *a) {
  if (!sf_mlp_isa_available(isa)) return NAN;
  sf_mlp_workspace ws;
  if (sf_mlp_workspace_init(&ws, a->shape)) return NAN;
  a->ws = &ws;
  double total = loss_groups_isa(isa, a);
  sf_mlp_workspace_free(&ws);
  return total;
}

double sf_mlp_loss_range_isa(sf_mlp_isa isa, const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                             const double *x, const double *y, const int *index, long begin, long end,
                             double *grad) {
  sf_mlp_kernel_args a = {s, params, loss, x, y, s->sizes[0], s->sizes[s->n_layers], index, NULL, begin, end, grad, NULL, 0, NULL, 0};
  return loss_isa_own_workspace(isa, &a);
}

double sf_mlp_loss_rows_isa(sf_mlp_isa isa, const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                            const sf_mlp_rows *r, const int *index, long begin, long end, double *grad) {
  sf_mlp_kernel_args a = {s, params, loss, r->data, r->data + r->n_in, r->stride, r->stride, index, NULL, begin, end,
                          grad, NULL, 0, NULL, 0};
  return loss_isa_own_workspace(isa, &a);
}

double sf_mlp_loss_range(const sf_mlp_shape *s, const double *params, const sf_mlp_loss *loss,
                         const double *x, const double *y, const int *index, long begin, long end,
                         double *grad) {
  return sf_mlp_loss_range_isa(SF_MLP_ISA_AUTO, s, params, loss, x, y, index, begin, end, grad);
}
