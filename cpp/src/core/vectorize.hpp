// Row kernels that the compiler vectorizes: built for AVX2 as well where the compiler can
// dispatch at run time (twice the lanes of the baseline SSE2), the same arithmetic, so the same
// result to rounding. Put MEREO_VECTOR_CLONES before a function with a plain counted loop over
// __restrict pointers and no branch in it.
#pragma once

// GCC only: clang 14 does not multiversion function templates (the fuzz build uses clang).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MEREO_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MEREO_VECTOR_CLONES
#endif
