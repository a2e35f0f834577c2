#pragma once
/// \file Influence lines of a model's quantities along its load path, and what they give without
/// integrating anything: the static extremes of a crawling train (the quasi-static response over
/// every head position, whatever the speed) and of Load Model 71 (EN 1991-2 6.3.2) placed where
/// it is most unfavourable.

#include <string>
#include <vector>

#include "viaduct/load/train.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// The static value of each quantity under one 1 N axle at x = x0 + i·h on the load path
/// (quantity_names() order: deck stations' deflections, then the load effects), from one
/// factorisation of K and one solve per quantity (z = K⁻¹ c, value = zᵀ f(x), plus the axle's
/// direct share of a rigid bearing's force). 0 off the path.
struct InfluenceLines {
  std::vector<std::string> names;
  double x0 = 0.0, h = 0.0;   ///< [m] first sample and spacing
  std::vector<Vector> value;  ///< per quantity, samples at x0 + i·h up to the path's end
  /// Linear interpolation between samples; 0 outside the path.
  double at(std::size_t q, double x) const;
};

/// Samples about every `h` [m] (0: an eighth of the shortest path element, so that linear
/// interpolation of the cubic lines is within about 1e-3 of their range), shortened so that the
/// path holds a whole number of them (its end is a sample). SolverError when K cannot be
/// factorised (an unsupported part).
InfluenceLines influence_lines(const PreparedModel& m, double h = 0.0);

/// The extremes over every head position of `train` × load_factor crawling along the path
/// (head from the path's start until the last axle has left, every h), per quantity.
std::vector<EffectPeak> static_extremes(const InfluenceLines& il, const load::Train& train, double load_factor);

/// Load Model 71 (EN 1991-2 6.3.2, Fig. 6.1): four 250 kN axles 1.6 m apart and 80 kN/m from
/// 0.8 m beyond the outer axles on, over any length — taken where it makes each extreme worse
/// (the part of the influence line of that sign), all × alpha (classification factor, 6.3.2(3))
/// × load_factor (the share of the track's load the model carries). Per quantity.
std::vector<EffectPeak> lm71_extremes(const InfluenceLines& il, double alpha, double load_factor);

}  // namespace viaduct::study
