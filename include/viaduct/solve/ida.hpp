#pragma once
/// \file Adaptive implicit integration of a SecondOrderSystem with SUNDIALS IDA (variable order
/// BDF, 1–5), KLU sparse direct linear solver, outputs sampled at a fixed recording interval.
///
/// Residual form with y = [u; v]: F₁ = u̇ − v, F₂ = M v̇ + C v + K u − f(t); Jacobian
/// ∂F/∂y + c_j ∂F/∂ẏ = [c_j I, −I; K, c_j M + C] assembled once in CSC and refilled per c_j.
/// Discontinuities of f (SecondOrderSystem::discontinuities(), e.g. axles entering and leaving)
/// are stop times: the integrator halts there and restarts with consistent v̇ = M⁻¹(f(t⁺) − C v − K u),
/// so adaptivity never smears a jump. Every SUNDIALS return code is checked; an exception thrown
/// by the system inside a callback is captured and rethrown intact after IDASolve; SUNDIALS'
/// messages never reach stdout/stderr: warnings go to the log sink, errors into the SolverError.

#include <functional>
#include <string>

#include "viaduct/core/log.hpp"
#include "viaduct/solve/newmark.hpp"
#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::solve {

struct IdaOptions {
  double dt_out = 1e-3;      ///< [s] recording interval, > 0 (outputs at k·dt_out, interpolated by IDA)
  double t_end = 1.0;        ///< [s] > 0
  double rtol = 1e-6;        ///< [-] relative tolerance, in [1e-12, 1e-1]
  double atol_disp = 1e-10;  ///< [m] absolute tolerance of displacements, > 0
  double atol_vel = 1e-8;    ///< [m/s] absolute tolerance of velocities, > 0
  int max_order = 5;         ///< BDF order limit, 1..5
  double max_step = 0.0;     ///< [s] largest internal step (0: no limit), >= 0
  long max_steps_per_output = 100000;  ///< internal steps allowed between two outputs, >= 1
  LogSink log;               ///< SUNDIALS' warnings (optional; errors are thrown with their message)
  bool is_valid(std::string* why) const;
};

/// What a run did (DESIGN.md §3.5).
struct IdaSummary {
  Index n_outputs = 0;       ///< samples delivered (t = 0 included)
  long n_steps = 0;          ///< internal steps
  long n_residuals = 0;      ///< residual evaluations
  long n_jacobians = 0;      ///< Jacobian evaluations (each one KLU refactorisation)
  long n_error_test_failures = 0;
  long n_nonlinear_failures = 0;
  long n_restarts = 0;       ///< restarts at discontinuities
  int last_order = 0;
  double t_reached = 0.0;    ///< [s]
  double wall_s = 0.0;       ///< [s]
  std::string stop_reason;
};

/// Integrates from rest; calls `observe` at t = 0 and every dt_out with (u, v, a). InputError for
/// invalid options, SolverError with IDA's flag and message when integration fails.
IdaSummary ida(const SecondOrderSystem& sys, const IdaOptions& opt, const StepObserver& observe);

}  // namespace viaduct::solve
