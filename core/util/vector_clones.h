// FACETOOL_VECTOR_CLONES: compiles a hot loop for AVX-512, AVX2 + FMA and the baseline x86-64,
// picked once at load time by the CPU's features (GCC's target_clones; elsewhere a no-op);
// FACETOOL_NO_ALIAS_LOOP for the loops inside them, and FACETOOL_NO_FP_CONTRACT for a function
// whose results must not depend on the clone.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define FACETOOL_VECTOR_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define FACETOOL_VECTOR_CLONES
#endif

// FACETOOL_NO_ALIAS_LOOP: placed before a loop whose output arrays never overlap its inputs or
// each other, so the compiler vectorises it without run-time overlap checks (GCC's ivdep).
#if defined(__GNUC__) && !defined(__clang__)
#define FACETOOL_NO_ALIAS_LOOP _Pragma("GCC ivdep")
#else
#define FACETOOL_NO_ALIAS_LOOP
#endif

// FACETOOL_NO_FP_CONTRACT: a function whose a * b + c is rounded twice (never one fused
// multiply-add), whichever clone or -march runs it, so that two implementations of one formula
// give the same floats (the batch norm on the cpu backend and on the host).
#if defined(__GNUC__) && !defined(__clang__)
#define FACETOOL_NO_FP_CONTRACT __attribute__((optimize("fp-contract=off")))
#else
#define FACETOOL_NO_FP_CONTRACT
#endif
