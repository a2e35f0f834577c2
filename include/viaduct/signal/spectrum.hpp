#pragma once
/// \file Spectra with SciPy's conventions (REFERENCE.md §6): one-sided amplitude spectrum,
/// Welch power and cross spectral densities (`scipy.signal.welch` / `csd`).

#include <complex>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::signal {

using ComplexVector = Eigen::VectorXcd;

/// Forward real-to-complex FFT of x (size n >= 1): X_k = Σ x_j e^{-2πi jk/n}, k = 0..n/2.
/// FFTW underneath; plans are made once per size (FFTW_ESTIMATE, serialised: FFTW's planner is
/// not thread-safe) and shared by all threads (execution is). Safe to call from any thread.
ComplexVector rfft(const Vector& x);

/// Inverse of rfft for an n-point real signal (X holds n/2 + 1 bins): x_j = (1/n) Σ X_k e^{2πi jk/n}.
Vector irfft(const ComplexVector& X, Index n);

/// Lag of y against x that maximises their cross-correlation, in samples, refined by a parabola
/// (y[j] ≈ g·x[j - lag]); lags searched in [-max_lag, max_lag]. FFT-based, O(n log n).
double best_lag(const Vector& x, const Vector& y, Index max_lag);

/// e with 2^e near max|x| when max|x| lies outside [1e-100, 1e100], else 0: squares and sums of
/// squares of such samples would overflow (underflow), so the functions here work on 2^-e·x,
/// which is exact, and scale their results back (an InputError if the result itself overflows).
int overflow_exponent(const Vector& x);

/// Frequencies [Hz] of the n/2 + 1 bins of an n-point rfft at sampling rate fs_hz.
Vector rfft_frequencies(Index n, double fs_hz);

enum class Window { rectangular, hann };
enum class Detrend { none, constant, linear };
/// The window named `name`: "hann", "rectangular" (or SciPy's "boxcar"); InputError
/// "<key> must be hann or rectangular, got '...'" otherwise. The CLI and the Python package read
/// their window options through it.
Window window_of(const std::string& name, const std::string& key = "window");
/// The detrending named `name`: "constant", "linear" or "none"; InputError naming `key` otherwise.
Detrend detrend_of(const std::string& name, const std::string& key = "detrend");

/// Window of n points; hann is SciPy's periodic ("DFT-even") window used for spectral analysis.
Vector make_window(Window w, Index n);

/// One-sided amplitude spectrum of a whole record: A_k = 2|X_k| / Σw (DC and, for even n, the
/// Nyquist bin not doubled). With the rectangular window Σw = N and a sine of amplitude a on a
/// bin reads exactly a.
struct AmplitudeSpectrum {
  Vector frequency_hz;
  Vector amplitude;  ///< in the signal's unit
};
AmplitudeSpectrum amplitude_spectrum(const Vector& x, double fs_hz, Window w = Window::rectangular);

/// Welch options, SciPy's defaults: Hann window of nperseg points, 50 % overlap, constant
/// detrend, density scaling, mean over segments.
struct WelchOptions {
  Index nperseg = 256;     ///< samples per segment, >= 2 and <= record length
  Index noverlap = -1;     ///< overlap in samples, [0, nperseg); -1: nperseg / 2
  Window window = Window::hann;
  Detrend detrend = Detrend::constant;
  bool is_valid(Index n_samples, std::string* why) const;
};

/// One-sided power spectral density [unit²/Hz]: 2|X|²/(fs·Σw²) averaged over segments (DC and
/// Nyquist not doubled). Integrates (Σ P·Δf) to the variance of the detrended record.
struct Psd {
  Vector frequency_hz;
  Vector density;
  Index n_segments = 0;
};
Psd welch(const Vector& x, double fs_hz, const WelchOptions& o = {});

/// One-sided cross spectral density S_xy = conj(X)·Y scaled as welch(); S_xx = welch(x).
struct Csd {
  Vector frequency_hz;
  ComplexVector density;
  Index n_segments = 0;
};
Csd csd(const Vector& x, const Vector& y, double fs_hz, const WelchOptions& o = {});

}  // namespace viaduct::signal
