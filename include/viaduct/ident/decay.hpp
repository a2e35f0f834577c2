#pragma once
/// \file Frequency and damping of one mode from the free vibration after a train has left the
/// bridge: isolate the mode with a zero-phase band-pass, find where the free decay starts, and
/// estimate by logarithmic decrement, an exponential fit of the cycle peaks and the Hilbert
/// envelope; damping and frequency along the decay as functions of amplitude; statistics over
/// many passages.
///
/// Viscous model of the isolated mode: x(t) = A e^{−σt} cos(ω_d t + φ), σ = ζωₙ,
/// ω_d = ωₙ√(1 − ζ²). Reported frequencies are undamped natural frequencies ωₙ/2π, from the
/// measured ω_d and σ; with amplitude-dependent damping the same holds window by window.

#include <limits>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::ident {

struct DecayOptions {
  double frequency_hz = 0.0;   ///< [Hz] the mode to isolate (a guess), > 0
  double band_ratio = 0.15;    ///< [-] band-pass from f·(1 − r) to f·(1 + r), in (0, 0.9)
  int filter_order = 2;        ///< [-] Chebyshev I order of the band-pass (2·order poles), 1..8; 0: no filter
  double ripple_db = 0.1;      ///< [dB] its passband ripple, > 0
  /// [s] start of the free decay in record time; NaN: detected as the first cycle peak after
  /// which the peaks only fall (see rise_tolerance), after the largest one.
  double start_s = std::numeric_limits<double>::quiet_NaN();
  /// [s] end of the analysis; NaN: where the envelope falls to noise_factor × the noise floor
  /// (the envelope's median over the record's last 5 %) or the record ends.
  double end_s = std::numeric_limits<double>::quiet_NaN();
  double noise_factor = 5.0;   ///< [-] >= 1
  double skip_cycles = 4.0;    ///< [-] cycles left out after the start (filter transients), >= 0
  double min_cycles = 5.0;     ///< [-] a decay shorter than this is an InputError, >= 2
  double window_cycles = 4.0;  ///< [-] window of the amplitude-dependent estimates, >= 1
  /// [-] start detection: a rise from one half-cycle peak to the next by more than this fraction
  /// plus twice the noise floor ends a decay (the start is the peak after the last such rise), > 0
  double rise_tolerance = 0.02;
  bool is_valid(double fs_hz, std::string* why) const;
};

/// Local estimate over one window of the decay.
struct AmplitudePoint {
  double t_s = 0.0;           ///< [s] window centre
  double amplitude = 0.0;     ///< envelope at the centre, in the record's unit
  double frequency_hz = 0.0;  ///< [Hz] natural frequency in the window
  double damping_ratio = 0.0; ///< [-]
};

struct DecayResult {
  double start_s = 0.0;        ///< [s] start of the free decay (given or detected)
  bool start_detected = false;
  double end_s = 0.0;          ///< [s] end of the analysis window
  double n_cycles = 0.0;       ///< cycles analysed
  /// [Hz] natural frequency from the upward zero crossings (least squares, weighted by the
  /// envelope², as their timing error is about noise/(amplitude·ω)) and the envelope fit's σ
  double frequency_hz = 0.0;
  /// [-] logarithmic decrement from the first positive peak to the last one above e^{-2} of it
  /// (at least two cycles)
  double zeta_log_decrement = 0.0;
  double zeta_envelope_fit = 0.0;   ///< [-] line through the logs of all half-cycle peaks (weights peak²)
  /// [-] rms residual of that line (in ln units): about the noise-to-amplitude ratio for one
  /// viscous mode; larger when the envelope is not exponential (two modes beating in the band,
  /// amplitude-dependent damping, forcing left in the window)
  double envelope_residual = 0.0;
  double zeta_hilbert = 0.0;        ///< [-] line through the log Hilbert envelope (weights envelope²)
  double frequency_hilbert_hz = 0.0;  ///< [Hz] from the slope of the analytic signal's phase
  double amplitude_start = 0.0;  ///< envelope at the start of the analysis window
  double amplitude_end = 0.0;    ///< envelope at its end
  std::vector<AmplitudePoint> by_amplitude;  ///< windows of window_cycles, one cycle apart
  /// Least-squares laws over the windows: ζ(A) = zeta0 + zeta_slope·A, f(A) = f0 + f_slope·A.
  double law_zeta0 = 0.0, law_zeta_slope = 0.0, law_f0_hz = 0.0, law_f_slope_hz = 0.0;
};

/// Analyses the free decay of one mode in x (sampled at fs_hz, first sample at t0_s).
/// InputError for invalid options, a record with NaN, a decay shorter than min_cycles, or a
/// start/end outside the record.
DecayResult analyse_decay(const Vector& x, double fs_hz, double t0_s, const DecayOptions& o);

/// [s] When the last axle leaves the bridge: entry of the first axle + (train length + bridge
/// length) / speed. All > 0 except entry_s.
double passage_end_time(double entry_s, double train_length_m, double bridge_length_m, double speed_mps);

/// Mean, sample standard deviation and count of one estimate over passages.
struct Statistic {
  double mean = 0.0, std = 0.0;
  std::size_t n = 0;
};
Statistic statistic(const std::vector<double>& values);

}  // namespace viaduct::ident
