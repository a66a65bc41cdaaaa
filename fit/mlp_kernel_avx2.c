/* The training kernel for x86-64 with AVX2 and FMA: CMakeLists.txt compiles
 * this file alone with -mavx2 -mfma (x86-64 only), and fit/mlp_backward.c
 * calls it only on a CPU that has both. fit/mlp_kernel.h. */
#if !defined(__AVX2__) || !defined(__FMA__)
#error "fit/mlp_kernel_avx2.c is compiled with -mavx2 -mfma (CMakeLists.txt)"
#endif
#define SF_MLP_KERNEL_NAME sf_mlp_kernel_avx2
#include "fit/mlp_kernel_body.h"
