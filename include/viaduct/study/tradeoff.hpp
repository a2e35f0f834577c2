#pragma once
/// \file Speed against accuracy: one scenario solved with a ladder of methods and settings,
/// each rung's envelope compared with a converged reference (`viaduct tradeoff`).

#include <string>
#include <vector>

#include "viaduct/study/sweep.hpp"

namespace viaduct::study {

/// One setting of the ladder.
struct TradeoffRung {
  std::string label;     ///< e.g. "modal 100 Hz +sc dt=1 ms"
  RunSettings settings;  ///< replaces the scenario's settings (filter and load factor kept)
};

/// Envelope error of one rung against the reference: for each (train, station) curve the
/// largest |x − x_ref| over speeds divided by the curve's largest |x_ref|; then the largest over
/// curves (and, per station, over trains).
struct TradeoffRow {
  std::string label;
  RunSettings settings;
  Index n_modes = 0;            ///< modal rungs: modes kept
  double wall_s = 0.0;          ///< [s] the whole sweep of this rung (model preparation included)
  std::size_t n_failed = 0;
  double max_acc_error = 0.0;   ///< [-] relative envelope error of the (filtered) acceleration
  double max_disp_error = 0.0;  ///< [-] relative envelope error of the deflection
  std::vector<double> station_acc_error, station_disp_error;  ///< per scenario station
};

struct TradeoffResult {
  TradeoffRow reference;          ///< errors 0 by definition
  std::vector<TradeoffRow> rungs;
  std::vector<std::string> stations;
};

/// The scenario's own ladder: Newmark at 4, 2, 1 and ½ × analysis.dt; modal bases up to 1, 1.5,
/// 2, 3 and 5 × the band edge f_c (filter.high_hz, or 30 Hz without filter: EN 1991-2's lowest
/// limit), each with and without the static correction; the presets "fast" and "default"; unit-response superposition of the
/// Newmark and modal rungs when the scenario has several trains; with `with_ida`, IDA at
/// rtol 1e-2, 1e-3 and 1e-4 (atol 1e-3·rtol m and 1e-1·rtol m/s; slow on track models).
std::vector<TradeoffRung> default_ladder(const Scenario& sc, bool with_ida = false);

/// Reference settings: Newmark at analysis.dt / 4 (or `reference_dt` when > 0).
RunSettings reference_settings(const Scenario& sc, double reference_dt = 0.0);

/// Runs the reference and every rung over the scenario's speeds and trains (its sweep variants
/// are not used). A rung whose cases fail is reported with n_failed and errors over the cases that
/// completed. Progress: called after each rung with (rungs done, rungs total).
TradeoffResult run_tradeoff(const Scenario& sc, const RunSettings& reference, const std::vector<TradeoffRung>& ladder,
                            int threads, const ProgressSink& progress = nullptr);

/// The band edge f_c the ladder and the presets scale with [Hz].
double band_edge_hz(const Scenario& sc);

/// Named presets (docs/accuracy.md gives their measured errors):
/// "fast": modal, modes up to 1.5 f_c, static correction, dt = 1/(16 f_c);
/// "default": modal, modes up to 3 f_c, static correction, dt = 1/(16 f_c);
/// "reference": Newmark, dt = 1/(80 f_c).
/// InputError for any other name.
RunSettings preset_settings(const std::string& name, const Scenario& sc);

}  // namespace viaduct::study
