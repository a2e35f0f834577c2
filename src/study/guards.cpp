#include "viaduct/study/guards.hpp"

#include <algorithm>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/study/tradeoff.hpp"

namespace viaduct::study {

namespace {
std::string fmt(double v, int digits = 3) { return format_number(v, digits); }
}  // namespace

double rail_on_pad_hz(const model::TrackParams& t) {
  return std::sqrt(t.pad.k / (t.sleeper_spacing * t.rail_mass_per_m)) / (2.0 * M_PI);
}

std::vector<std::string> accuracy_warnings(const Scenario& sc, const std::vector<double>& speeds) {
  std::vector<std::string> out;
  // Soft pads under a modal basis: measured on the Old Guadiana Talgo run (preset "default",
  // filtered S1_mid peak against Newmark at 0.25 ms).
  const double cut = sc.settings.modal.max_frequency_hz > 0 ? sc.settings.modal.max_frequency_hz : 2.0 * band_edge_hz(sc);
  const bool vehicles = sc.settings.vehicle.model != VehicleModel::forces;
  if (sc.track && !vehicles && sc.settings.method == Method::modal && rail_on_pad_hz(*sc.track) < cut)
    out.push_back("track.pad.k = " + fmt(sc.track->pad.k) + " N/m puts the rail's resonance on its pads at " +
                  fmt(rail_on_pad_hz(*sc.track)) + " Hz, below the modal basis' " + fmt(cut) +
                  " Hz: the basis then truncates rail bending modes that carry the load (measured on the Old Guadiana "
                  "model with a 60 Hz basis: +6.4 % at 46 Hz, +21 % at 8.4 Hz; 0.7 % at 84 Hz); use "
                  "analysis.method = \"newmark\"");
  // Vehicles on a track's modes: the wheels bear on the rail, whose resonance on its pads sets
  // their contact forces; a basis that stops below it leaves them a massless, undamped track.
  // Measured on Old Guadiana with its track (rail on pads 265 Hz), eight AVE S103 coaches,
  // 200 km/h, FRA 5, against the full model (docs/vehicles.md, "The static correction").
  const bool reduced = sc.settings.method == Method::modal || sc.settings.method == Method::ida;
  const double vcut = sc.settings.modal.max_frequency_hz;  // 0: n_modes alone (not checked)
  if (sc.track && vehicles && reduced && vcut > 0.0 && vcut < kMinVehicleCutPerPad * rail_on_pad_hz(*sc.track))
    out.push_back("modal.max_frequency_hz = " + fmt(vcut) + " Hz stops the modes below " + fmt(kMinVehicleCutPerPad, 2) +
                  " x the rail's resonance on its pads (" + fmt(rail_on_pad_hz(*sc.track)) +
                  " Hz), which sets the wheels' contact forces: measured on the Old Guadiana model on a FRA 5 rail, "
                  "contact forces 69 % of the static load off the full model's with modes to 0.75 x (with the "
                  "static correction, wheels that stay on the rail leave it), 0.7 % with modes to 1.5 x; take "
                  "modal.max_frequency_hz >= " + fmt(kMinVehicleCutPerPad * rail_on_pad_hz(*sc.track)) +
                  " Hz, or analysis.method = \"newmark\" (faster on a track)");
  // A track file of one rail line under whole axle loads (or of both rails under half loads)
  // doubles (halves) every response.
  const double lf = sc.settings.load_factor;
  if (sc.track && sc.track_rails == "one" && std::abs(lf - 0.5) > 1e-9)
    out.push_back("the track is one rail line on half a deck (track.rails = \"one\") and train.load_factor = " + fmt(lf) +
                  ": each rail carries half of each axle, so load_factor = 0.5 (with a half-deck bridge) gives the "
                  "model's responses; " + fmt(lf / 0.5) + " times that is computed");
  if (sc.track && sc.track_rails == "both" && std::abs(lf - 1.0) > 1e-9)
    out.push_back("the track holds both rails (track.rails = \"both\") and train.load_factor = " + fmt(lf) +
                  ": a whole-deck model carries whole axle loads (load_factor = 1); " + fmt(lf) + " times that is computed");
  const double dt = sc.settings.dt;
  const auto& f = sc.settings.filter;
  // The filter's upper band edge sampled too coarsely: measured on the Old Guadiana model,
  // f_c = 60 Hz (docs/accuracy.md and docs/reliability.md).
  if (f.enabled && f.cheby.band != signal::BandType::highpass) {
    const double edge = f.cheby.high_hz, r = edge * dt;
    if (r > kMaxEdgeStepRatio)
      out.push_back("analysis.dt = " + fmt(dt) + " s samples the filter's band edge " + fmt(edge) + " Hz " + fmt(1.0 / r, 2) +
                    " times per period (f_c·dt = " + fmt(r, 2) +
                    "): measured envelope errors grow from 2 % at f_c·dt = 0.06 to 6.5 % at 0.12 and 15 % at 0.24 with "
                    "Newmark, and a modal run is 5 % low at 0.24 and 12 % at 0.48; take analysis.dt <= " +
                    fmt(0.06 / edge) + " s");
  }
  // Too few steps while the axles cross the shortest span: measured on a 15 m span under
  // HSLM-A1 at 400 km/h without a filter (Newmark).
  if (!speeds.empty() && !sc.bridge.spans.empty()) {
    double l_min = sc.bridge.spans.front().length;
    for (const auto& s : sc.bridge.spans) l_min = std::min(l_min, s.length);
    const double v_max = *std::max_element(speeds.begin(), speeds.end());
    const double steps = l_min / v_max / dt;
    if (steps < kMinStepsPerCrossing)
      out.push_back("at " + fmt(v_max * 3.6, 4) + " km/h the axles cross the shortest span (" + fmt(l_min) + " m) in " +
                    fmt(steps, 2) + " steps of analysis.dt: the deflection peak was measured 1.5 % low at 20 steps, 5 % at 10, "
                    "19 % at 5 and 52 % at 2.5; take analysis.dt <= " + fmt(l_min / v_max / kMinStepsPerCrossing) + " s");
  }
  return out;
}

}  // namespace viaduct::study
