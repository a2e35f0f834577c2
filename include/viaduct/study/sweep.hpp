#pragma once
/// \file Speed × train × variant sweeps → maximum-response envelopes.

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/study/scenario.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// One envelope row (tidy: one observation per row).
struct EnvelopeRow {
  std::string variant, train, station;
  double speed = 0.0;         ///< [m/s]
  double max_abs_acc = 0.0;   ///< [m/s²] filtered as the scenario says
  double max_abs_disp = 0.0;  ///< [m]
};

/// The extremes of one quantity (deck deflection or load effect, its unit in its name) in one
/// case, with the same train's quasi-static extremes (crawling, any speed: static_extremes()).
struct QuantityRow {
  std::string variant, train, quantity;
  double speed = 0.0;     ///< [m/s]
  EffectPeak dynamic;     ///< over the run
  EffectPeak quasi_static;
  /// φ′dyn = max|dynamic| / max|quasi-static| − 1 (EN 1991-2 6.4.6.5); NaN when the static is 0.
  double phi_dyn() const;
};

/// The vehicles' extremes in one case of a sweep with vehicle models.
struct VehicleRow {
  std::string variant, train;
  double speed = 0.0;  ///< [m/s]
  VehiclePeaks peaks;
};

/// A case that did not complete; the sweep carries on without it.
struct CaseFailure {
  std::string variant, train;
  double speed = 0.0;  ///< [m/s]
  std::string message;
  bool input_error = false;  ///< the input is wrong for this case (InputError), not the computation
};

struct SweepSummary {
  std::size_t n_cases = 0, n_failed = 0;
  double wall_s = 0.0;           ///< [s]
  Index n_steps_total = 0;       ///< time steps over all completed cases
  std::vector<Index> n_dofs;     ///< per variant
  std::vector<Index> n_modes;    ///< per variant: modes of the modal method (0 otherwise)
  /// The sweep was cut by its cancellation (SweepOptions::cancel, or the caller's CancelScope):
  /// its results are incomplete, and whoever asked for it must say so (the Python package raises).
  bool cancelled = false;
};

struct SweepResult {
  std::vector<EnvelopeRow> rows;  ///< ordered variant, train, speed, station (thread-independent)
  /// With SweepOptions::load_effects: ordered variant, train, speed, quantity.
  std::vector<QuantityRow> quantities;
  /// With vehicle models (train.vehicle sprung or multibody): ordered variant, train, speed.
  std::vector<VehicleRow> vehicles;
  std::vector<CaseFailure> failures;
  SweepSummary summary;
};

/// The governing case of one station and quantity: the largest value over variants, trains and
/// speeds, and where it occurs.
struct GoverningCase {
  double value = 0.0;  ///< [m/s²] or [m]
  std::string variant, train;
  double speed = 0.0;  ///< [m/s]
};

/// Per station, in the order of the envelope: its governing acceleration and deflection.
struct GoverningRow {
  std::string station;
  GoverningCase acc, disp;
};

/// The governing cases of an envelope; the first of equal values (in envelope order) wins.
std::vector<GoverningRow> governing(const std::vector<EnvelopeRow>& rows);

/// Runs one case; replaceable for tests. Default: simulate(). Not used by variants whose
/// settings ask for unit-response superposition (those run simulate_by_unit_response per speed).
using CaseRunner =
    std::function<RunResult(const PreparedModel&, const load::Train&, double speed, const RunSettings&)>;

struct SweepOptions {
  int threads = 1;           ///< >= 1; results are identical for any count
  ProgressSink progress;     ///< optional; called after each case
  CaseRunner runner;         ///< optional; default simulate()
  /// Also keep the signed extremes of every deck deflection and load effect (load_effects()) and
  /// their quasi-static extremes (SweepResult::quantities), with direct superposition. Modal
  /// variants keep them in the peaks kernel (a bearing force's inertia, damping and direct-load
  /// parts as solve::OutputSum); other cases run with histories (simulate(), batched Newmark).
  bool load_effects = false;
  /// Only the cases [case_begin, case_end) of the sweep's order — variant, train, speed, as
  /// count_cases() counts them — run and are reported (a shard of a sweep). A variant or train
  /// with no case in the range is not built; a job (a block of speeds, a speed of every train)
  /// that straddles an end runs whole, as in the full sweep, so every kept case is bit for bit
  /// the full sweep's. SweepSummary::n_cases counts the range.
  std::size_t case_begin = 0, case_end = static_cast<std::size_t>(-1);
  /// Optional: when it becomes true, jobs not yet started are skipped and fail with "cancelled"
  /// (the Python package's Ctrl-C); jobs running finish.
  const std::atomic<bool>* cancel = nullptr;
};

/// The cases of a sweep: over the variants, trains × the train's speeds.
std::size_t count_cases(const std::vector<Variant>& variants);

/// Prepares each variant's model once, in parallel (structure, stations, modes for the modal
/// method; a variant whose model cannot be built fails all its cases with the reason), then runs
/// every (variant, train, speed) case in parallel — or, for unit-response superposition, every
/// (variant, speed) with all trains at once. Failures
/// are recorded, never thrown; the rows of completed cases are kept.
SweepResult run_sweep(const std::vector<Variant>& variants, const SweepOptions& options);

}  // namespace viaduct::study
