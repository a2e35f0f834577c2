#pragma once
/// \file Newmark-β / HHT-α fixed-step integration of a SecondOrderSystem.

#include <functional>
#include <string>

#include "viaduct/solve/options.hpp"
#include "viaduct/solve/second_order_system.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve {


/// Called at t = 0 and after every step with the state at `t`. The vectors are only valid
/// during the call.
using StepObserver =
    std::function<void(Index step, double t, const Vector& u, const Vector& v, const Vector& a)>;

/// Integrates from rest (u = v = 0; a from M a = f(0)) unless u0/v0 are given (size n_dofs), on
/// the grid of `grid`. Factors the effective matrix once (wall_s includes it). Throws InputError
/// for an invalid grid or options, SolverError for a matrix that is not positive definite, a
/// conditionally stable scheme used beyond its limit, or a non-finite state (with the time at
/// which it appeared). Most callers go through Integrator (integrator.hpp).
Summary newmark(const SecondOrderSystem& sys, const TimeGrid& grid, const NewmarkOptions& opt,
                const StepObserver& observe, const Vector* u0 = nullptr, const Vector* v0 = nullptr);

/// One load case of newmark_batch(): its loads (the system's M, C, K must be those of every
/// other case) and its duration.
struct BatchCase {
  const SecondOrderSystem* system = nullptr;
  double t_end = 1.0;  ///< [s] > 0; steps: ceil(t_end/dt)
};

/// Output histories of one case: row k is t = k·dt, one column per Functional.
struct BatchHistories {
  Matrix disp;  ///< (n_steps + 1) × n_outputs, Σ w u
  Matrix acc;   ///< (n_steps + 1) × n_outputs, Σ w a
  Summary summary;  ///< wall_s: the batch's wall time shared equally among its cases
};

/// Cases newmark_batch() advances together.
constexpr std::size_t kNewmarkBatch = 4;

/// Newmark / HHT-α of up to kNewmarkBatch load cases on one structure (the same M, C and K
/// objects): the scheme, step and answers of newmark() for each (from rest, each to its own t_end), with one factorisation and every sparse product and triangular solve
/// done on all the cases at once (four SIMD lanes), with the step dt [s] > 0. Records only the
/// outputs. InputError for invalid options, an empty or oversized batch, cases on different
/// matrices or outputs out of range; SolverError as newmark().
std::vector<BatchHistories> newmark_batch(const std::vector<BatchCase>& cases, double dt, const NewmarkOptions& opt,
                                          const std::vector<Functional>& outputs);

/// [rad/s] estimate of the largest ω of K φ = ω² M φ by power iteration (upper-biased by 2 %).
double estimate_max_omega(const SparseMatrix& M, const SparseMatrix& K);

}  // namespace viaduct::solve
