#pragma once
/// \file The instruction set the SIMD kernels run (the modal peaks kernel, batched Newmark; and
/// SHA-256's SHA extensions, off at the baseline). Each kernel is built for several and gives the
/// same numbers on every one (no FMA contraction; src/solve/lanes.hpp); the choice is speed only.

// A function built for AVX2 or AVX-512 besides the baseline (VIADUCT_HAVE_AVX2_VARIANT: where the
// compiler builds such variants; the caller picks one at run time by simd_level()), and a helper
// always inlined, so that a vector caller builds it with its own instructions: for the SIMD
// kernels (src/solve/lanes.hpp) and the filter's four-record cascade (src/signal/iir.cpp).
#if defined(__GNUC__) && defined(__x86_64__)
#define VIADUCT_HAVE_AVX2_VARIANT 1
#define VIADUCT_TARGET_AVX2 __attribute__((target("avx2")))
// GCC's avx512f brings FMA with it: -ffp-contract=off (CMakeLists.txt) keeps a·b + c two roundings.
#define VIADUCT_TARGET_AVX512 __attribute__((target("avx512f")))
#else
#define VIADUCT_TARGET_AVX2
#define VIADUCT_TARGET_AVX512
#endif

#if defined(__GNUC__)
#define VIADUCT_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define VIADUCT_ALWAYS_INLINE inline
#endif

namespace viaduct {

/// The instruction sets the kernels are built for, in increasing order.
enum class Simd { baseline, avx2, avx512 };

/// The best instruction set the processor runs (baseline where the kernels have no vector build),
/// capped by the environment variable VIADUCT_SIMD = baseline | avx2 | avx512 when it is set (the
/// tests compare the sets; a benchmark can pin one). InputError for another value. Read once.
Simd simd_level();

}  // namespace viaduct
