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
struct NewmarkOptions {
  double beta = 0.25;   ///< [-] > 0; 0.25 with gamma 0.5 = constant average acceleration
  double gamma = 0.5;   ///< [-] >= 0.5 (smaller values add negative numerical damping)
  /// [-] HHT-α in [-1/3, 0]; 0 is plain Newmark. With alpha != 0 use beta = (1 - alpha)²/4 and
  /// gamma = (1 - 2 alpha)/2 for second order and unconditional stability (see hht()).
  double alpha = 0.0;
  /// Throw SolverError when the state stops being finite.
  bool check_finite = true;

  /// Options for HHT-α with its standard β and γ.
  static NewmarkOptions hht(double alpha);
  /// True when 2β >= γ >= 1/2: stable for any step on a linear system.
  bool unconditionally_stable() const;
  /// *why: "NewmarkOptions::FIELD = VALUE: violated constraint ..." (the struct, field and rule).
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
