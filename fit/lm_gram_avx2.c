/* The polish's block Gram matrix for x86-64 with AVX2 and FMA:
 * CMakeLists.txt compiles this file alone with -mavx2 -mfma (x86-64
 * only), and fit/lm_gram.c calls it only on a CPU that has both. A vector
 * of 8 lanes is two registers there (fit/mlp_lanes.h): tiles of 2 x 2
 * entries keep their 8 accumulators and 8 loaded halves in 16. */
#if !defined(__AVX2__) || !defined(__FMA__)
#error "fit/lm_gram_avx2.c is compiled with -mavx2 -mfma (CMakeLists.txt)"
#endif
#define SF_LM_GRAM_NAME sf_lm_gram_avx2
#define SF_LM_GRAM_TILE_ROWS 2
#define SF_LM_GRAM_TILE_COLS 2
#include "fit/lm_gram_body.h"
