#pragma once
/// \file What every time-stepping kernel takes (its time grid) and returns (one Summary with typed
/// counters, DESIGN.md §3.5).

#include <string>

#include "viaduct/core/types.hpp"

namespace viaduct::solve {

/// The time grid of a run, shared by every method: samples at t_k = k·dt, k = 0 … n_steps().
struct TimeGrid {
  double dt = 1e-3;    ///< [s] step (Newmark), load-sampling interval (modal) and recording interval, > 0
  double t_end = 1.0;  ///< [s] last time, > 0 (rounded up to a whole step)
  /// ceil(t_end/dt) (a t_end within 1e-9 steps of a sample ends there).
  Index n_steps() const;
  /// dt and t_end finite and > 0, at most 2e9 steps; *why names the field and the constraint.
  bool is_valid(std::string* why) const;
};

/// The time-stepping kernel that ran a case: one per loop in src/solve.
enum class Kernel {
  none,              ///< nothing ran (a default Summary)
  newmark,           ///< Newmark/HHT on every DOF, one case
  newmark_batch,     ///< Newmark/HHT on every DOF, four cases per pass
  modal,             ///< modal superposition, classical modes
  modal_complex,     ///< modal superposition, complex modes (non-proportional damping)
  modal_peaks,       ///< the fused modal kernel of envelope sweeps (peaks and sums of outputs only)
  ida,               ///< SUNDIALS IDA on every DOF
  newmark_vehicles,  ///< Newmark/HHT, structure and vehicles coupled through the contact
  modal_vehicles,    ///< the same on the structure's modes
  ida_vehicles,      ///< IDA, structure and vehicles coupled
};
/// "newmark", "newmark-batch", "modal", "modal-complex", "modal-peaks", "ida",
/// "newmark-vehicles", "modal-vehicles", "ida-vehicles" ("none").
const char* kernel_name(Kernel k);

/// What a run did, the same for every kernel.
struct Summary {
  Kernel kernel = Kernel::none;  ///< the kernel that ran (kernel_name() for messages)
  Index n_steps = 0;           ///< steps: one per sample interval (fixed-step kernels), internal steps (IDA)
  Index n_samples = 0;         ///< samples delivered, t = 0 included
  Index n_rejected_steps = 0;  ///< IDA: steps rejected by the error test (0 for fixed-step kernels)
  Index n_nonlinear_failures = 0;  ///< IDA: Newton convergence failures (each retries the step)
  Index n_factorisations = 0;  ///< sparse factorisations (Newmark: one per run or batch; IDA: Jacobians)
  Index n_residuals = 0;       ///< IDA: residual evaluations
  Index n_restarts = 0;        ///< IDA: restarts at load discontinuities
  int last_order = 0;          ///< IDA: BDF order of the last step
  Index n_dofs = 0;            ///< DOFs of the structure
  Index n_modes = 0;           ///< modal coordinates (modal kernels)
  double t_reached = 0.0;      ///< [s]
  double wall_s = 0.0;         ///< [s] (a batch's wall time is shared equally among its cases)
  std::string stop_reason;     ///< "t_end reached"
  /// The stop reason with the counters that matter for the kernel, on one line.
  std::string describe() const;
};

}  // namespace viaduct::solve
