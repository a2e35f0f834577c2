#pragma once
/// \file Train speed from a record, as the Old Guadiana authors did from the frequency of the
/// bogie (shared-axle) distance: a train of regular spacing d passing at v excites lines at
/// k·v/d. Two estimators: the spectral comb, and the spacing of axle-passage peaks.

#include <functional>
#include <limits>

#include "viaduct/core/types.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/study/scenario.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

struct SpeedEstimate {
  double speed = 0.0;        ///< [m/s]
  double uncertainty = 0.0;  ///< [m/s] spectral: speed step of one frequency bin at the highest
                             ///< harmonic used; peaks: standard error of the mean spacing
  double frequency_hz = 0.0; ///< spectral: the identified fundamental v/d
  int n_used = 0;            ///< harmonics (spectral) or peak intervals (peaks) used
  /// How far the train stands above the record's noise: spectral, the geometric mean over the
  /// harmonics of each line's amplitude over the spectrum's median in its search band; peaks, the
  /// largest peak's prominence over the noise RMS (of the first differences, robust). Below
  /// kMinSpectralDetection / kMinPeakDetection no train is found (InputError).
  double detection = 0.0;
};

/// A train's lines stand this many times above the spectrum's median: white or low-passed noise
/// reached 2.6 and 3.8 at its best speed (200 records of 10 s to 2 min), a regular train's
/// passage 9.8 (tests/unit/study/test_speed.cpp).
constexpr double kMinSpectralDetection = 5.0;
/// Axle peaks stand this many noise RMS (from the first differences) out of the record: white
/// noise reached 8.8, a train's deflection 75. Smooth noise fools the differences; the intervals'
/// regularity (most within 15 % of their median) catches it.
constexpr double kMinPeakDetection = 10.0;
/// The axle peaks' median prominence stands this many times above every smaller peak's.
constexpr double kMinPeakSeparation = 4.0;
/// A record whose best match to the train's signature correlates less is no passage of it.
constexpr double kMinSignatureCorrelation = 0.5;

/// Spectral comb: maximises Σ_k log A(k·v/d), k = 1..n_harmonics, over v in [v_min, v_max] on the
/// Hann amplitude spectrum A of x (interpolated between bins), refined by a parabola.
/// d [m] > 0, 0 < v_min < v_max, fs_hz > 0. InputError if the harmonics leave the spectrum, and
/// "no train found" when the channel is constant or the lines do not stand kMinSpectralDetection
/// times above the spectrum's median (never a speed out of noise).
SpeedEstimate speed_from_spectrum(const Vector& x, double fs_hz, double d, double v_min, double v_max,
                                  int n_harmonics = 4);

/// Axle passages: the median interval between consecutive peaks of x (e.g. a deflection or
/// strain under the rails) at least `min_interval_s` apart and with at least 10 % of the
/// largest prominence, v = d / interval, using only intervals within 15 % of the median.
/// Needs at least 3 peaks. InputError "no train found" when the largest peak stands less than
/// kMinPeakDetection noise RMS out, and when the speed lies outside [v_min, v_max] (the range
/// searched: 0 and +infinity for none).
SpeedEstimate speed_from_peaks(const Vector& x, double fs_hz, double d, double min_interval_s, double v_min = 0.0,
                               double v_max = std::numeric_limits<double>::infinity());

/// The speed and timing of a passage from the shape of its signal: the record against the
/// signal expected at each trial speed (for a train on a bridge model, the station's simulated
/// response; for two sensors, the other sensor's record).
struct SignatureMatch {
  double speed = 0.0;        ///< [m/s] (for the delay of two sensors: the delay [s])
  double speed_se = 0.0;     ///< [m/s] standard error (least squares, residual noise band-limited)
  double shift_s = 0.0;      ///< [s] record time of the template's t = 0
  double shift_se = 0.0;     ///< [s] standard error
  double amplitude = 0.0;    ///< record ≈ amplitude × template (1 for a model that matches)
  double correlation = 0.0;  ///< of the filtered record and the aligned, scaled template
  Index n_evaluations = 0;   ///< templates computed
  double n_effective = 0.0;  ///< independent samples the standard errors assume (N × 2B/fs)
};

struct SignatureOptions {
  double v_min = 40.0 / 3.6, v_max = 400.0 / 3.6;  ///< [m/s] range searched, 0 < v_min < v_max
  double grid_step = 0.01;   ///< relative step of the first, coarse search (log-spaced speeds)
  FilterSpec filter;         ///< applied to record and template alike (disabled: none)
  double max_shift_s = 600.0;  ///< [s] alignment search range
};

/// Maximises over v the correlation of the filtered record with the filtered template_at(v)
/// (sampled at fs_template from its t = 0) aligned by cross-correlation: a log-spaced grid
/// (grid_step), then golden-section refinement around the best point to 1e-6 relative. The
/// standard errors come from the least-squares fit of amplitude, speed and shift at the optimum
/// (Jacobian by central differences), with the residual's variance and N × 2B/fs independent
/// samples (B: the filter's band; fs/2 without a filter); the residual holds the noise and any
/// mismatch of the template, so both widen them. InputError for bad ranges, too short or
/// non-finite signals.
SignatureMatch match_signature(const Vector& record, double fs_hz, double t0_s, const std::function<Vector(double)>& template_at,
                               double fs_template, const SignatureOptions& o);

/// The filter a train's signature is matched under: filter_for(scenario_filter, kind), with
/// deflection and strain low-passed even when the scenario's filter is off (only the noise
/// above the band goes; their axle peaks are looked for under it too).
FilterSpec signature_filter(const FilterSpec& scenario_filter, ResponseKind kind);

/// A record channel at a model's station matched to a train's signature: match_signature with
/// the station's simulated response (`settings`, run unfiltered) as the template, record and
/// template filtered with signature_filter(), alignment searched over the record's duration + 60 s. `m` holds the station (with load effects for a strain). What
/// `viaduct speed --model` and `viaduct passages` identify speeds with. InputError "no train
/// found" when the best match correlates below kMinSignatureCorrelation.
SignatureMatch match_train_signature(const PreparedModel& m, const RunSettings& settings, const load::Train& train, std::size_t station,
                                     ResponseKind kind, const Vector& record, double fs_hz, double t0_s, const FilterSpec& scenario_filter,
                                     double v_min, double v_max, double grid_step = 0.01);

/// The delay of sensor b behind sensor a (both sampled at fs from the same start) by
/// cross-correlation of the filtered channels, refined by a parabola; standard error from the
/// least-squares fit b ≈ c + g·a(t − delay) as in match_signature. For two sensors d metres apart
/// along the track the speed is d / delay.
struct Delay {
  double delay_s = 0.0, delay_se = 0.0, correlation = 0.0;
};
Delay delay_between(const Vector& a, const Vector& b, double fs_hz, const FilterSpec& filter, double max_delay_s);

/// One axle of a train at a station: when the identified speed and entry time say it passes,
/// and the record's peak that matched it where the channel sees single axles (a deflection or
/// strain whose influence line is shorter than the axle spacing: short spans, rails, cross-girders).
struct AxlePassage {
  std::size_t axle = 0;     ///< index in the train
  double offset_m = 0.0;    ///< [m] behind the first axle
  double load_n = 0.0;      ///< [N]
  double t_s = 0.0;         ///< [s] record time it passes: entry + offset / v
  double t_se = 0.0;        ///< [s] standard error, from the entry's and the speed's
  bool seen = false;        ///< a peak of the record matched it
  double peak_t_s = 0.0;    ///< [s] the matched peak's time (refined between samples)
  double peak_value = 0.0;  ///< the matched peak's value (the channel's unit)
};

struct AxleMatch {
  std::vector<AxlePassage> axles;  ///< in the train's order
  std::size_t n_seen = 0;
  double rms_residual_s = 0.0;     ///< [s] RMS of peak_t_s − t_s over the axles seen (0 if none)
  double tolerance_s = 0.0;        ///< [s] largest |peak − axle| accepted
};

/// The axles' passing times at a station (entry_s: the first axle's, as match_signature gives it
/// with the station's distance; speed [m/s] > 0) matched to the peaks of x (sampled at fs from
/// t0, filtered with `filter` when enabled): peaks with at least min_prominence × the largest
/// prominence, paired one to one with the axles, nearest pairs first, within a tenth of the
/// shortest time between two axles that are apart (at least three samples). Axles closer than the
/// channel resolves share one peak, so one of them goes unseen: the count says what the channel
/// sees. InputError for invalid arguments.
AxleMatch match_axles(const Vector& x, double fs_hz, double t0_s, const load::Train& train, double speed, double speed_se, double entry_s,
                      double entry_se, const FilterSpec& filter, double min_prominence = 0.1);


/// Speed and timing from the train's geometry alone (issue #39 item 5): the peaks of a deflection
/// or strain channel that sees axles or bogies one by one, matched to the train's axle groups.
struct TrainTimingOptions {
  double v_min = 40.0 / 3.6, v_max = 400.0 / 3.6;  ///< [m/s] range searched, 0 < v_min < v_max
  /// [m] axles closer than this merge into one group (a bogie) at their load-weighted mean
  /// offset; 0: the record chooses among every axle, bogies (3.5 m) and neighbouring bogies (8 m)
  /// the grouping it matches best.
  double merge_m = 0.0;
  FilterSpec filter;            ///< applied first (a low-pass); disabled: none
  double min_prominence = 0.1;  ///< peaks kept: at least this share of the largest prominence, (0, 1)
};
struct TrainTiming {
  double speed = 0.0, speed_se = 0.0;   ///< [m/s] least squares of the matched peak times, se from their residual
  double entry_s = 0.0, entry_se = 0.0; ///< [s] record time the first axle passes the sensor
  double merge_m = 0.0;                 ///< [m] the grouping used
  std::size_t n_groups = 0, n_matched = 0, n_peaks = 0;
  double rms_residual_s = 0.0;          ///< [s] of the matched peaks about the fitted times
};
/// Peaks (orientation from the largest excursion about the median; parabolic refinement) and
/// groups are paired for every trial speed on a log grid fine enough that the train's length
/// drifts by less than the pairing tolerance (a sixth of the shortest time between groups, at
/// least 2 samples), the best count kept (ties: the smaller residual), then times = entry +
/// offset / v fitted by least squares and re-paired until stable. InputError "no train found"
/// when fewer than 3 groups, or under half of them, are matched.
TrainTiming speed_from_train(const Vector& x, double fs_hz, double t0_s, const load::Train& train, const TrainTimingOptions& o);

/// What a train-signature match cannot say of itself (issue #39 item 5): its standard error
/// counts the residual as noise, not a shape the model gets wrong (a span too long stretches the
/// response in time), so a mismatched model gives a tight speed that is off. Checks that do not
/// trust the model, as `viaduct speed --model` and `viaduct passages` apply them:
/// - a deflection or strain whose channel sees the axle groups: the speed from the train's
///   geometry alone (speed_from_train, searched over v_min … v_max); a flag where the two
///   disagree by more than 3 standard errors of both. A channel that merges the axles has no
///   such check.
/// - the match's correlation below 0.9 (kFlagSignatureCorrelation) and its amplitude outside
///   0.5–2 × the model: flags (a model or a unit to check).
/// When any flag is raised and the timing was found, the standard error is widened so that 3 of
/// them cover the timing's interval too: (|Δv| + 3 se_timing) / 3, and a last flag says so.
struct SignatureCheck {
  std::vector<std::string> flags;  ///< sentences, empty when none applies
  double speed_se = 0.0;           ///< [m/s] the match's standard error, widened as above
  bool timing_checked = false;     ///< the model-free timing was found and compared
  double timing_speed = 0.0, timing_speed_se = 0.0;  ///< [m/s] its result when checked
  double timing_entry_s = 0.0, timing_entry_se = 0.0; ///< [s] its first axle's passing time at the sensor
};
constexpr double kFlagSignatureCorrelation = 0.9;
SignatureCheck check_train_signature(const SignatureMatch& m, const load::Train& train, ResponseKind kind, const Vector& record,
                                     double fs_hz, double t0_s, const FilterSpec& scenario_filter, double v_min, double v_max);

}  // namespace viaduct::study
