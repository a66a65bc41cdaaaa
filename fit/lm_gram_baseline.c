/* The polish's block Gram matrix for any CPU: compiled without
 * instruction-set flags (on x86-64: SSE2, multiply-adds by exact
 * arithmetic, fit/mlp_lanes_fma.h). A vector of 8 lanes is four SSE2
 * registers: one entry at a time. */
#define SF_LM_GRAM_NAME sf_lm_gram_baseline
#define SF_LM_GRAM_TILE_ROWS 1
#define SF_LM_GRAM_TILE_COLS 1
#include "fit/lm_gram_body.h"
