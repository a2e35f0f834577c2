#pragma once
/// \file The options of every integration method, apart from the kernels: what a scenario sets
/// (study::RunSettings holds them) without compiling the solver API. Each struct validates
/// itself with is_valid(why), *why naming the struct, the field and the violated constraint.

#include <string>

#include "viaduct/core/log.hpp"

namespace viaduct::solve {

/// How the equations of motion are solved.
enum class Method {
  newmark,  ///< direct Newmark/HHT integration of every DOF
  modal,    ///< modal superposition (ModalReduction)
  ida,      ///< adaptive BDF (SUNDIALS IDA) of every DOF, sampled every dt
};
/// "newmark", "modal", "ida".
const char* method_name(Method m);

/// The scheme; the step and duration are the run's (TimeGrid).
///
/// HHT-α (alpha < 0) is unconditionally stable only with gamma >= 1/2 − alpha and 2 beta >= gamma
/// (the spectral radius of one step is then <= 1 at every ω·dt; tests/unit/solve/test_newmark.cpp
/// computes it). With plain Newmark's beta = 1/4, gamma = 1/2 every alpha < 0 amplifies the highest
/// modes at every step, so that scheme is refused, never run: take hht(alpha) (the scenario's
/// loader does when analysis.beta and analysis.gamma are not given).
struct NewmarkOptions {
  double beta = 0.25;   ///< [-] > 0; 0.25 with gamma 0.5 = constant average acceleration
  double gamma = 0.5;   ///< [-] >= 0.5 (smaller values add negative numerical damping); >= 1/2 − alpha with HHT
  /// [-] HHT-α in [-1/3, 0]; 0 is plain Newmark. With alpha != 0: beta = (1 - alpha)²/4 and
  /// gamma = (1 - 2 alpha)/2 for second order and unconditional stability (hht()).
  double alpha = 0.0;
  /// Throw SolverError when the state stops being finite.
  bool check_finite = true;

  /// Options for HHT-α with its standard β and γ.
  static NewmarkOptions hht(double alpha);
  /// True when the scheme is stable for any step on a linear system: alpha in [-1/3, 0],
  /// gamma >= 1/2 − alpha and 2β >= γ (plain Newmark: 2β >= γ >= 1/2).
  bool unconditionally_stable() const;
  /// [-] Spectral radius of one step of the scheme on ü + 2ξω u̇ + ω² u = 0 at Ω = ω·dt (>= 0,
  /// +infinity for the limit Ω → ∞) and ξ >= 0: the largest |eigenvalue| of the amplification
  /// matrix of (u, dt·v, dt²·a). > 1 means the step amplifies that frequency.
  double spectral_radius(double omega_dt, double xi = 0.0) const;
  /// *why: "NewmarkOptions::FIELD = VALUE: violated constraint ..." (the struct, field and rule).
  /// With alpha != 0 a scheme outside the unconditionally stable set is invalid (beta, gamma named).
  bool is_valid(std::string* why) const;
};

/// Options of modal integration; the load-sampling and output interval is the run's (TimeGrid).
struct ModalOptions {
  /// Throw SolverError when the modal state stops being finite.
  bool check_finite = true;
  bool is_valid(std::string* why) const;
};

/// Tolerances and limits of IDA; the recording interval and duration are the run's (TimeGrid:
/// outputs at k·dt, interpolated by IDA).
struct IdaOptions {
  double rtol = 1e-6;        ///< [-] relative tolerance, in [1e-12, 1e-1]
  double atol_disp = 1e-10;  ///< [m] absolute tolerance of displacements, > 0
  double atol_vel = 1e-8;    ///< [m/s] absolute tolerance of velocities, > 0
  int max_order = 5;         ///< BDF order limit, 1..5
  double max_step = 0.0;     ///< [s] largest internal step (0: no limit), >= 0
  long max_steps_per_output = 100000;  ///< internal steps allowed between two outputs, >= 1
  LogSink log;               ///< SUNDIALS' warnings (optional; errors are thrown with their message)
  bool is_valid(std::string* why) const;
};

/// Everything make_integrator() needs to know of the analysis: the step (the analysis's, shared
/// by every method: the fixed step of Newmark, the load-sampling interval of modal superposition
/// and the recording interval of all three) and one options set per method.
struct IntegrationSettings {
  Method method = Method::newmark;
  double dt = 1e-3;  ///< [s] step and recording interval, > 0
  NewmarkOptions newmark;
  ModalOptions modal;
  IdaOptions ida;
  /// Checks dt and the options of the chosen method; *why names the struct and field.
  bool is_valid(std::string* why) const;
};

}  // namespace viaduct::solve
