#pragma once
/// \file Accuracy guards: settings outside the region where the methods' errors were measured
/// (docs/accuracy.md, docs/reliability.md), reported as warnings that name the setting, the
/// error it risks and the remedy. They never change a result.

#include <string>
#include <vector>

#include "viaduct/model/structure.hpp"
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

/// Fewer deck elements per span than this misses the deflection and acceleration peaks (measured,
/// docs/reliability.md: one element -58 % / -66 %, two -3 %, four within 0.5 %).
constexpr int kMinElementsPerSpan = 4;
/// Fewer elements than this per half-wave of the highest bending mode of a span inside the band.
constexpr double kMinElementsPerHalfWave = 1.0;
/// A deflection beyond span / this is not a railway bridge's (a unit slip, a bearing stiffness
/// off by orders of magnitude).
constexpr double kMaxDeflectionRatio = 100.0;
/// [kg/m] A deck lighter than this per metre is not a railway bridge's (mass in t/m, or the deck
/// of one girder).
constexpr double kMinMassPerMetre = 500.0;
/// [-] A structural damping ratio above this is not a railway bridge's (EN 1991-2 Table 6.6's lower
/// bounds are 0.5 to 2.6 %): a percentage entered as a ratio (0.5 for 0.5 %), which lowers the
/// resonant response and passes a check that should fail.
constexpr double kMaxDampingRatio = 0.10;
/// [N] A train whose heaviest axle is lighter than this is no railway train (the lightest axles in
/// service, an empty bogie wagon's, carry about 45 kN; a 35 t axle in tonnes reads 35): loads in
/// tonnes where kN are asked.
constexpr double kMinHeaviestAxleN = 40e3;
/// [m] Two consecutive axles of a train farther apart than this, or closer than kMinAxleGap, are
/// no railway vehicle's (the longest gap, inside a long coach or wagon, is about 25 m; the
/// shortest, a bogie's wheelbase, about 1.4 m): positions in mm (or km) where m are asked.
constexpr double kMaxAxleGap = 50.0;
constexpr double kMinAxleGap = 1.0;
/// [m] A track pressed down more than this under the heaviest wheel, statically (the rail relative
/// to the deck under it, or on the approach), is no track in service (ballasted: 0.5 to 3 mm).
constexpr double kMaxTrackCompression = 0.010;

/// [Hz] EN 1991-2 6.4.4 Fig. 6.10: the limits of a simply supported span's first natural frequency
/// for a span of L [m] in [4, 100] (outside: the limits at the nearer end).
struct FrequencyLimits {
  double lower = 0.0, upper = 0.0;
};
FrequencyLimits fig_6_10_limits(double span_m);

/// Warnings about the model `s` built from `sc` (run at `speeds` [m/s]): a deck too coarse for its
/// spans or its band, the modal method at speeds where its floor dominates, and the plausibility of
/// the inputs — each span's f1 against Fig. 6.10 (far outside: the key whose unit to check), its
/// mass per metre, the bridge's damping ratios against kMaxDampingRatio, each train's heaviest axle
/// against kMinHeaviestAxleN and its axles' gaps against kMinAxleGap and kMaxAxleGap, the track's
/// static compression under the heaviest wheel against kMaxTrackCompression, its static deflection under the heaviest axle against L/100 (a unit slip warned,
/// never reported as a result). Every warning names the key, the figure and its measured effect.
std::vector<std::string> model_warnings(const Scenario& sc, const model::Structure& s, const std::vector<double>& speeds);

/// accuracy_warnings() and model_warnings() of `sc` at `speeds` (the model built here): what
/// check, run, sweep and assess print and keep in the manifest before any result.
std::vector<std::string> scenario_warnings(const Scenario& sc, const std::vector<double>& speeds);

/// Warnings about results: a deck station whose largest |deflection| [m] (`max_disp`, one per
/// sc.stations entry, rail stations ignored) exceeds its span / kMaxDeflectionRatio.
std::vector<std::string> response_warnings(const Scenario& sc, const std::vector<double>& max_disp);

}  // namespace viaduct::study
