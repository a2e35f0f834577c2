#pragma once
// Checks shared by the kernels of src/solve (private).

#include "viaduct/core/error.hpp"
#include "viaduct/core/types.hpp"

namespace viaduct::solve::detail {

/// Throws InputError("<who>: M, C and K must be square and of one size") unless they are.
inline Index require_square_system(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                                   const char* who) {
  const Index n = M.rows();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n)
    throw InputError(std::string(who) + ": M, C and K must be square and of one size");
  return n;
}

}  // namespace viaduct::solve::detail
