#pragma once
/// \file Four doubles as one value, for the kernels that advance four load cases in lock-step
/// (the modal peaks kernel, batched Newmark). GCC/Clang vector extension: two SSE2 operations
/// per lane operation in a baseline x86-64 build, one AVX operation where a function is built
/// for AVX2 (VIADUCT_TARGET_AVX2, chosen at run time with viaduct::cpu_has_avx2()).
/// Eight doubles (`lanes8`) for the complex-modes peaks kernel where the processor has AVX-512
/// (VIADUCT_TARGET_AVX512, cpu_has_avx512()): one operation for eight cases.
/// Every lane computes the same operations in the same order whatever the lanes' number and the
/// instruction set (no FMA contraction: -ffp-contract=off, CMakeLists.txt), so a case's numbers
/// do not depend on either; VIADUCT_SIMD=baseline|avx2|avx512 caps the instruction set used
/// (viaduct/core/simd.hpp; the tests compare them).
/// Private to the library's kernels: never part of a public function's signature (the vector
/// ABI differs between the builds).

#include <cstddef>
#include <cstdint>

#include "viaduct/core/simd.hpp"

namespace viaduct {

constexpr std::size_t kLanes = 4;
/// may_alias: kernels view aligned double buffers as lanes (and lanes as doubles).
typedef double lanes __attribute__((vector_size(kLanes * sizeof(double)), __may_alias__));
constexpr std::size_t kWideLanes = 8;
typedef double lanes8 __attribute__((vector_size(kWideLanes * sizeof(double)), __may_alias__));

// VIADUCT_TARGET_AVX2, VIADUCT_TARGET_AVX512, VIADUCT_ALWAYS_INLINE: viaduct/core/simd.hpp.

/// True when the kernels run AVX2 code (the processor has it and VIADUCT_SIMD allows it).
inline bool cpu_has_avx2() { return simd_level() >= Simd::avx2; }
/// True when the kernels run AVX-512 code (likewise).
inline bool cpu_has_avx512() { return simd_level() >= Simd::avx512; }

/// Rounds p up to the lane type's full size (aligned loads in a vector build, whatever alignof
/// says in the baseline build). Buffers carry one spare group for it.
template <class L = lanes>
inline L* align_lanes(double* p) {
  constexpr std::uintptr_t a = sizeof(L);
  return reinterpret_cast<L*>((reinterpret_cast<std::uintptr_t>(p) + a - 1) & ~(a - 1));
}

}  // namespace viaduct
