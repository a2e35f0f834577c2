#pragma once
/// \file Simulated against measured: the same filter on both, time alignment, overlays and
/// metrics (the Old Guadiana paper's comparison, REFERENCE.md §1).

#include <limits>
#include <string>

#include "viaduct/core/types.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::study {

struct ComparisonOptions {
  FilterSpec filter;           ///< applied to record and model alike (at their own rates)
  double max_shift_s = 60.0;   ///< [s] alignment search range, > 0
  double spectrum_max_hz = 0;  ///< [Hz] upper end of the spectral metrics (0: filter high edge, or fs/2)
  /// [s] > 0: a record holding one value this long while the model's response moves is a stuck
  /// channel (InputError); the run must also be at least 16 samples long.
  double stuck_s = 0.05;
  /// [s] When finite: the record time of the model's t = 0, known (e.g. from a speed
  /// identification); no search. A record with an offset or a step biases the search.
  double shift_s = std::numeric_limits<double>::quiet_NaN();
};

/// One record channel against one model quantity, both in the same unit.
struct ChannelComparison {
  double shift_s = 0.0;               ///< [s] record time of the model's t = 0 (t_rec = t_model + shift)
  double peak_record = 0, peak_model = 0;  ///< max |filtered| over the overlap
  double peak_ratio = 0;              ///< model / record
  double rms_ratio = 0;               ///< model / record, over the overlap
  double correlation = 0;             ///< Pearson coefficient over the overlap, aligned
  double f_peak_record_hz = 0, f_peak_model_hz = 0;  ///< main peak of each amplitude spectrum (Hann)
  double spectral_correlation = 0;    ///< Pearson coefficient of the amplitude spectra up to spectrum_max_hz
  Vector t;                           ///< [s] record time grid
  Vector record, model;               ///< filtered; model aligned onto the record grid (0 outside it)
  Vector frequency_hz, record_amplitude, model_amplitude;  ///< spectra of the two aligned signals
};

/// `record` sampled at fs_record from t0_record; `model` at fs_model from 0. Throws InputError
/// for non-finite samples, too short signals or an invalid filter, and when the record cannot
/// carry the comparison (issue #36): the aligned model's response (where it exceeds 5 % of its
/// peak) runs past the record's ends — the record lost part of the passage — or the record holds
/// the same value for ComparisonOptions' stuck run or longer while the model's response moves (a
/// stuck channel); the message names the record's time span and the passage's.
ChannelComparison compare_channel(const Vector& record, double fs_record, double t0_record, const Vector& model,
                                  double fs_model, const ComparisonOptions& o);

/// What is left of a record once the model is taken out: white noise, or a structure the model
/// does not have (a zero offset, a step, a drift) that would otherwise pass for noise and widen
/// every band set by it (issue #36: a 20 mm step inflated a passage's noise and let a 3.2 x
/// peak pass as "within").
struct ResidualStructure {
  std::string kind = "white";  ///< "white", "offset", "step" or "drift"
  double size = 0.0;           ///< the offset, the step's height or the drift over the record (unit of the signal)
  double at_s = 0.0;           ///< [s] from the first sample: where the step is (step only)
  /// RMS of the residual of the model that explains it best (with the offset, step or drift
  /// taken out): the noise, not inflated by the structure.
  double noise_rms = 0.0;
  bool white() const { return kind == "white"; }
};
/// record ≈ a·model (a by least squares), or with an offset b, or b and a step c at one sample
/// (the best of every position between 5 % and 95 % of the record), or b and a linear drift: the
/// structure is reported when it explains at least half of what a·model leaves and is at least
/// 6 times the noise left after it. Same-size vectors of at least 16 samples at fs_hz.
ResidualStructure residual_structure(const Vector& record, const Vector& model, double fs_hz);

/// How a deflection or strain channel's zero is set before it is compared with the model (a
/// gauge's offset is no response): kept as recorded, the mean of the record before the train's
/// entry, or the mean over a window of record time.
struct ZeroSpec {
  enum class Mode { keep, pre_entry, window };
  Mode mode = Mode::keep;
  double start_s = 0.0, end_s = 0.0;  ///< [s] record time, window only
};
/// "pre-entry", "START:END" (seconds of record time) or "keep"; InputError naming `who`.
ZeroSpec parse_zero(const std::string& text, const std::string& who);

/// The level of a record over [from_s, to_s] of record time: mean and noise (standard
/// deviation about it).
struct Level {
  double mean = 0.0, noise = 0.0;
  double from_s = 0.0, to_s = 0.0;
  Index n = 0;
};
/// InputError naming `channel` and `who` when the span holds fewer than 10 samples (say which
/// fix: a window of the record's quiet part) or a missing sample.
Level level_between(const Vector& x, double fs_hz, double t0_s, double from_s, double to_s, const std::string& channel,
                    const std::string& who);

/// A warning, or "" : the level before the train's entry is an offset when it is beyond both
/// twice its noise and 1 % of the channel's peak |x| (a clean record's mean is not zero to the
/// last digit; a noisy one's wanders by its noise).
std::string offset_warning(const Level& pre_entry, double peak, const std::string& channel, const std::string& unit);

/// A warning, or "": the record and the model differ by a unit's factor over the whole passage
/// while their shapes agree — the peak and the RMS ratios (model / record) both within `band`
/// (1.2: 20 %, as a ratio either way) of
/// 9.80665 (g against m/s²), 1000 (mm against m, kN against N) or 1e6 (µε against ε), or of
/// their inverses, with a correlation of at least 0.8. A model that far off in amplitude alone,
/// with the record's shape, is rarer than a channel in another unit than its name says (a record
/// in g read as m/s² gave peak ratio 9.76, RMS ratio 9.71, correlation 0.9999 and no word).
std::string unit_slip_warning(double peak_ratio, double rms_ratio, double correlation, const std::string& channel,
                              double band = 1.2);

/// [s] The model's time at which its response first exceeds 1 % of its peak: the train's entry
/// as the station sees it (0 for a zero response).
double response_onset_s(const Vector& model, double fs_model);

/// The zero of one deflection or strain channel whose train enters at `entry_s` (record time;
/// NaN when unknown, which pre_entry refuses): keep leaves `x` and reports an offset
/// (offset_warning against max |x|; nothing when under 10 samples precede the entry); pre_entry
/// and window subtract their level from `x` (InputError naming `who` and the channel when the
/// span is too short).
struct ZeroOutcome {
  double removed = 0.0;     ///< the level subtracted (0 for keep)
  double level_seen = 0.0;  ///< keep: the mean before the entry
  std::string warning;      ///< keep: offset_warning's text, or empty
};
ZeroOutcome apply_zero(const ZeroSpec& z, Vector& x, double fs_hz, double t0_s, double entry_s, const std::string& channel,
                       const std::string& unit, const std::string& who);

}  // namespace viaduct::study
