#pragma once
// Checks shared by the kernels of src/solve (private).

#include <chrono>
#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/core/types.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve::detail {

/// Throws InputError("<who>: M, C and K must be square and of one size") unless they are.
inline Index require_square_system(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                                   const char* who) {
  const Index n = M.rows();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n)
    throw InputError(std::string(who) + ": M, C and K must be square and of one size");
  return n;
}

/// [s] of wall time since `t0`.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The Summary of a fixed-step kernel that reached t_end: n_steps steps of dt, n_steps + 1 samples.
inline Summary fixed_step_summary(Kernel kernel, Index n_steps, double dt, Index n_dofs, Index n_modes,
                                  Index n_factorisations, double wall_s) {
  Summary s;
  s.kernel = kernel;
  s.n_steps = n_steps;
  s.n_samples = n_steps + 1;
  s.n_factorisations = n_factorisations;
  s.n_dofs = n_dofs;
  s.n_modes = n_modes;
  s.t_reached = static_cast<double>(n_steps) * dt;
  s.stop_reason = "t_end reached";
  s.wall_s = wall_s;
  return s;
}

}  // namespace viaduct::solve::detail
