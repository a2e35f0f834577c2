#pragma once
/// \file Recorded passages over the model's speed envelope: the check a monitoring campaign makes
/// (issue #19 part 5). Each passage's speed is identified from the train's signature (or given),
/// its peak per channel taken under the scenario's filter, and set against the model's peak for
/// that train at that speed and the model's envelope over the scenario's speeds.

#include <string>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/scenario.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// One record channel of a passage, mapped to a station.
struct PassageChannel {
  std::string name;         ///< the record's channel
  std::size_t station = 0;  ///< index into the prepared model's stations
  ResponseKind kind = ResponseKind::acceleration;
  Vector x;                 ///< in viaduct's units (m/s², m, µε), at the passage's rate, finite
};

/// One recorded passage of a train.
struct Passage {
  std::string name;       ///< how reports name it (the record's file)
  std::size_t train = 0;  ///< index into the trains given to run_passages
  double fs_hz = 0.0;     ///< [Hz] > 0
  double t0_s = 0.0;      ///< [s] time of the first sample
  /// At least one; the first is matched to the train's signature when the speed is identified.
  std::vector<PassageChannel> channels;
  double speed = 0.0;     ///< [m/s] known speed, > 0; 0: identified from the record
};

struct PassageOptions {
  double v_min = 40.0 / 3.6, v_max = 400.0 / 3.6;  ///< [m/s] identification range, 0 < v_min < v_max
  double grid_step = 0.01;   ///< relative step of the identification's coarse search, (0, 0.2]
  /// The predicted peak's range is taken over v ± speed_band × (the identification's standard
  /// error), as the speed command states its uncertainty (3 standard errors). >= 0.
  double speed_band = 3.0;
  /// A passage is within the model when its peak lies in [predicted_low − noise_band·noise,
  /// predicted_high + noise_band·noise]: the peak of a signal with Gaussian noise of RMS σ over
  /// the few samples near its maximum stays within 4σ of the noiseless peak but for about 1 in
  /// 10³ (P(|z| > 4) = 6e-5 a sample). > 0.
  double noise_band = 4.0;
  /// Deflection and strain channels' zero (keep: an offset before the train's entry is
  /// reported, and the residual's structure flags it; pre_entry or window: its mean removed).
  ZeroSpec zero;
  int threads = 1;         ///< >= 1; results do not depend on it
  ProgressSink progress;   ///< optional; called after each envelope case and each passage
  bool is_valid(std::string* why) const;
};

/// One channel of one passage against the model.
struct ChannelVerdict {
  std::string channel, station;
  ResponseKind kind = ResponseKind::acceleration;
  double measured = 0.0;        ///< max |filtered record| (unit of kind)
  double predicted = 0.0;       ///< max |filtered model| for the train at the passage's speed
  double predicted_low = 0.0;   ///< smallest and largest predicted peak over the speed's
  double predicted_high = 0.0;  ///< uncertainty (PassageOptions::speed_band)
  double ratio = 0.0;           ///< measured / predicted (NaN when predicted is 0)
  /// RMS of the filtered record minus the aligned model scaled by least squares over their
  /// overlap, an offset, step or drift taken out first when the residual holds one
  /// (residual_structure): the noise, and whatever the model's shape misses.
  double noise_rms = 0.0;
  /// "white", or the structure the residual holds ("offset", "step", "drift"; its size in the
  /// channel's unit): a record the model cannot judge (a zero offset kept, a step, a drift).
  std::string residual = "white";
  double residual_size = 0.0;
  double correlation = 0.0;     ///< of the filtered record and the aligned model
  double zero_removed = 0.0;    ///< the level subtracted (PassageOptions::zero; 0 when kept)
  std::string offset_warning;   ///< when kept: the level before the train's entry is an offset (offset_warning); not within
  double zero_level_seen = 0.0; ///< the level before the train's entry (when kept)
  /// The record and the model a unit's factor apart with the same shape (unit_slip_warning); not within.
  std::string unit_warning;
  /// See PassageOptions::noise_band; false when the residual is structured.
  bool within = false;
};

/// One passage's outcome; `failure` set (and no channels) when it could not be processed.
struct PassageResult {
  std::string name, train;
  double speed = 0.0;           ///< [m/s]
  double speed_se = 0.0;        ///< [m/s] standard error of the identification (0 when given), widened where speed_flags say
  bool identified = false;      ///< the speed was identified (not given)
  double signature_correlation = 0.0;  ///< of the identification's match (0 when given)
  /// What check_train_signature() says of an identified speed (a model that does not match the
  /// record); speed_se is then the widened standard error. Empty when given or when none applies.
  std::vector<std::string> speed_flags;
  std::vector<ChannelVerdict> channels;
  std::string failure;
  bool input_error = false;     ///< failure caused by the input (InputError)
};

/// The model's envelope of one train at one station and response: its filtered peak at each of
/// the scenario's speeds.
struct EnvelopeCurve {
  std::string train, station;
  ResponseKind kind = ResponseKind::acceleration;
  std::vector<double> speeds;  ///< [m/s] ascending
  std::vector<double> peaks;   ///< max |filtered model|, unit of kind
};

struct PassageStudy {
  std::vector<PassageResult> passages;  ///< in input order
  std::vector<EnvelopeCurve> curves;    ///< per train used, station, response (in channel order)
  /// Envelope cases that failed ("TRAIN at V km/h: why"); their curves go without those speeds.
  std::vector<std::string> envelope_failures;
};

/// The peak of a signal as passages are compared: max |x filtered by f| (zero-phase, at fs),
/// taken between samples (parabolic vertex) when filtered.
double filtered_peak(const Vector& x, double fs_hz, const FilterSpec& f);

/// Runs the check: the model `m` (prepared for `settings` with every station the passages map,
/// and with load effects when a channel is a strain) under each train used at every speed of
/// `speeds` (the envelope), and every passage: its speed identified from its first channel
/// (match_signature over [v_min, v_max], filtered as filter_for() says), or taken as given, the
/// model run at it and at its uncertainty's ends, each channel's peak and noise. Every response is
/// filtered with filter_for(filter, kind), record and model alike (settings.filter is ignored: the
/// model runs unfiltered). A passage that fails is recorded and the others go on. InputError for
/// invalid options, no speeds or a passage naming a train or station out of range.
PassageStudy run_passages(const PreparedModel& m, const RunSettings& settings, const FilterSpec& filter,
                          const std::vector<load::Train>& trains, const std::vector<double>& speeds,
                          const std::vector<Passage>& passages, const PassageOptions& options);

}  // namespace viaduct::study
