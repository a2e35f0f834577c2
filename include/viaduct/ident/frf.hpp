#pragma once
/// \file Frequency response functions from force and response records: Welch H1/H2 and
/// coherence (random or impulsive excitation), stepped-sine processing (one FRF point per dwell)
/// and swept-sine processing (one long transform).
///
/// Convention (REFERENCE.md §6, SciPy): time dependence e^{iωt}, so a response y(t) = x(t − τ)
/// has H = e^{−iωτ} (phase −360°·f·τ); cross spectrum S_xy = conj(X)·Y; H1 = S_fa/S_ff,
/// H2 = S_aa/S_af, coherence |S_fa|²/(S_ff·S_aa). A sine a·cos ωt + b·sin ωt has the phasor
/// a − i·b, so that stepped-sine points, Welch estimates and the model's (K − ω²M + iωC)⁻¹
/// agree in sign.

#include <complex>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::ident {

using Complex = std::complex<double>;
using ComplexVector = Eigen::VectorXcd;
using ComplexMatrix = Eigen::MatrixXcd;

/// What an FRF's response is per unit force: the unit suffix of the response channel decides
/// (m → receptance, mps → mobility, mps2 → accelerance).
enum class FrfQuantity { receptance, mobility, accelerance };

/// Time derivatives of displacement the quantity is: 0 receptance, 1 mobility, 2 accelerance
/// (an FRF of that quantity is (iω)^k times the receptance).
int derivative_order(FrfQuantity q);

/// FrfQuantity of a record unit suffix ("m", "mps", "mps2"); InputError for any other unit.
FrfQuantity quantity_of_unit(const std::string& unit);
/// The unit suffix of a quantity ("m", "mps", "mps2").
std::string unit_of_quantity(FrfQuantity q);

/// FRFs of n_responses channels to one force, on one frequency axis. The responses' physical
/// quantity may differ per channel.
struct Frf {
  Vector frequency_hz;                 ///< [Hz] ascending, > 0 for the modal fits
  std::vector<std::string> responses;  ///< response names (without unit)
  std::vector<FrfQuantity> quantity;   ///< per response
  std::string force_unit = "N";        ///< unit suffix of the force channel
  ComplexMatrix h;                     ///< n_freq × n_responses [response unit / force unit]
  Matrix coherence;                    ///< n_freq × n_responses, in [0, 1]; empty if not estimated
  Index n_responses() const { return h.cols(); }
  /// InputError naming the first inconsistency (sizes, non-finite values, unsorted axis).
  void check(const std::string& what) const;
};

/// h converted to another quantity: multiplied by (iω)^k, k = target − source (accelerance =
/// (iω)² receptance). Requires f > 0 when dividing.
ComplexVector convert(const Vector& frequency_hz, const ComplexVector& h, FrfQuantity from, FrfQuantity to);

// ---------------------------------------------------------------------------------------------
// Welch H1 / H2 / coherence

struct WelchFrf {
  Vector frequency_hz;
  ComplexMatrix h1, h2;   ///< n_freq × n_responses
  Matrix coherence;       ///< n_freq × n_responses
  Index n_segments = 0;
};

/// H1, H2 and coherence of every column of `responses` against `force` (same length and rate)
/// by Welch averaging (signal::WelchOptions, SciPy defaults). Bins where the force has no power
/// get H = 0 and coherence 0. InputError for a zero or non-finite force, mismatched lengths or
/// invalid options.
WelchFrf welch_frf(const Vector& force, const Matrix& responses, double fs_hz, const signal::WelchOptions& o);

// ---------------------------------------------------------------------------------------------
// Stepped sine

/// One dwell of a stepped-sine test: constant drive frequency between two times.
struct SineStep {
  double t_start_s = 0.0;     ///< [s] record time where the dwell begins
  double t_end_s = 0.0;       ///< [s] where it ends, > t_start_s
  double frequency_hz = 0.0;  ///< [Hz] nominal drive frequency, > 0
};

/// A schedule of n_steps dwells of dwell_s each, from t0_s, frequencies evenly spaced from
/// f_start_hz to f_end_hz (both included; n_steps >= 1, f_start = f_end allowed for one step).
std::vector<SineStep> regular_schedule(double f_start_hz, double f_end_hz, Index n_steps, double dwell_s,
                                       double t0_s = 0.0);

/// How detect_steps() finds the dwells of a stepped-sine force.
struct StepDetectionOptions {
  double min_cycles = 20.0;    ///< [-] shorter runs of one frequency are not steps, >= 2
  double tolerance = 0.002;    ///< [-] relative change of the (median-smoothed) cycle frequency that starts a new step, > 0
  int smooth_cycles = 9;       ///< [-] cycles in the running median of the cycle frequencies, odd, >= 1
  double hysteresis = 0.1;     ///< [-] zero crossings are counted after the force has been below −hysteresis × its peak, in (0, 1)
  bool is_valid(std::string* why) const;
};

/// The dwells of a stepped-sine test found from the force alone (when no schedule was logged):
/// upward zero crossings (with hysteresis against noise), one frequency per cycle, a running
/// median (which keeps the steps' edges sharp), and a new step wherever it leaves the step's mean
/// by more than the tolerance for three cycles running. Each step spans whole cycles and ends
/// smooth_cycles/2 + 2 cycles before the detected change (never late); its frequency is the
/// median of its cycles.
/// InputError when the force has no steady sine of min_cycles.
std::vector<SineStep> detect_steps(const Vector& force, double fs_hz, double t0_s, const StepDetectionOptions& o = {});

struct SteppedSineOptions {
  double settle_cycles = 30.0;  ///< [-] drive cycles discarded at the start of every dwell, >= 0
  double settle_s = 0.0;        ///< [s] at least this much is discarded too, >= 0
  double min_cycles = 10.0;     ///< [-] cycles that must remain for the fit, >= 2
  int n_harmonics = 5;          ///< harmonics 2..n fitted for the distortion indicator, 1..20
  bool refine_frequency = true; ///< 4-parameter (IEEE 1057) fit of the drive frequency on the force
  bool is_valid(std::string* why) const;
};

/// One FRF point: what the sine fits of one dwell gave.
struct SteppedSinePoint {
  double frequency_hz = 0.0;   ///< [Hz] drive frequency (refined on the force when asked)
  double t_from_s = 0.0;       ///< [s] samples used: [t_from, t_to]
  double t_to_s = 0.0;
  double n_cycles = 0.0;       ///< drive cycles fitted
  Complex force;               ///< phasor of the force (amplitude |force|)
  ComplexVector response;      ///< phasor of each response
  ComplexVector h;             ///< response / force
  double force_distortion = 0.0;  ///< [-] THD+N: rms of all but the fundamental / its rms
  Vector response_distortion;     ///< [-] the same per response
  /// [-] |H(first half) − H(second half)| / |H| per response: large when the response had not
  /// settled (transient left) or the system drifts.
  Vector settle_change;
};

/// Fits each dwell of `schedule` in the record (samples at t0_s + k/fs_hz). InputError when a
/// dwell lies outside the record, leaves fewer than min_cycles after settling, exceeds the
/// Nyquist limit, or when the force is not a sine at the scheduled frequency (zero, or with
/// more rms outside the fundamental than in it, or refined more than 5 % away).
std::vector<SteppedSinePoint> stepped_sine(const Vector& force, const Matrix& responses, double fs_hz, double t0_s,
                                           const std::vector<SineStep>& schedule, const SteppedSineOptions& o = {});

/// Least-squares fit of a sine at frequency_hz (plus offset and harmonics 2..n_harmonics) to
/// x sampled at times t: returns the fundamental's phasor, and the THD+N ratio in distortion.
Complex fit_sine(const Vector& t, const Vector& x, double frequency_hz, int n_harmonics, double* distortion = nullptr);

/// Refines the frequency of a periodic signal x(t) by Gauss–Newton on the model
/// c + Σ_h (a_h cos hωt + b_h sin hωt), h = 1..n_harmonics (n_harmonics = 1: the 4-parameter
/// sine fit of IEEE 1057), from frequency_hz (which must be within a fraction of a cycle over the
/// record). Returns the refined frequency [Hz].
double refine_sine_frequency(const Vector& t, const Vector& x, double frequency_hz, int n_harmonics = 1);

// ---------------------------------------------------------------------------------------------
// Swept sine

struct SweptSineOptions {
  double f_min_hz = 0.0;  ///< [Hz] band kept, > 0
  double f_max_hz = 0.0;  ///< [Hz] band kept, > f_min_hz, < fs/2
  /// [-] bins whose force amplitude is below this fraction of the band's median are dropped
  /// (the sweep did not excite them); in [0, 1).
  double min_force_ratio = 0.1;
  bool is_valid(double fs_hz, std::string* why) const;
};

/// FRF of a swept-sine test as the ratio of the whole records' transforms, zero-padded to at
/// least twice their length (exact when the response has died out before the record ends):
/// H = conj(F)·Y / |F|² on the band. One-sweep estimate: no coherence.
Frf swept_sine(const Vector& force, const Matrix& responses, double fs_hz, const SweptSineOptions& o);

}  // namespace viaduct::ident
