/* The training kernel for any CPU: compiled without instruction-set flags
 * (on x86-64, SSE2 and libm's fma). fit/mlp_kernel.h. */
#define SF_MLP_KERNEL_NAME sf_mlp_kernel_baseline
#include "fit/mlp_kernel_body.h"
