/* The Levenberg-Marquardt polish's hot loop (fit/mlp_lm.c): a block of
 * Jacobian rows' Gram matrix added to J^T J. */
#ifndef SKYFIT_FIT_LM_GRAM_H
#define SKYFIT_FIT_LM_GRAM_H

/* Rows of the block per pass; a block holds up to this many. */
#define SF_LM_GRAM_BLOCK 64

/* A[i][j] += sum_r B[i][r] B[j][r] for 0 <= i <= j < P (the upper triangle
 * of A, P x P row-major), B parameter-major: B[i][r] = block[i *
 * SF_LM_GRAM_BLOCK + r], rows r < padded (a multiple of 8; the caller
 * zeroes rows past its last). Each entry's sum in a fixed order: row r goes
 * to lane r mod 8 (rows in order), and the lanes are added as ((l0 + l4) +
 * (l2 + l6)) + ((l1 + l5) + (l3 + l7)). By the widest path the CPU runs
 * (below), each with the same operations per lane (no fused
 * multiply-adds): the same bits on every CPU. */
void sf_lm_add_block_gram(int P, const double *block, int padded, double *A);

/* The paths: the plain loop (any CPU), and with GCC on x86-64 two tiled
 * ones, for AVX2 and for AVX-512F. */
typedef enum sf_lm_gram_path { SF_LM_GRAM_PLAIN, SF_LM_GRAM_AVX2, SF_LM_GRAM_AVX512 } sf_lm_gram_path;
/* Whether this build and CPU can run path p. */
int sf_lm_gram_path_available(sf_lm_gram_path p);
/* sf_lm_add_block_gram by path p, which must be available (tests: every
 * path gives the same bits). */
void sf_lm_add_block_gram_path(sf_lm_gram_path p, int P, const double *block, int padded, double *A);

#endif
