#pragma once
/// \file Accuracy guards: settings outside the region where the methods' errors were measured
/// (docs/accuracy.md, docs/reliability.md), reported as warnings that name the setting, the
/// error it risks and the remedy. They never change a result.

#include <string>
#include <vector>

#include "viaduct/study/scenario.hpp"

namespace viaduct::study {

/// Below this many steps per period of the filter's upper band edge (f_c·dt > 0.1) the envelope
/// error grows past a few per cent.
constexpr double kMaxEdgeStepRatio = 0.1;
/// Below this many steps per crossing of the shortest span the sampled load misses the peaks.
constexpr double kMinStepsPerCrossing = 20.0;

/// With vehicles on a track's modes (analysis.method modal or ida) the modes must reach this many
/// times the rail's resonance on its pads for the contact forces (measured at 0.75 and 1.5 x).
constexpr double kMinVehicleCutPerPad = 1.5;

/// [Hz] The rail's resonance on its pads, sqrt(k_pad / (sleeper spacing · rail mass per m)) / 2π:
/// below the modal basis' cut-off the basis truncates the rail's bending modes that then carry
/// the load to the deck (measured +6 % to +22 % with preset "default", docs/reliability.md).
double rail_on_pad_hz(const model::TrackParams& t);

/// Warnings for `sc` run at `speeds` [m/s] (the sweep's, or the one speed of a run); empty when
/// the settings lie in the measured region.
std::vector<std::string> accuracy_warnings(const Scenario& sc, const std::vector<double>& speeds);

}  // namespace viaduct::study
