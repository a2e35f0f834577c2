#pragma once
/// \file A rail profile's spectrum against the irregularity spectra (issue #21 part 3): which
/// class of track a measured profile is, and the check of a generated one.

#include <vector>

#include "viaduct/core/types.hpp"
#include "viaduct/load/irregularity.hpp"

namespace viaduct::study {

struct ProfileSpectrum {
  Vector wavenumber;  ///< [rad/m] Welch bins with wavelengths in the band, ascending
  Vector psd;         ///< [m²/(rad/m)] the profile's one-sided PSD at them (Welch, Hann, per rad/m)
  double rms_band = 0.0;  ///< [m] √(Σ PSD·Δ) over the band's bins
  /// Per load::IrregularitySpectrum, in its order: the median over the band's bins of measured /
  /// target PSD.
  std::vector<double> median_ratio;
  load::IrregularitySpectrum nearest = load::IrregularitySpectrum::fra6;  ///< smallest |log median_ratio|
  Index nperseg = 0;  ///< the Welch segment used
};

/// Every spectrum, in load::IrregularitySpectrum's order.
const std::vector<load::IrregularitySpectrum>& all_irregularity_spectra();

/// Welch's estimate (segments of min(nperseg, samples), Hann, 50 % overlap) of the profile's
/// PSD over the wavelengths [lambda_min, lambda_max], against every spectrum. InputError when
/// lambda_min < 4 dx, lambda_max is not in (lambda_min, segment length], fewer than 3 bins fall
/// in the band or the profile is flat there.
ProfileSpectrum profile_spectrum(const load::RailProfile& p, double lambda_min, double lambda_max, Index nperseg = 4096);

}  // namespace viaduct::study
