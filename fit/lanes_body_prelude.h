/* Included first by the bodies built once per instruction set
 * (fit/mlp_kernel_body.h, fit/lm_gram_body.h), for the rest of their file:
 * no implicit contraction, so a multiply-add is fused exactly where
 * written, the same on every build (GCC contracts in GNU mode, Clang
 * within an expression by default); and FORCE_INLINE, for the helpers
 * whose constant arguments must unroll their loops. */
#ifndef SKYFIT_FIT_LANES_BODY_PRELUDE_H
#define SKYFIT_FIT_LANES_BODY_PRELUDE_H

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__GNUC__)
#define FORCE_INLINE __attribute__((always_inline)) inline
#else
#define FORCE_INLINE inline
#endif

#endif
