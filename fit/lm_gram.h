/* The Levenberg-Marquardt polish's hot loop (fit/mlp_lm.c): the Gram
 * matrix J^T J of a block of samples, from the Kronecker form of a
 * network's Jacobian.
 *
 * For sample s and output k, back-propagation gives g_k[u] = d e_k / d z_u
 * for every unit u = (layer l, row i), z_u its pre-activation; the
 * Jacobian entry of the weight joining input j of layer l to that unit is
 * g_k[u] a_l[j] (a_l the layer's inputs, a_l[n_in] = 1 for the bias). So
 * the entry of J^T J between parameters (u, j) and (u', j') is
 *   sum_s G_s(u, u') a_l[j] a_m[j'],   G_s(u, u') = sum_k g_k[u] g_k[u'],
 * the outputs' rows of a sample folded into one term: about one multiply-
 * add per entry and sample, where a row per output and sample takes one per
 * output (3 for the sky's networks): 100 polish steps of the build's
 * 2-16-16-3 transmittance network on one core of the 2-core Xeon took 6.9 s
 * against 14.9 s with a Gram matrix of the rows (one run each).
 *
 * A block holds SF_LM_GRAM_BLOCK samples, sample-minor:
 *   g[(u n_out + k) SF_LM_GRAM_BLOCK + s]   units u in parameter order
 *                                           (layer by layer, rows in order)
 *   a[(r_l + j) SF_LM_GRAM_BLOCK + s]       r_l = sum over layers before l
 *                                           of n_in + 1; row j = n_in holds 1
 * A block holds n samples (1 <= n <= SF_LM_GRAM_BLOCK); the columns from n
 * to the next multiple of 8 have g = 0 and a finite a: they add nothing. */
#ifndef SKYFIT_FIT_LM_GRAM_H
#define SKYFIT_FIT_LM_GRAM_H

#include "fit/mlp_backward.h"
#include "models/mlp.h"

/* Samples per block, a multiple of 8. */
#define SF_LM_GRAM_BLOCK 256

/* Units of a shape (rows of g: units x outputs), rows of a, and doubles of
 * the scratch sf_lm_add_block_gram needs. */
int sf_lm_gram_units(const sf_mlp_shape *s);
int sf_lm_gram_input_rows(const sf_mlp_shape *s);
long sf_lm_gram_scratch_size(const sf_mlp_shape *s);

/* The unit of row i of layer l, and the row of a for input j of layer l. */
int sf_lm_gram_unit(const sf_mlp_shape *s, int l, int i);
int sf_lm_gram_input_row(const sf_mlp_shape *s, int l, int j);

/* A[p][q] += the entry (p, q) of J^T J of a block of n samples for p <= q (the upper
 * triangle of A, P x P row-major, P the parameter count; below the
 * diagonal untouched). Each entry by the same operations on every CPU,
 * multiply-adds fused where written (in the lanes of fit/mlp_lanes.h):
 * for parameters (u, j) and (u', j'), u <= u' in parameter order and j <=
 * j' where u = u',
 *   G_s = g_0[u] g_0[u'], then G_s = fma(g_k[u], g_k[u'], G_s), k = 1..
 *   T_s = G_s a_l[j]
 *   lane c (0..7): L_c = T_c a_m[j']_c, then L_c = fma(T_s, a_m[j']_s, L_c)
 *                  for s = c + 8, c + 16, ... below n rounded up to 8
 *   entry = ((L_0 + L_1) + (L_2 + L_3)) + ((L_4 + L_5) + (L_6 + L_7)),
 * added to A at (min(p, q), max(p, q)) (a bias comes after its layer's
 * weights). scratch: sf_lm_gram_scratch_size(s) doubles. */
void sf_lm_add_block_gram(const sf_mlp_shape *s, const double *g, const double *a, int n, double *scratch, double *A);

/* The same by instruction set isa (fit/mlp_backward.h: baseline, AVX2+FMA
 * or AVX-512F), which must be available (sf_mlp_isa_available); tests:
 * every one gives the same bits. */
void sf_lm_add_block_gram_isa(sf_mlp_isa isa, const sf_mlp_shape *s, const double *g, const double *a, int n,
                              double *scratch, double *A);

#endif
