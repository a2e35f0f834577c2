#pragma once
/// \file Four doubles as one value, for the kernels that advance four load cases in lock-step
/// (the modal peaks kernel, batched Newmark). GCC/Clang vector extension: two SSE2 operations
/// per lane operation in a baseline x86-64 build, one AVX operation where a function is built
/// for AVX2 (VIADUCT_TARGET_AVX2, chosen at run time with viaduct::cpu_has_avx2()).
/// Private to the library's kernels: never part of a public function's signature (the vector
/// ABI differs between the two builds).

#include <cstddef>
#include <cstdint>

namespace viaduct {

constexpr std::size_t kLanes = 4;
/// may_alias: kernels view aligned double buffers as lanes (and lanes as doubles).
typedef double lanes __attribute__((vector_size(kLanes * sizeof(double)), __may_alias__));

#if defined(__GNUC__) && defined(__x86_64__)
#define VIADUCT_HAVE_AVX2_VARIANT 1
#define VIADUCT_TARGET_AVX2 __attribute__((target("avx2")))
/// True when the processor runs AVX2 code (checked once).
inline bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#else
#define VIADUCT_TARGET_AVX2
inline bool cpu_has_avx2() { return false; }
#endif

#if defined(__GNUC__)
#define VIADUCT_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define VIADUCT_ALWAYS_INLINE inline
#endif

/// Rounds p up to the lanes' full size (aligned 32-byte loads in an AVX2 build, whatever
/// alignof says in the baseline build). Buffers carry one spare group for it.
inline lanes* align_lanes(double* p) {
  constexpr std::uintptr_t a = sizeof(lanes);
  return reinterpret_cast<lanes*>((reinterpret_cast<std::uintptr_t>(p) + a - 1) & ~(a - 1));
}

}  // namespace viaduct
