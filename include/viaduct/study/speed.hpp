#pragma once
/// \file Train speed from a record, as the Old Guadiana authors did from the frequency of the
/// bogie (shared-axle) distance: a train of regular spacing d passing at v excites lines at
/// k·v/d. Two estimators: the spectral comb, and the spacing of axle-passage peaks.

#include "viaduct/core/types.hpp"

namespace viaduct::study {

struct SpeedEstimate {
  double speed = 0.0;        ///< [m/s]
  double uncertainty = 0.0;  ///< [m/s] spectral: speed step of one frequency bin at the highest
                             ///< harmonic used; peaks: standard error of the mean spacing
  double frequency_hz = 0.0; ///< spectral: the identified fundamental v/d
  int n_used = 0;            ///< harmonics (spectral) or peak intervals (peaks) used
};

/// Spectral comb: maximises Σ_k log A(k·v/d), k = 1..n_harmonics, over v in [v_min, v_max] on the
/// Hann amplitude spectrum A of x (interpolated between bins), refined by a parabola.
/// d [m] > 0, 0 < v_min < v_max, fs_hz > 0. InputError if the harmonics leave the spectrum.
SpeedEstimate speed_from_spectrum(const Vector& x, double fs_hz, double d, double v_min, double v_max,
                                  int n_harmonics = 4);

/// Axle passages: the median interval between consecutive peaks of x (e.g. a deflection or
/// strain under the rails) at least `min_interval_s` apart and with at least 10 % of the
/// largest prominence, v = d / interval, using only intervals within 15 % of the median.
/// Needs at least 3 peaks.
SpeedEstimate speed_from_peaks(const Vector& x, double fs_hz, double d, double min_interval_s);

}  // namespace viaduct::study
