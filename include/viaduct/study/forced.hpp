#pragma once
/// \file Forced vibration of the model: FRFs by a direct frequency-domain solve and a simulated
/// shaker test (stepped or swept sine, Newmark) that writes synthetic records with the model's
/// known modal properties.

#include <string>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/ident/frf.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// Where the exciter pushes and what is read.
struct ForcedSetup {
  double force_x_m = 0.0;  ///< [m] global x of the exciter on the deck (positive down, like the loads)
  /// Response points: deck stations read the deck, rail stations the rail (resolve_stations).
  std::vector<StationSpec> responses;
  ident::FrfQuantity quantity = ident::FrfQuantity::accelerance;  ///< what the responses are
};

/// Deck station named `name` at global x [m] (span found from x; InputError outside the deck).
StationSpec deck_station_at(const model::Structure& s, const std::string& name, double x_m);

/// FRFs of the responses to a unit force at force_x_m: (K − ω²M + iωC) x = F solved directly
/// (sparse LU, pattern analysed once per thread) at each frequency [Hz] (> 0, ascending), then
/// read at the responses and multiplied by (iω)^k for mobility/accelerance. Frequencies are
/// spread over `threads`. SolverError when the matrix is singular (an undamped resonance hit
/// exactly); InputError for points off the model or bad frequencies.
ident::Frf model_frf(const model::Structure& s, const ForcedSetup& setup, const Vector& frequency_hz, int threads = 1,
                     const ProgressSink& progress = {});

/// A simulated shaker test.
struct ShakerTest {
  enum class Kind { stepped, swept };
  Kind kind = Kind::stepped;
  double amplitude_N = 10e3;      ///< [N] force amplitude (a 50 kN exciter runs at a fraction), > 0
  std::vector<ident::SineStep> steps;  ///< stepped: dwells, contiguous from t = 0, phase-continuous
  double sweep_f_start_hz = 0.0;  ///< swept: linear sweep from, > 0
  double sweep_f_end_hz = 0.0;    ///< swept: to, > start
  double sweep_s = 0.0;           ///< [s] swept: duration of the sweep, > 0
  double tail_s = 0.0;            ///< [s] recording after the force stops (swept: let it die out), >= 0
  double fs_hz = 500.0;           ///< [Hz] sampling rate of the record, > 2·highest drive frequency
  /// Newmark steps per sample; 0: enough that 2π·f_max·dt <= 0.03, so the discrete system's
  /// period error (ω dt)²/12 stays below 1e-4 at the drive frequencies.
  int substeps = 0;
  double noise_snr_db = -1.0;     ///< Gaussian noise at this SNR on every channel (< 0: none)
  unsigned seed = 1;              ///< of the noise
  bool is_valid(std::string* why) const;
  double duration_s() const;      ///< [s] record length
  double max_frequency_hz() const;
};

/// What the simulated test recorded: force and responses at fs_hz from t = 0.
struct ShakerRecord {
  double fs_hz = 0.0;
  Vector force;                   ///< [N]
  Matrix responses;               ///< n_samples × n_responses, unit of setup.quantity
  std::vector<std::string> names; ///< response names
  Index n_steps = 0;              ///< Newmark steps taken
  double wall_s = 0.0;
};

/// Integrates the structure from rest under the exciter force (Newmark, average acceleration)
/// and samples force and responses. InputError for invalid tests or setups.
ShakerRecord simulate_shaker_test(const model::Structure& s, const ForcedSetup& setup, const ShakerTest& test,
                                  const ProgressSink& progress = {});

/// The undamped modes of a model seen at measured responses (the last step of the
/// identification workflow: modes from FRFs against the model, by MAC). Each response is a
/// station of `sc` or a deck position given in `sensors_x` [m, global]; modes up to f_max_hz.
struct ModelModesAtResponses {
  Vector frequency_hz;        ///< [Hz] per mode
  ident::ComplexMatrix shape; ///< n_responses × n_modes (real shapes stored as complex, for ident::mac)
};
/// InputError naming a response that is neither a station nor a sensor.
ModelModesAtResponses model_modes_at(const Scenario& sc, const std::vector<std::string>& responses,
                                     const std::vector<std::pair<std::string, double>>& sensors_x, double f_max_hz);

}  // namespace viaduct::study
