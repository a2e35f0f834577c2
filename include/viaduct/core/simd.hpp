#pragma once
/// \file The instruction set the SIMD kernels run (the modal peaks kernel, batched Newmark; and
/// SHA-256's SHA extensions, off at the baseline). Each kernel is built for several and gives the
/// same numbers on every one (no FMA contraction; src/solve/lanes.hpp); the choice is speed only.

namespace viaduct {

/// The instruction sets the kernels are built for, in increasing order.
enum class Simd { baseline, avx2, avx512 };

/// The best instruction set the processor runs (baseline where the kernels have no vector build),
/// capped by the environment variable VIADUCT_SIMD = baseline | avx2 | avx512 when it is set (the
/// tests compare the sets; a benchmark can pin one). InputError for another value. Read once.
Simd simd_level();

}  // namespace viaduct
