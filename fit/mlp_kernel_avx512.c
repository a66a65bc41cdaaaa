/* The training kernel for x86-64 with AVX-512F: CMakeLists.txt compiles this
 * file alone with -mavx512f (x86-64 only), and fit/mlp_backward.c calls it
 * only on a CPU that has it. fit/mlp_kernel.h. */
#if !defined(__AVX512F__)
#error "fit/mlp_kernel_avx512.c is compiled with -mavx512f (CMakeLists.txt)"
#endif
#define SF_MLP_KERNEL_NAME sf_mlp_kernel_avx512
#include "fit/mlp_kernel_body.h"
