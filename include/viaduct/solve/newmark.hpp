#pragma once
/// \file Newmark-β / HHT-α fixed-step integration of a SecondOrderSystem.

#include <functional>
#include <string>

#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::solve {

struct NewmarkOptions {
  double dt = 1e-3;     ///< [s] fixed step, > 0
  double t_end = 1.0;   ///< [s] last time, > 0 (steps: ceil(t_end/dt))
  double beta = 0.25;   ///< [-] > 0; 0.25 with gamma 0.5 = constant average acceleration
  double gamma = 0.5;   ///< [-] >= 0.5 (smaller values add negative numerical damping)
  /// [-] HHT-α in [-1/3, 0]; 0 is plain Newmark. With alpha != 0 use beta = (1 - alpha)²/4 and
  /// gamma = (1 - 2 alpha)/2 for second order and unconditional stability (see hht()).
  double alpha = 0.0;
  /// Throw SolverError when the state stops being finite.
  bool check_finite = true;

  /// Options for HHT-α with its standard β and γ.
  static NewmarkOptions hht(double alpha, double dt, double t_end);
  /// True when 2β >= γ >= 1/2: stable for any step on a linear system.
  bool unconditionally_stable() const;
  bool is_valid(std::string* why) const;
};

/// Called at t = 0 and after every step with the state at `t`. The vectors are only valid
/// during the call.
using StepObserver =
    std::function<void(Index step, double t, const Vector& u, const Vector& v, const Vector& a)>;

/// What a run did (DESIGN.md §3.5).
struct NewmarkSummary {
  Index n_steps = 0;        ///< steps taken
  Index n_dofs = 0;
  double t_reached = 0.0;   ///< [s]
  double wall_s = 0.0;      ///< [s] wall time of the whole call, factorisation included
  std::string stop_reason;  ///< "t_end reached"
};

/// Integrates from rest (u = v = 0; a from M a = f(0)) unless u0/v0 are given (size n_dofs).
/// Factors the effective matrix once. Throws InputError for invalid options, SolverError for a
/// matrix that is not positive definite, a conditionally stable scheme used beyond its limit,
/// or a non-finite state (with the time at which it appeared).
NewmarkSummary newmark(const SecondOrderSystem& sys, const NewmarkOptions& opt,
                       const StepObserver& observe, const Vector* u0 = nullptr,
                       const Vector* v0 = nullptr);

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
  NewmarkSummary summary;  ///< wall_s: the batch's wall time shared equally among its cases
};

/// Cases newmark_batch() advances together.
constexpr std::size_t kNewmarkBatch = 4;

/// Newmark / HHT-α of up to kNewmarkBatch load cases on one structure (the same M, C and K
/// objects): the scheme, step and answers of newmark() for each (from rest, opt.t_end ignored
/// for each case's own), with one factorisation and every sparse product and triangular solve
/// done on all the cases at once (four SIMD lanes). Records only the outputs. InputError for
/// invalid options, an empty or oversized batch, cases on different matrices or outputs out of
/// range; SolverError as newmark().
std::vector<BatchHistories> newmark_batch(const std::vector<BatchCase>& cases, const NewmarkOptions& opt,
                                          const std::vector<Functional>& outputs);

/// [rad/s] estimate of the largest ω of K φ = ω² M φ by power iteration (upper-biased by 2 %).
double estimate_max_omega(const SparseMatrix& M, const SparseMatrix& K);

}  // namespace viaduct::solve
