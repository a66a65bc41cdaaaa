/* Back-propagation (fit/mlp_backward.h) against finite differences: random
 * networks of every activation and every loss, Richardson-extrapolated
 * central differences (error O(h^4)), agreement <= 1e-6 relative to the
 * gradient's size; the forward pass against a hand-computed 2-2-1 network;
 * the blocked kernel on many shuffled samples (several blocks, a partial
 * one) against the one-sample forward pass of models/mlp.h and against
 * finite differences, and read from packed rows; chunked passes against a
 * pass per chunk; the kernel compiled for
 * each instruction set this CPU runs (AVX-512F, AVX2 with FMA) against the
 * baseline one, bit for bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/mlp_backward.h"
#include "models/mlp.h"
#include "models/rng.h"
#include "tests/check.h"

static double total_loss(const sf_mlp_shape *s, double *p, const sf_mlp_loss *loss, const double *x,
                         const double *y, int n) {
  return sf_mlp_loss_range(s, p, loss, x, y, NULL, 0, n, NULL);
}

static double worst_gradient_error(const sf_mlp_shape *s, sf_mlp_loss_kind kind, uint64_t seed) {
  sf_rng rng;
  sf_rng_seed(&rng, seed, 7, 0);
  int np = sf_mlp_param_count(s), n_in = s->sizes[0], n_out = s->sizes[s->n_layers];
  enum { N = 5 };
  double *p = malloc(sizeof(double) * np), *g = calloc(np, sizeof(double));
  double x[N * 16], y[N * 16], delta[16];
  for (int k = 0; k < np; ++k) p[k] = 1.2 * (2.0 * sf_rng_uniform(&rng) - 1.0);
  for (int k = 0; k < N * n_in; ++k) x[k] = 2.0 * sf_rng_uniform(&rng) - 1.0;
  for (int k = 0; k < N * n_out; ++k) y[k] = 0.05 + sf_rng_uniform(&rng);
  for (int k = 0; k < n_out; ++k) delta[k] = 0.01;
  sf_mlp_loss loss = {kind, delta};
  sf_mlp_loss_range(s, p, &loss, x, y, NULL, 0, N, g);
  double gmax = 0.0, worst = 0.0;
  for (int k = 0; k < np; ++k) gmax = fmax(gmax, fabs(g[k]));
  for (int k = 0; k < np; ++k) {
    double d[2];
    for (int r = 0; r < 2; ++r) {
      double h = r == 0 ? 1e-3 : 5e-4, keep = p[k];
      p[k] = keep + h;
      double fp = total_loss(s, p, &loss, x, y, N);
      p[k] = keep - h;
      double fm = total_loss(s, p, &loss, x, y, N);
      p[k] = keep;
      d[r] = (fp - fm) / (2.0 * h);
    }
    double fd = (4.0 * d[1] - d[0]) / 3.0;
    double e = fabs(g[k] - fd) / fmax(fabs(fd), 1e-3 * gmax);
    worst = worst_of(worst, e);
  }
  free(p);
  free(g);
  return worst;
}

/* sf_mlp_loss_chunks_ws over begin..end-1 in chunks of 64 (the last one
 * partial) against one call per chunk, bit for bit: from packed rows
 * through index (prefetching past end), from columns, from x and y. */
static void chunked_passes(const sf_mlp_shape *s, const double *p, const sf_mlp_loss *loss, const double *x,
                           const double *y, const sf_mlp_rows *rows, const int *index, long n, long begin, long end,
                           sf_mlp_workspace *ws) {
  enum { CHUNK = 64, MAX_CHUNKS = 64 };
  int np = sf_mlp_param_count(s);
  long n_chunks = (end - begin + CHUNK - 1) / CHUNK;
  CHECK(n_chunks <= MAX_CHUNKS && (end - begin) % CHUNK != 0);
  sf_mlp_columns columns;
  CHECK(sf_mlp_columns_make(&columns, x, y, n, s->sizes[0], s->sizes[s->n_layers]) == 0);
  double *g_one = calloc((size_t)(MAX_CHUNKS * np), sizeof(double));
  double *g_all = calloc((size_t)(MAX_CHUNKS * np), sizeof(double));
  static const char *const sources[] = {"packed rows, shuffled", "columns", "x and y rows, shuffled"};
  for (int src = 0; src < 3; ++src) {
    const int *ix = src == 1 ? NULL : index;
    double l_one[MAX_CHUNKS], l_all[MAX_CHUNKS];
    memset(g_one, 0, sizeof(double) * (size_t)(MAX_CHUNKS * np));
    memset(g_all, 0, sizeof(double) * (size_t)(MAX_CHUNKS * np));
    double sum_one = 0.0;
    for (long c = 0; c < n_chunks; ++c) {
      long b = begin + c * CHUNK, e = b + CHUNK < end ? b + CHUNK : end;
      double *g = g_one + c * np;
      l_one[c] = src == 0   ? sf_mlp_loss_rows_ws(s, p, loss, rows, ix, b, e, g, ws)
                 : src == 1 ? sf_mlp_loss_columns_ws(s, p, loss, &columns, b, e, g, ws)
                            : sf_mlp_loss_range_ws(s, p, loss, x, y, ix, b, e, g, ws);
      sum_one += l_one[c];
    }
    double sum_all = sf_mlp_loss_chunks_ws(s, p, loss, src == 1 ? &columns : NULL, src == 0 ? rows : NULL, x, y, ix,
                                           begin, end, CHUNK, ix ? end + 32 : 0, l_all, g_all, ws);
    int same = memcmp(l_one, l_all, sizeof(double) * (size_t)n_chunks) == 0 &&
               memcmp(g_one, g_all, sizeof(double) * (size_t)(n_chunks * np)) == 0 &&
               memcmp(&sum_one, &sum_all, sizeof sum_one) == 0;
    printf("%s: %ld chunks in one pass, losses and gradients bit for bit a pass per chunk: %s\n", sources[src],
           n_chunks, same ? "yes" : "no");
    CHECK(same);
  }
  sf_mlp_columns_free(&columns);
  free(g_one);
  free(g_all);
}

/* 1000 samples of a 4-8-8-9 network taken through a shuffled index: the
 * loss against sf_mlp_forward + sf_mlp_sample_loss sample by sample, and
 * the gradient of a few parameters of every layer against differences. */
static void many_samples(void) {
  sf_mlp_shape s;
  sf_error err = {0};
  sf_mlp_shape_parse_layers("4,8,8,9", &s, &err);
  s.hidden = SF_ACT_SIGMOID;
  s.output = SF_ACT_EXP_NEG;
  enum { N = 1500, BEGIN = 100, END = 1101 };
  int np = sf_mlp_param_count(&s);
  double *x = malloc(sizeof(double) * N * 4), *y = malloc(sizeof(double) * N * 9);
  double *p = malloc(sizeof(double) * np), *g = calloc(np, sizeof(double));
  int *index = malloc(sizeof(int) * N);
  sf_rng rng;
  sf_rng_seed(&rng, 5, 6, 7);
  for (int k = 0; k < np; ++k) p[k] = 2.0 * sf_rng_uniform(&rng) - 1.0;
  for (int k = 0; k < N * 4; ++k) x[k] = 2.0 * sf_rng_uniform(&rng) - 1.0;
  for (int k = 0; k < N * 9; ++k) y[k] = 0.05 + sf_rng_uniform(&rng);
  for (int k = 0; k < N; ++k) index[k] = k;
  for (int k = N - 1; k > 0; --k) {
    int j = (int)(sf_rng_uniform(&rng) * (k + 1));
    int t = index[k];
    index[k] = index[j];
    index[j] = t;
  }
  double delta[9];
  for (int k = 0; k < 9; ++k) delta[k] = 0.01;
  sf_mlp_loss loss = {SF_LOSS_REL, delta};
  double want = 0.0;
  for (int i = BEGIN; i < END; ++i) {
    double out[9];
    sf_mlp_forward(&s, p, x + 4L * index[i], out);
    want += sf_mlp_sample_loss(&loss, 9, out, y + 9L * index[i], NULL);
  }
  double got = sf_mlp_loss_range(&s, p, &loss, x, y, index, BEGIN, END, g);
  printf("1001 shuffled samples, 4-8-8-9, rel loss: blocked %.17g, one by one %.17g\n", got, want);
  CHECK_REL(got, want, 1e-13);
  double worst = 0.0, gmax = 0.0;
  for (int k = 0; k < np; ++k) gmax = fmax(gmax, fabs(g[k]));
  /* 4-8-8-9 has 193 parameters: W0 0-31, b0 32-39, W1 40-103, b1 104-111,
   * W2 112-183, b2 184-192; two or more probes in each weight block, one in
   * each bias block. */
  const int probes[] = {0, 17, 39, 40, 47, 70, 107, 130, 150, np - 1};
  for (int q = 0; q < 10; ++q) {
    int k = probes[q];
    double d[2];
    for (int r = 0; r < 2; ++r) {
      double h = r == 0 ? 1e-3 : 5e-4, keep = p[k];
      p[k] = keep + h;
      double fp = sf_mlp_loss_range(&s, p, &loss, x, y, index, BEGIN, END, NULL);
      p[k] = keep - h;
      double fm = sf_mlp_loss_range(&s, p, &loss, x, y, index, BEGIN, END, NULL);
      p[k] = keep;
      d[r] = (fp - fm) / (2.0 * h);
    }
    double fd = (4.0 * d[1] - d[0]) / 3.0;
    worst = worst_of(worst, fabs(g[k] - fd) / fmax(fabs(fd), 1e-3 * gmax));
  }
  printf("1001 shuffled samples: worst rel. gradient error of 10 parameters %.3g\n", worst);
  CHECK(worst <= 1e-6);
  /* the packed rows of shuffled training (fit/mlp_backward.h): the same sums */
  sf_mlp_rows rows;
  sf_mlp_workspace ws;
  double *g_rows = calloc(np, sizeof(double));
  CHECK(sf_mlp_rows_make(&rows, x, y, N, 4, 9) == 0 && sf_mlp_workspace_init(&ws, &s) == 0);
  double got_rows = sf_mlp_loss_rows_ws(&s, p, &loss, &rows, index, BEGIN, END, g_rows, &ws);
  int same = memcmp(&got_rows, &got, sizeof got) == 0 && memcmp(g_rows, g, sizeof(double) * np) == 0;
  printf("packed rows: loss and gradient bit for bit those of x and y rows: %s\n", same ? "yes" : "no");
  CHECK(same);
  /* and on each instruction set's kernel (each its own gather transposes) */
  for (int q = SF_MLP_ISA_BASELINE; q < SF_MLP_ISA_COUNT; ++q) {
    const sf_mlp_isa isa = (sf_mlp_isa)q;
    if (!sf_mlp_isa_available(isa)) {
      printf("packed rows: skip %s: not on this CPU or build\n", sf_mlp_isa_name(isa));
      continue;
    }
    memset(g_rows, 0, sizeof(double) * np);
    got_rows = sf_mlp_loss_rows_isa(isa, &s, p, &loss, &rows, index, BEGIN, END, g_rows);
    same = memcmp(&got_rows, &got, sizeof got) == 0 && memcmp(g_rows, g, sizeof(double) * np) == 0;
    printf("packed rows, %s kernel: bit for bit: %s\n", sf_mlp_isa_name(isa), same ? "yes" : "no");
    CHECK(same);
  }
  chunked_passes(&s, p, &loss, x, y, &rows, index, N, BEGIN, END, &ws);
  sf_mlp_rows_free(&rows);
  sf_mlp_workspace_free(&ws);
  free(g_rows);
  free(x);
  free(y);
  free(p);
  free(g);
  free(index);
}

/* Loss and gradient of every activation and loss, over shuffled samples
 * (several groups and a partial one), on each instruction set: the same
 * bits as the baseline kernel (fit/mlp_backward.h). */
static void same_bits_on_every_isa(void) {
  enum { N = 300 };
  double x[N * 4], y[N * 9], delta[9];
  int index[N];
  sf_rng rng;
  sf_rng_seed(&rng, 11, 12, 13);
  for (int k = 0; k < N * 4; ++k) x[k] = 3.0 * (2.0 * sf_rng_uniform(&rng) - 1.0);
  for (int k = 0; k < N * 9; ++k) y[k] = 0.05 + sf_rng_uniform(&rng);
  for (int k = 0; k < 9; ++k) delta[k] = 0.01;
  for (int k = 0; k < N; ++k) index[k] = (int)((k * 7919L) % N);
  /* every build but the baseline itself */
  for (int q = SF_MLP_ISA_BASELINE + 1; q < SF_MLP_ISA_COUNT; ++q) {
    const sf_mlp_isa isa = (sf_mlp_isa)q;
    const char *name = sf_mlp_isa_name(isa);
    if (!sf_mlp_isa_available(isa)) {
      printf("skip %s: not on this CPU or build\n", name);
      continue;
    }
    int cases = 0, same = 0;
    for (int hidden = SF_ACT_SIGMOID; hidden <= SF_ACT_LINEAR; ++hidden)
      for (int output = SF_ACT_SIGMOID; output <= SF_ACT_EXP_NEG_EXP; ++output)
        for (int kind = SF_LOSS_MSE; kind <= SF_LOSS_LOG; ++kind) {
          if (kind == SF_LOSS_LOG && (output == SF_ACT_LINEAR || output == SF_ACT_TANH || output == SF_ACT_RELU))
            continue;
          sf_mlp_shape s;
          sf_error err = {0};
          sf_mlp_shape_parse_layers("4,8,8,9", &s, &err);
          s.hidden = (sf_mlp_activation)hidden;
          s.output = (sf_mlp_activation)output;
          double p[193], g_base[193] = {0}, g_isa[193] = {0};
          for (int k = 0; k < 193; ++k) p[k] = 2.0 * sf_rng_uniform(&rng) - 1.0;
          sf_mlp_loss loss = {(sf_mlp_loss_kind)kind, delta};
          double l_base = sf_mlp_loss_range_isa(SF_MLP_ISA_BASELINE, &s, p, &loss, x, y, index, 3, N - 2, g_base);
          double l_isa = sf_mlp_loss_range_isa(isa, &s, p, &loss, x, y, index, 3, N - 2, g_isa);
          cases += 1;
          same += memcmp(&l_base, &l_isa, sizeof l_base) == 0 && memcmp(g_base, g_isa, sizeof g_base) == 0 &&
                  isfinite(l_base);
        }
    printf("%s kernel: loss and gradient bit for bit the baseline's in %d of %d networks\n", name, same,
           cases);
    CHECK(same == cases);
    /* Saturated units: weights up to 300 put the exponentials' arguments
     * in the thousands, past both clamps (sigmoid 0 and 1, exp_neg outputs
     * at e^-708 and e^709). */
    int saturated_same = 0;
    for (int trial = 0; trial < 4; ++trial) {
      sf_mlp_shape s;
      sf_error err = {0};
      sf_mlp_shape_parse_layers("4,8,8,9", &s, &err);
      s.hidden = SF_ACT_SIGMOID;
      s.output = trial % 2 ? SF_ACT_EXP_NEG : SF_ACT_EXP_NEG_EXP;
      double p[193], g_base[193] = {0}, g_isa[193] = {0};
      for (int k = 0; k < 193; ++k) p[k] = 300.0 * (2.0 * sf_rng_uniform(&rng) - 1.0);
      sf_mlp_loss loss = {SF_LOSS_REL, delta};
      double l_base = sf_mlp_loss_range_isa(SF_MLP_ISA_BASELINE, &s, p, &loss, x, y, index, 3, N - 2, g_base);
      double l_isa = sf_mlp_loss_range_isa(isa, &s, p, &loss, x, y, index, 3, N - 2, g_isa);
      saturated_same += memcmp(&l_base, &l_isa, sizeof l_base) == 0 && memcmp(g_base, g_isa, sizeof g_base) == 0;
    }
    printf("%s kernel, saturated units: bit for bit the baseline's in %d of 4 networks\n", name, saturated_same);
    CHECK(saturated_same == 4);
  }
}

int main(void) {
  /* Forward pass by hand: 2-2-1, sigmoid hidden, exp_neg output. */
  sf_mlp_shape s = {2, {2, 2, 1}, SF_ACT_SIGMOID, SF_ACT_EXP_NEG};
  double p[9] = {0.5, -1.0, 2.0, 0.25, /* W0 */ 0.1, -0.2, /* b0 */ 1.5, -0.7, /* W1 */ 0.3 /* b1 */};
  double x[2] = {0.4, -0.3}, out;
  sf_mlp_forward(&s, p, x, &out);
  double a0 = 1.0 / (1.0 + exp(-(0.5 * 0.4 - 1.0 * -0.3 + 0.1)));
  double a1 = 1.0 / (1.0 + exp(-(2.0 * 0.4 + 0.25 * -0.3 - 0.2)));
  CHECK_REL(out, exp(-(1.5 * a0 - 0.7 * a1 + 0.3)), 1e-15);

  static const char *const shapes[] = {"2,4,3", "4,8,8,3", "3,5,2", "4,8,8,9", "1,3,3,3,1"};
  int worst_ok = 1;
  for (int sh = 0; sh < 5; ++sh)
    for (int hidden = SF_ACT_SIGMOID; hidden <= SF_ACT_LINEAR; ++hidden)
      for (int output = SF_ACT_SIGMOID; output <= SF_ACT_EXP_NEG_EXP; ++output)
        for (int kind = SF_LOSS_MSE; kind <= SF_LOSS_LOG; ++kind) {
          if (kind == SF_LOSS_LOG && (output == SF_ACT_LINEAR || output == SF_ACT_TANH || output == SF_ACT_RELU))
            continue;   /* log needs a positive output */
          sf_mlp_shape shape;
          sf_error err = {0};
          sf_mlp_shape_parse_layers(shapes[sh], &shape, &err);
          shape.hidden = (sf_mlp_activation)hidden;
          shape.output = (sf_mlp_activation)output;
          double e = worst_gradient_error(&shape, (sf_mlp_loss_kind)kind, (uint64_t)(sh * 100 + hidden * 10 + output));
          int ok = e <= 1e-6;
          if (!ok || sh == 1)
            printf("%s %-10s hidden %-8s output %-8s loss %-4s worst rel. gradient error %.3g\n", ok ? "ok  " : "FAIL",
                   shapes[sh], sf_mlp_activation_name(shape.hidden), sf_mlp_activation_name(shape.output),
                   sf_mlp_loss_name((sf_mlp_loss_kind)kind), e);
          worst_ok &= ok;
          CHECK(e <= 1e-6);
        }
  printf("all gradient checks within 1e-6: %s\n", worst_ok ? "yes" : "no");
  many_samples();
  same_bits_on_every_isa();
  return check_summary();
}
