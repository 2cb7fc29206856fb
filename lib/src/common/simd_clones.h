// GDOF_CLONES: a function compiled twice, for AVX2 and for the baseline, the
// version picked when the program loads (the hot loops of the solvers; the
// same operations in the same order either way, so the same bits: no FMA,
// which the ISO mode's fp-contract=off keeps out).
#pragma once

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define GDOF_NO_CLONES 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) || defined(GDOF_NO_CLONES) || !defined(__x86_64__)
// Under ThreadSanitizer one version only: the clones' resolver runs while the
// program is loaded, before the sanitizer's runtime is ready, and crashes.
#define GDOF_CLONES
#else
#define GDOF_CLONES __attribute__((target_clones("avx2", "default")))
#endif
