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

#include "viaduct/solve/newmark.hpp"
#include "viaduct/solve/options.hpp"
#include "viaduct/solve/second_order_system.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve {


/// Integrates from rest; calls `observe` at t = 0 and every grid.dt with (u, v, a). InputError for
/// an invalid grid or options, SolverError with IDA's flag and message when integration fails.
/// Summary: n_steps internal steps, n_factorisations Jacobians (KLU refactorisations),
/// n_rejected_steps error-test failures, n_nonlinear_failures, n_residuals, n_restarts, last_order.
Summary ida(const SecondOrderSystem& sys, const TimeGrid& grid, const IdaOptions& opt, const StepObserver& observe);

}  // namespace viaduct::solve
