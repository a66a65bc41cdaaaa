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
 * (l2 + l6)) + ((l1 + l5) + (l3 + l7)). Tiled for AVX2 where the CPU has
 * it (x86-64, GCC), else the plain loop, with the same operations per lane
 * (no fused multiply-adds): the same bits on every CPU. */
void sf_lm_add_block_gram(int P, const double *block, int padded, double *A);
/* The plain loop on any CPU (tests: the same bits as the above). */
void sf_lm_add_block_gram_plain(int P, const double *block, int padded, double *A);

#endif
