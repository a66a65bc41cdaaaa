/* The training kernel for x86-64 with AVX-512F whose sigmoids take half
 * their reciprocals by multiply-adds (fit/mlp_lanes_reciprocal.h), for
 * Intel cores, whose 8-lane division takes 16 cycles of the divider: the
 * same bits as fit/mlp_kernel_avx512.c. CMakeLists.txt compiles this file
 * alone with -mavx512f (x86-64 only); fit/mlp_backward.c picks it. */
#if !defined(__AVX512F__)
#error "fit/mlp_kernel_avx512_newton.c is compiled with -mavx512f (CMakeLists.txt)"
#endif
#define SF_MLP_KERNEL_NAME sf_mlp_kernel_avx512_newton
#define SF_MLP_SIGMOID_NEWTON 1
#include "fit/mlp_kernel_body.h"

void sf_mlp_reciprocals_avx512(const double *d, double *out, long n) {
  for (long i = 0; i < n; i += SF_LANES) {
    double v[SF_LANES];
    for (int k = 0; k < SF_LANES; ++k) v[k] = i + k < n ? d[i + k] : 1.0;
    sf_lanes y = sf_lanes_load(v);
    sf_lanes_reciprocal_n(&y, 1);
    sf_lanes_store(v, y);
    for (int k = 0; k < SF_LANES && i + k < n; ++k) out[i + k] = v[k];
  }
}
