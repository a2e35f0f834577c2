#pragma once
/// \file IIR filter design as second-order sections and zero-phase filtering, matching SciPy
/// (`scipy.signal.cheby1(..., output='sos')`, `sosfilt`, `sosfilt_zi`, `sosfiltfilt`).

#include <array>
#include <complex>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::signal {

/// One biquad [b0, b1, b2, a0, a1, a2] with a0 = 1 (SciPy's sos row layout).
using Section = std::array<double, 6>;

/// Cascade of second-order sections; the overall gain sits in the first section.
struct Sos {
  std::vector<Section> sections;
  std::size_t n_sections() const { return sections.size(); }
  /// Complex gain at frequency f_hz for sampling rate fs_hz.
  std::complex<double> response(double f_hz, double fs_hz) const;
};

enum class BandType { lowpass, highpass, bandpass };

/// Chebyshev type I design, SciPy convention: the single-pass gain first drops below
/// -ripple_db at the edge frequencies. Order N gives N poles (2N for band-pass).
/// low_hz is used by highpass and bandpass, high_hz by lowpass and bandpass;
/// 0 < low_hz < high_hz < fs_hz/2. Throws InputError naming the violated constraint.
struct Cheby1Spec {
  int order = 3;            ///< [-] 1..12
  double ripple_db = 0.5;   ///< [dB] passband ripple, > 0
  BandType band = BandType::bandpass;
  double low_hz = 1.0;      ///< [Hz]
  double high_hz = 30.0;    ///< [Hz] (the schema's filter.high_hz: EN 1991-2's lowest cut-off)
  bool is_valid(double fs_hz, std::string* why) const;
};
Sos cheby1(const Cheby1Spec& spec, double fs_hz);

/// Causal filtering with initial state zi (n_sections × 2, transposed direct form II), or zero
/// state when zi is empty. Writes y (resized to x.size()).
/// zf, when given, receives the final state (same layout).
void sosfilt(const Sos& sos, const Vector& x, Vector& y, const std::vector<std::array<double, 2>>* zi = nullptr,
             std::vector<std::array<double, 2>>* zf = nullptr);

/// Steady-state initial conditions for a unit step (SciPy `sosfilt_zi`).
std::vector<std::array<double, 2>> sosfilt_zi(const Sos& sos);

/// Default pad length of SciPy's sosfiltfilt: 3·(2·n_sections + 1 − (#b2 == 0 ∧ … ), see code).
std::size_t default_padlen(const Sos& sos);

/// Zero-phase forward–backward filtering with odd extension of `padlen` samples at each end
/// and steady-state initial conditions (SciPy `sosfiltfilt` defaults). The magnitude is
/// squared: band edges sit at -2·ripple_db. Requires x.size() > padlen (InputError otherwise).
Vector sosfiltfilt(const Sos& sos, Eigen::Ref<const Vector> x);  // x read in place (a numpy array, a matrix column)

/// Zero-phase forward–backward filtering of a signal that is zero before its first sample and
/// after its last (a simulated response that starts at rest and is cut at the record's end):
/// the forward pass starts from rest; the backward pass starts in the state it would reach after
/// running back over the forward pass's infinite free ringing beyond the record (a 2·n_sections
/// Stein equation, solved by doubling: exact, no padding). The result is the zero-phase filter of
/// the zero-extended signal, so appending zeros to a record changes nothing and two records of
/// the same response at different rates give the same filtered maxima (the odd extension of
/// sosfiltfilt spans padlen samples, a length in time that changes with the rate, and moves
/// maxima a second away by per cent). Any length, including 0.
Vector filtfilt_from_rest(const Sos& sos, const Vector& x);

/// filtfilt_from_rest of one filter for many records: the backward pass's start map (the
/// doubling, as long as filtering a record of a few thousand samples) built once. The same
/// numbers as filtfilt_from_rest. InputError for an unstable filter.
class FiltfiltFromRest {
 public:
  explicit FiltfiltFromRest(const Sos& sos);
  Vector operator()(const Vector& x) const;
  /// Several records at once, each the numbers operator() gives it (the same operations in the
  /// same order): records of any lengths, taken four at a time so that their chains of dependent
  /// operations overlap in the processor (a sweep filters every case's record).
  std::vector<Vector> operator()(const std::vector<Vector>& xs) const;

 private:
  Sos sos_;
  Matrix W_;  // the forward pass's end state → the backward pass's start state
};

}  // namespace viaduct::signal
