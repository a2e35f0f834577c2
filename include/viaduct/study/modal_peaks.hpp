#pragma once
/// \file The fused modal kernel of envelope sweeps.
///
/// A sweep only keeps each station's maximum |acceleration| and |deflection|. With the modal
/// method each case reduces to one tight loop: the train's modal loads read from a table folded
/// once per train, the exact step of every modal equation (classical modes) or complex coordinate
/// (damping that couples the modes, in split real arithmetic), the station outputs and their
/// running maxima, four speeds in SIMD lanes. With a filter the station accelerations are
/// recorded and filtered as simulate() filters them (nothing else is kept). Same model, same
/// step, same values as peaks(simulate(...)) up to rounding (tests/unit/study/test_modal_peaks.cpp);
/// only the bookkeeping is gone.

#include <memory>
#include <vector>

#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// A train's modal loads along the load path, Σₖ Pₖ g(X − oₖ) for every load channel g (and
/// every static-correction residual), as one piecewise cubic in the head position X [m]: the
/// per-element cubics of the unit-axle table re-expanded on the merged breakpoints of all axles,
/// so the fold is exact. Speed-independent: built once per (model, train), used at every speed.
struct TrainModalLoads {
  std::vector<double> breaks;  ///< [m] head positions, ascending; piece i is [breaks[i], breaks[i+1])
  /// Per piece, 4 powers of s = X − breaks[i] (s⁰ … s³), each with n_channels values; one more
  /// block of zeros follows for X beyond the last break (every axle has left).
  std::vector<double> coef;
  std::size_t n_modes = 0;    ///< load channels (one per classical mode; re and im per complex pair)
  std::size_t n_outputs = 0;  ///< residual channels (static correction only; else 0)
  std::size_t n_channels = 0; ///< n_modes + n_outputs
  double train_length = 0.0;  ///< [m] first to last axle
  double x_start = 0.0, x_end = 0.0;  ///< [m] the load path
};

/// True when modal_peaks() can run the cases of `m` under `s`: modal method (prepared for it) and
/// direct superposition.
bool modal_peaks_apply(const PreparedModel& m, const RunSettings& s);

/// Folds `train` (loads × load_factor, > 0) over the unit-axle table of `m` (prepared for the
/// modal method). InputError for an invalid train or a model without a modal table.
std::shared_ptr<const TrainModalLoads> fold_train(const PreparedModel& m, const load::Train& train,
                                                  double load_factor);

struct PeaksRun {
  std::vector<StationPeaks> peaks;  ///< per station, as peaks() of the full run
  Index n_steps = 0;
  double wall_s = 0.0;  ///< [s]
};

/// One case: the train of `loads` at `speed` [m/s, > 0] from the entry of its first axle until
/// settings.free_vibration_s after the last has left, sampled every settings.newmark.dt (the
/// steps of simulate()). Needs modal_peaks_apply(m, settings). SolverError when the state stops
/// being finite.
PeaksRun modal_peaks(const PreparedModel& m, const TrainModalLoads& loads, double speed, const RunSettings& settings);
/// The same at several speeds (one result each, in order), four at a time in lock-step: the
/// arithmetic of four cases runs in SIMD lanes. Faster than one call per speed.
std::vector<PeaksRun> modal_peaks(const PreparedModel& m, const TrainModalLoads& loads, const std::vector<double>& speeds,
                                  const RunSettings& settings);

}  // namespace viaduct::study
