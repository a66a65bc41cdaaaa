/* SF_X86_CLONES: compile a function for AVX-512F, AVX2 and baseline x86-64
 * and let the loader pick the one the CPU runs (GCC's target_clones on
 * x86-64 Linux; elsewhere a plain function). The binary is built without
 * -march, so it runs on any x86-64 and is fast where the wide units are.
 * A clone does the same exactly rounded operations per lane as the others,
 * hence the same bits, while nothing is contracted into fused multiply-adds
 * (C11 mode does not; fit/fit_sky_config.c also says so by pragma) and the
 * function calls nothing that differs per instruction set. */
#ifndef SKYFIT_UTIL_TARGET_CLONES_H
#define SKYFIT_UTIL_TARGET_CLONES_H

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define SF_X86_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define SF_X86_CLONES
#endif

#endif
