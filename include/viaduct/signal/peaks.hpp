#pragma once
/// \file Peak picking in a sampled curve (a spectrum or a time history), after
/// `scipy.signal.find_peaks`: local maxima (the middle of flat tops), then height, distance and
/// prominence filters; positions refined between samples.

#include <limits>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::signal {

struct PeakOptions {
  double min_height = -std::numeric_limits<double>::infinity();  ///< keep y >= min_height
  double min_prominence = 0.0;  ///< keep prominence >= this (SciPy's definition), >= 0
  Index min_distance = 1;       ///< samples between kept peaks, >= 1; higher peaks win
  std::size_t max_peaks = 0;    ///< keep the highest ones only (0: all)
  bool is_valid(std::string* why) const;
};

enum class Interpolation {
  none,       ///< position = index
  parabolic,  ///< parabola through the three samples
  gaussian,   ///< parabola through their logarithms (positive samples; exact for a Gaussian;
              ///< Hann-windowed sines: position within 0.1 bin, amplitude within 4 %); falls
              ///< back to parabolic
};

struct Peak {
  Index index = 0;          ///< sample of the maximum
  double position = 0.0;    ///< refined position in samples (index + offset in (-0.5, 0.5))
  double value = 0.0;       ///< refined peak value
  double prominence = 0.0;  ///< height above the higher of the two bases (SciPy)
};

/// Peaks ordered by position. Throws InputError for invalid options or non-finite samples.
std::vector<Peak> find_peaks(const Vector& y, const PeakOptions& o = {}, Interpolation interp = Interpolation::gaussian);

/// Largest |y| of a smooth (band-limited, well sampled) signal between its samples: the vertex of
/// the parabola through the largest |y| sample (the first of equals) and its two neighbours,
/// when it curves down there inside the record; the sample itself otherwise (or at an end). For a
/// sine sampled n times per period the sampled maximum can be low by 1 − cos(π/n) (0.6 % at
/// 28 samples), the vertex by about (2π/n)⁴/64 (1e-4). 0 for an empty signal; NaN propagates.
double max_abs_between_samples(const Vector& y);

}  // namespace viaduct::signal
