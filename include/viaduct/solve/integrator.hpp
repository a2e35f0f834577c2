#pragma once
/// \file The one face of every time-stepping kernel (docs/architecture.md).
///
/// An Integrator advances load cases on one structure (M, C, K) from rest and records a fixed set
/// of outputs (Functionals, e.g. the deflection of a deck point) on the grid t_k = k·dt,
/// k = 0 … ceil(t_end/dt). make_integrator() is the one place where a method is chosen from the
/// settings; the caller never names a kernel. Behind it:
///
/// | method  | run() (one case)                         | run_batch() (cases of one structure)          |
/// |---------|------------------------------------------|-----------------------------------------------|
/// | newmark | newmark(): Newmark/HHT on every DOF      | newmark_batch(): four cases per factorisation |
/// | modal   | ModalReduction::integrate (classical or  | with peaks-only recording and moving loads:   |
/// |         | complex modes), or the peaks kernel when | modal_peaks(), four speeds in SIMD lanes;     |
/// |         | only peaks are asked of a moving load    | else one run() per case                       |
/// | ida     | ida(): adaptive BDF (SUNDIALS IDA)       | one run() per case                            |
///
/// Vehicles coupled to the structure at moving wheel–rail contacts (coupled.hpp) go through the
/// same face, run_coupled(): newmark runs coupled_newmark on every DOF; modal runs coupled_newmark
/// on the structure's modes ("modal-vehicles"); ida runs coupled_ida on them. coupled_coordinates()
/// tells the caller which coordinates the case's matrices and contact path must be in.
///
/// A new kernel implements Integrator and gets a Method value and a branch in make_integrator();
/// nothing above `solve` changes.

#include <memory>
#include <string>
#include <vector>

#include "viaduct/core/buffer.hpp"
#include "viaduct/core/log.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/guard.hpp"
#include "viaduct/solve/ida.hpp"
#include "viaduct/solve/modal.hpp"
#include "viaduct/solve/newmark.hpp"
#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::solve {



/// Loads given as piecewise cubics of a coordinate X that moves at a constant speed,
/// X = x_start + v·t (e.g. a train's modal loads as functions of its head position): one cubic per
/// piece and channel. Speed-independent, so one table serves every speed (the peaks kernel).
struct MovingChannels {
  std::vector<double> breaks;  ///< [m] ascending; piece i is [breaks[i], breaks[i+1])
  /// Per piece, 4 powers of s = X − breaks[i] (s⁰ … s³), each with n_channels values; one more
  /// block of zeros follows for X beyond the last break. Not zeroed when resized (UninitAllocator):
  /// whoever builds the table writes every number.
  std::vector<double, UninitAllocator<double>> coef;
  std::size_t n_modes = 0;    ///< load channels (ModalReduction::n_channels())
  std::size_t n_outputs = 0;  ///< static-correction residual channels (0 without the correction)
  /// Further channels after the residuals, read by OutputSum::load_channel (a rigid bearing's
  /// direct share of the axle loads on its own elements).
  std::size_t n_extra = 0;
  std::size_t n_channels = 0; ///< n_modes + n_outputs + n_extra
  /// With extra channels: per break (breaks.size() × n_extra) what they add when the head is
  /// exactly at that break and nowhere else: a load that the piece before ends with (an axle at
  /// the path's very end, which its last element holds: load::MovingLoads' rule).
  std::vector<double> point;
  /// Per piece, bounds of each static-correction residual channel over it (bound_residuals): at
  /// (2p)·n_outputs + j the largest, at (2p + 1)·n_outputs + j the smallest value of channel
  /// n_modes + j; empty when not computed (the peaks kernel then computes them for itself).
  std::vector<double> residual_bounds;
  double length = 0.0;        ///< [m] extent of the load itself (a train's first to last axle)
  double x_start = 0.0, x_end = 0.0;  ///< [m] the path: loads enter at x_start, leave past x_end
  /// [s] time from entry until the load has left the path at speed v [m/s].
  double t_exit(double v) const { return (x_end - x_start + length) / v; }
};

/// Fills pieces [p0, p1) of L.residual_bounds (sized 2 × pieces × n_outputs by the caller) from
/// L.coef: the range of each residual's cubic a0 + a1 s + a2 s² + a3 s³ over its piece
/// (0 ≤ s ≤ ℓ: its values at the ends and at the turning points within) widened by 1e-10 of
/// |a0| + Σ|aₙ|ℓⁿ, far above the rounding of the few operations that evaluate it (where the range
/// is not a number, infinite coefficients: the terms bounded one by one). Used by the peaks kernel
/// to leave out blocks of steps that cannot reach beyond an output's extremes.
void bound_residuals(MovingChannels& L, std::size_t p0, std::size_t p1) noexcept;

/// One load case. `system` gives the matrices and the nodal loads f(t) (required: every kernel can
/// use it). Modal kernels take the same loads projected when given: `modal_force` (history
/// recording) or `moving` at `speed` (peaks-only recording; four cases per SIMD pass).
struct LoadCase {
  const SecondOrderSystem* system = nullptr;
  ModalForce* modal_force = nullptr;        ///< optional; stateful, one per case
  const MovingChannels* moving = nullptr;   ///< optional, with speed
  double speed = 0.0;                       ///< [m/s] > 0 with `moving`
  double t_end = 1.0;                       ///< [s] > 0: samples k·dt up to ceil(t_end/dt)
  /// Optional: bounds no physical response of the case reaches, per output (guard.hpp). A run
  /// past one stops with a SolverError naming the output, the bound and the likely cause.
  const DivergenceBound* bound = nullptr;
  /// Optional: told (steps done, steps in all) about a hundred times a run (run() only).
  const ProgressSink* progress = nullptr;
};

/// An output made of recorded ones, of which only the signed extremes are kept: a rigid bearing's
/// force is its stiffness part (an output's deflection) + its inertia part (an output's
/// acceleration) + its damping part (an output's acceleration integrated from rest by the
/// trapezoidal rule, as the history path integrates it) + the axle loads on its own elements (a
/// load channel of the moving loads). -1: no such part.
struct OutputSum {
  Index disp = -1;          ///< output whose deflection is added
  Index acc = -1;           ///< output whose acceleration is added
  Index acc_integral = -1;  ///< output whose acceleration's time integral is added
  Index load_channel = -1;  ///< MovingChannels extra channel (0-based among the n_extra) added
};

/// What to keep of each case.
struct Recording {
  bool disp_history = true;  ///< every output's deflection at every sample
  bool acc_history = true;   ///< every output's acceleration at every sample
  /// The modal peaks kernel computes the acceleration of the first acc_outputs outputs only
  /// (their max_abs_acc and, with acc_history, their histories; the other outputs report
  /// max_abs_acc 0) and of the outputs that sums take; -1: of every output. The other kernels
  /// record every output.
  Index acc_outputs = -1;
  /// Every output's velocity at every sample (newmark and ida, run() only; InputError elsewhere).
  bool vel_history = false;
  /// Samples kept in the histories: steps 0, stride, 2·stride, … (a kernel step finer than the
  /// record's, e.g. a shaker's substeps); the running extremes see every step. newmark and ida,
  /// run() only, when > 1.
  Index stride = 1;
  /// Largest histories one case may hold [bytes]; InputError beyond.
  double max_history_bytes = 2.0 * (1 << 30);
  /// Sums whose signed extremes are tracked (CaseResult::max_sum, min_sum): the modal peaks
  /// kernel only (moving loads, no deflection history); InputError elsewhere.
  std::vector<OutputSum> sums;
};

/// The result of one case.
struct CaseResult {
  Matrix disp;  ///< n_samples × n_outputs when recorded (Recording::disp_history), else empty
  Matrix acc;   ///< n_samples × n_outputs when recorded (× Recording::acc_outputs where the kernel honours it), else empty
  Matrix vel;   ///< n_samples × n_outputs when recorded (Recording::vel_history), else empty
  Vector max_abs_disp;  ///< running maximum of |deflection| per output (always)
  /// Signed extremes of the deflection per output (always; max >= 0 >= min: every case starts at rest).
  Vector max_disp, min_disp;
  Vector max_abs_acc;   ///< running maximum of |acceleration| per output, unfiltered (always)
  /// Signed extremes of each Recording::sums entry over every sample (its value at rest need not
  /// be 0: a load on a bearing's element), when sums were asked for.
  Vector max_sum, min_sum;
  Summary summary;
};

/// One run of vehicles coupled to the structure (coupled.hpp), from rest. M, C, K and `path` are
/// in the coordinates Integrator::coupled_coordinates() names: every DOF, or the structure's
/// modes (a reduction with the vehicles' static correction in `path`). `observe` sees the
/// coupled state after every step of `grid`; `bound` is the divergence guard.
struct CoupledCase {
  const SparseMatrix* M = nullptr;
  const SparseMatrix* C = nullptr;
  const SparseMatrix* K = nullptr;
  const LinearVehicle* vehicle = nullptr;
  const ContactPath* path = nullptr;
  TimeGrid grid;
  CoupledObserver observe;
  const DivergenceBound* bound = nullptr;
};

/// The coordinates a coupled case is integrated in.
enum class Coordinates { physical, modal };

/// The integration interface (DESIGN.md §5: MFEM's one solver face, with batches inside it).
class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual Method method() const = 0;
  /// Cases run_batch() advances together (callers give it blocks of this size or less).
  virtual std::size_t batch_width() const { return 1; }
  /// One case from rest. InputError for an invalid case or oversized histories, SolverError when
  /// the kernel fails (non-finite state, a matrix that cannot be factored, IDA's failures).
  virtual CaseResult run(const LoadCase& c, const Recording& rec) const = 0;
  /// Several cases on this structure, one result each in order: the same answers as run() up to
  /// rounding (summation order), in a fraction of the time where the kernel batches.
  virtual std::vector<CaseResult> run_batch(const std::vector<LoadCase>& cases, const Recording& rec) const;
  /// The coordinates run_coupled() integrates the structure in (newmark: physical; modal, ida:
  /// modal, the vehicles physical).
  virtual Coordinates coupled_coordinates() const = 0;
  /// Vehicles and structure together (the kernel of coupled.hpp this method stands for). Its
  /// summary's kernel names it ("newmark-vehicles", "modal-vehicles", "ida-vehicles").
  virtual CoupledSummary run_coupled(const CoupledCase& c) const = 0;
  const std::vector<Functional>& outputs() const { return outputs_; }

 protected:
  explicit Integrator(std::vector<Functional> outputs) : outputs_(std::move(outputs)) {}
  std::vector<Functional> outputs_;
};

/// What a method's integrator needs from its caller, known before it is built: callers ask
/// these (which model to prepare, how to batch, in which coordinates vehicles take the
/// structure), never the method itself. The integrators make_integrator() builds agree with them.
struct MethodTraits {
  bool needs_reduction = false;    ///< run() and run_batch() take a ModalReduction (modal)
  bool batches_histories = false;  ///< run_batch() advances several history-recording cases at once (newmark)
  Coordinates coupled = Coordinates::physical;  ///< what run_coupled() integrates the structure in
  /// Compiled into this build: false for ida when built without SUNDIALS (CMake VIADUCT_IDA=OFF,
  /// as scripts/demo.sh does when libsundials-dev is missing); make_integrator() refuses it then.
  bool built = true;
  const char* not_built = "";  ///< when !built: why, and how to build it (for the user's message)
};
MethodTraits method_traits(Method m);

/// The one place a method is chosen. `outputs` are the recorded functionals; `modal` is the
/// reduction of the structure (needed by Method::modal's run() and run_batch(), whose outputs it
/// already holds: then `outputs` must be empty or its first outputs; not by run_coupled(), whose
/// case brings its modes). InputError for invalid settings (the struct and field named), or at the
/// first run() of a modal integrator without a reduction, or for a method this build lacks
/// (MethodTraits::built).
std::unique_ptr<Integrator> make_integrator(const IntegrationSettings& s, std::vector<Functional> outputs,
                                            std::shared_ptr<const ModalReduction> modal = nullptr);

}  // namespace viaduct::solve
