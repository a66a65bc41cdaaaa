/* The block's layout (fit/lm_gram.h) and the pick of a build of its Gram
 * matrix (fit/lm_gram_body.h) by the CPU, as the training kernel's
 * (fit/mlp_backward.c). */
#include "fit/lm_gram.h"

void sf_lm_gram_baseline(const sf_mlp_shape *s, const double *g, const double *a, int vecs, double *scratch, double *A);
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
void sf_lm_gram_avx2(const sf_mlp_shape *s, const double *g, const double *a, int vecs, double *scratch, double *A);
void sf_lm_gram_avx512(const sf_mlp_shape *s, const double *g, const double *a, int vecs, double *scratch, double *A);
#endif

int sf_lm_gram_unit(const sf_mlp_shape *s, int l, int i) {
  int u = 0;
  for (int k = 0; k < l; ++k) u += s->sizes[k + 1];
  return u + i;
}

int sf_lm_gram_units(const sf_mlp_shape *s) { return sf_lm_gram_unit(s, s->n_layers, 0); }

int sf_lm_gram_input_row(const sf_mlp_shape *s, int l, int j) {
  int r = 0;
  for (int k = 0; k < l; ++k) r += s->sizes[k] + 1;
  return r + j;
}

int sf_lm_gram_input_rows(const sf_mlp_shape *s) { return sf_lm_gram_input_row(s, s->n_layers, 0); }

long sf_lm_gram_scratch_size(const sf_mlp_shape *s) {
  int widest = 0;
  for (int l = 0; l < s->n_layers; ++l)
    if (s->sizes[l] > widest) widest = s->sizes[l];
  return (long)(widest + 1) * SF_LM_GRAM_BLOCK;
}

void sf_lm_add_block_gram_isa(sf_mlp_isa isa, const sf_mlp_shape *s, const double *g, const double *a, int n,
                              double *scratch, double *A) {
  int vecs = (n + 7) / 8;
  if (isa == SF_MLP_ISA_AUTO) isa = sf_mlp_isa_auto();
#if defined(SKYFIT_MLP_KERNEL_DISPATCH)
  if (isa == SF_MLP_ISA_AVX512 || isa == SF_MLP_ISA_AVX512_NEWTON) {
    sf_lm_gram_avx512(s, g, a, vecs, scratch, A);
    return;
  }
  if (isa == SF_MLP_ISA_AVX2_FMA) {
    sf_lm_gram_avx2(s, g, a, vecs, scratch, A);
    return;
  }
#else
  (void)isa;
#endif
  sf_lm_gram_baseline(s, g, a, vecs, scratch, A);
}

void sf_lm_add_block_gram(const sf_mlp_shape *s, const double *g, const double *a, int n, double *scratch, double *A) {
  sf_lm_add_block_gram_isa(sf_mlp_isa_auto(), s, g, a, n, scratch, A);
}
