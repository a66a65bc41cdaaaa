/* The training kernel for any CPU: compiled without instruction-set flags
 * (on x86-64: SSE2, multiply-adds by exact arithmetic, fit/mlp_lanes_fma.h).
 * fit/mlp_kernel.h. */
#if defined(__SSE2__)
/* One vector at a time: each of the 8 lanes' vectors takes 4 of SSE2's 16
 * registers, and 4 vectors at once spilled (the same sums either way):
 * 2,4,3 full batch 818 -> 609 ns per sample, 4,8,8,9 4348 -> 3205 on an
 * Emerald Rapids Xeon (build/bench_mlp_kernel). */
#define SF_MLP_KERNEL_VECS 1
#endif
#define SF_MLP_KERNEL_NAME sf_mlp_kernel_baseline
#include "fit/mlp_kernel_body.h"
