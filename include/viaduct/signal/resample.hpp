#pragma once
/// \file Rate changes and envelopes of sampled signals.

#include "viaduct/core/types.hpp"

namespace viaduct::signal {

/// scipy.signal.decimate(x, q) (IIR, zero phase): Chebyshev I low-pass of order 8, 0.05 dB
/// ripple, edge at 0.8·fs/(2q), forward and backward, then every q-th sample. q >= 2.
Vector decimate(const Vector& x, int q);

/// Most samples resample() makes of one channel (2 GiB of doubles).
constexpr double kMaxResampled = 268435456.0;

/// x (at fs_in) on a grid at fs_out from the same start, by linear interpolation; when
/// fs_out < fs_in the signal is first low-passed (Chebyshev I order 8, 0.05 dB, edge at
/// 0.8·fs_out/2, zero phase) so that nothing aliases; its passband ripple changes amplitudes by
/// up to 1.2 % (2 x 0.05 dB). The last sample is at or before x's. InputError when fs_out leaves
/// fewer than two samples or more than kMaxResampled.
Vector resample(const Vector& x, double fs_in, double fs_out);

/// Root mean square over a centred window of `window` samples (odd, >= 1); shorter windows at
/// the ends.
Vector running_rms(const Vector& x, Index window);

/// Largest |x| over a centred window of `window` samples (odd, >= 1).
Vector maxabs_envelope(const Vector& x, Index window);

/// x + i·H[x], the analytic signal (scipy.signal.hilbert), via FFT: its modulus is the envelope,
/// its unwrapped argument the instantaneous phase.
Eigen::VectorXcd analytic_signal(const Vector& x);

/// |x + i·H[x]|, the magnitude of the analytic signal (scipy.signal.hilbert), via FFT.
Vector hilbert_envelope(const Vector& x);

/// Inverse complex FFT, x_j = (1/n) Σ X_k e^{2πi jk/n}.
Eigen::VectorXcd ifft(const Eigen::VectorXcd& X);

}  // namespace viaduct::signal
