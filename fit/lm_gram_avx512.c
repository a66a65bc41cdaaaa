/* The polish's block Gram matrix for x86-64 with AVX-512F: CMakeLists.txt
 * compiles this file alone with -mavx512f (x86-64 only), and
 * fit/lm_gram.c calls it only on a CPU that has it. Tiles of 4 x 4
 * entries: 16 accumulators and 8 loaded vectors in 32 registers. */
#if !defined(__AVX512F__)
#error "fit/lm_gram_avx512.c is compiled with -mavx512f (CMakeLists.txt)"
#endif
#define SF_LM_GRAM_NAME sf_lm_gram_avx512
#include "fit/lm_gram_body.h"
