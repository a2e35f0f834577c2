#include "viaduct/study/guards.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/study/tradeoff.hpp"
#include "viaduct/study/vehicles.hpp"

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
  const bool reduced = vehicles && vehicles_on_modes(sc.settings);
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

FrequencyLimits fig_6_10_limits(double span_m) {
  const double L = std::clamp(span_m, 4.0, 100.0);
  FrequencyLimits f;
  f.upper = 94.76 * std::pow(L, -0.748);
  f.lower = L <= 20.0 ? 80.0 / L : 23.58 * std::pow(L, -0.592);
  return f;
}

namespace {

// [Hz] The first bending frequency of span i as a simply supported beam on rigid supports,
// π/(2L²)·sqrt(EI/m), with the mass the deck carries (the track's on it when modelled).
double span_f1(const Scenario& sc, std::size_t i) {
  const model::SpanParams& sp = sc.bridge.spans[i];
  double m = sp.mass_per_m + sc.bridge.added_mass_per_m;
  if (sc.track && !sc.bridge.mass_includes_track)
    m += sc.track->rail_mass_per_m + (sc.track->sleeper_mass + sc.track->ballast_mass) / sc.track->sleeper_spacing;
  return M_PI / (2.0 * sp.length * sp.length) * std::sqrt(sp.EI / m);
}

// The deck's discretisation against the spans and the band's modes.
void element_warnings(const Scenario& sc, const model::Structure& s, std::vector<std::string>& out) {
  const double fc = band_edge_hz(sc);
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i) {
    const auto [first, last] = s.span_elements(i);
    const auto n = static_cast<double>(last - first);
    const double L = sc.bridge.spans[i].length, f1 = span_f1(sc, i);
    // The highest bending order of the span inside the band: f_j = j² f1 <= f_c.
    const double order = std::max(1.0, std::floor(std::sqrt(fc / f1)));
    const double need = std::max(static_cast<double>(kMinElementsPerSpan), kMinElementsPerHalfWave * order);
    if (n < need)
      out.push_back("bridge.element_size = " + fmt(sc.bridge.element_size) + " m gives span " + std::to_string(i + 1) + " (" +
                    fmt(L) + " m) " + fmt(n, 3) + " element" + (n == 1 ? "" : "s") + "; it needs " + fmt(need, 3) +
                    " (at least " + std::to_string(kMinElementsPerSpan) + ", and one per half-wave of its bending mode " +
                    fmt(order, 3) + " at " + fmt(order * order * f1) + " Hz inside the " + fmt(fc) +
                    " Hz band): measured on the 15 m HSLM span, 1 element -58 % deflection and -66 % acceleration, 2 "
                    "elements -3 %, 4 within 0.5 %; take bridge.element_size <= " + fmt(L / need) + " m");
  }
}

// The modal method on a track at speeds where the response is quasi-static: its accelerations
// have a floor of their own (measured on Old Guadiana with track, preset "default").
void low_speed_warnings(const Scenario& sc, const std::vector<double>& speeds, std::vector<std::string>& out) {
  if (!sc.track || sc.settings.method != Method::modal || speeds.empty() ||
      sc.settings.vehicle.model != VehicleModel::forces)
    return;
  double f1 = 1e300;
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i) f1 = std::min(f1, span_f1(sc, i));
  const double v_min = *std::min_element(speeds.begin(), speeds.end());
  const double passing = v_min / sc.track->sleeper_spacing;  // [Hz] sleepers passed per second
  if (passing < 1.5 * f1)
    out.push_back("at " + fmt(v_min * 3.6, 4) + " km/h the axles pass " + fmt(passing) + " sleepers a second, below 1.5 x f1 (" +
                  fmt(f1) + " Hz): the response is nearly static and the modal method's accelerations have a floor of "
                  "their own that dominates it (measured on Old Guadiana with track, preset \"default\": 0.0098 m/s² "
                  "against Newmark's 0.0016 at 20 km/h, 0.0095 against 0.0094 at 40 km/h); use analysis.method = "
                  "\"newmark\" below " + fmt(1.5 * f1 * sc.track->sleeper_spacing * 3.6, 3) + " km/h");
}

// The bridge's damping ratios: a percentage entered as a ratio. Measured on the 15 m HSLM span
// (scenarios/hslm-simply-supported.toml, HSLM-A1, 140-420 km/h every 2 km/h): ratio 0.005 gives
// 72.9 m/s² and 76.6 mm, 0.5 gives 2.03 m/s² and 5.03 mm.
void damping_plausibility(const model::BridgeDamping& d, std::vector<std::string>& out) {
  std::vector<std::pair<const char*, double>> ratios;
  if (d.kind == model::DampingKind::modal) ratios = {{"bridge.damping.ratio", d.ratio}};
  if (d.kind == model::DampingKind::rayleigh) ratios = {{"bridge.damping.ratio1", d.ratio1}, {"bridge.damping.ratio2", d.ratio2}};
  for (const auto& [key, r] : ratios)
    if (r > kMaxDampingRatio)
      out.push_back(std::string(key) + " = " + fmt(r) + " (" + fmt(100.0 * r) + " % of critical), above the " +
                    fmt(100.0 * kMaxDampingRatio) + " % of any railway bridge (EN 1991-2 Table 6.6's lower bounds are 0.5 "
                    "to 2.6 %): the key is a ratio, not a percentage (0.5 % is 0.005). Damping that high lowers the "
                    "resonant response, and a check that should fail passes (the 15 m HSLM span under HSLM-A1: "
                    "72.9 m/s² at 0.005, 2.03 m/s² at 0.5)");
}

// A train's axles: positions in mm where m are asked spread a 20 m coach over 20 km, and every
// axle then crosses a span alone (measured: HSLM's 15 m span ran a 20 km "train" with exit 0).
void axle_gap_plausibility(const load::Train& t, std::vector<std::string>& out) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  std::size_t at_lo = 0, at_hi = 0;
  for (std::size_t k = 1; k < t.offset.size(); ++k) {
    const double g = t.offset[k] - t.offset[k - 1];
    if (g < lo) lo = g, at_lo = k;
    if (g > hi) hi = g, at_hi = k;
  }
  auto pair = [](std::size_t k) { return "axles " + std::to_string(k) + " and " + std::to_string(k + 1); };
  if (hi > kMaxAxleGap)
    out.push_back("train " + t.name + ": " + pair(at_hi) + " are " + fmt(hi) + " m apart, beyond the " + fmt(kMaxAxleGap) +
                  " m of any railway vehicle (a long coach's is about 25 m): check the unit of its positions (m, not mm: a 20 m "
                  "coach in mm is 20 km long, its axles loading the bridge one at a time)");
  if (t.offset.size() > 1 && lo < kMinAxleGap)
    out.push_back("train " + t.name + ": " + pair(at_lo) + " are " + fmt(lo) + " m apart, closer than the " + fmt(kMinAxleGap) +
                  " m of any two axles (a bogie's wheelbase is 1.4 m or more): check the unit of its positions (m, not km), "
                  "or an axle given twice");
}

// The track's own compression under the heaviest wheel `load` [N], statically (the rail's
// deflection less the deck's under it): at each span's middle and the approach's. Stiffnesses in
// kN/m where N/m are asked make it tens of millimetres (measured: Old Guadiana's ballast at
// 1.933e5 instead of 1.933e8 N/m, the Talgo run: the rail 60 mm down instead of 1.8 mm, the deck
// acceleration 0.19 instead of 0.52 m/s², exit 0 and no word).
void track_plausibility(const Scenario& sc, const model::Structure& s, const Eigen::SimplicialLDLT<SparseMatrix>& lk, double load,
                        std::vector<std::string>& out) {
  std::vector<std::pair<std::string, double>> where;  // (what, x)
  if (sc.track->approach_length > 0.0) where.push_back({"the approach", -0.5 * sc.track->approach_length});
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i)
    where.push_back({"span " + std::to_string(i + 1) + "'s middle", s.span_start[i] + 0.5 * sc.bridge.spans[i].length});
  double worst = 0.0;
  std::string at;
  bool on_deck = false;
  for (const auto& [what, x] : where) {
    const model::PointCoupling rail = s.rail_point(x);
    Vector f = Vector::Zero(s.K.rows());
    for (std::size_t q = 0; q < 4; ++q)
      if (rail.dofs[q] >= 0) f[rail.dofs[q]] += load * rail.N[q];
    const Vector u = lk.solve(f);
    double w = std::abs(rail.value(u));
    for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i)  // on a span: relative to the deck under it
      if (x >= s.span_start[i] && x <= s.span_start[i] + sc.bridge.spans[i].length)
        w = std::abs(rail.value(u) - s.deck_point(i, x - s.span_start[i]).value(u));
    if (w > worst) worst = w, at = what + " (x = " + fmt(x) + " m)", on_deck = what != "the approach";
  }
  if (worst > kMaxTrackCompression)  // once, where it is worst
    out.push_back("the track at " + at + ": the heaviest wheel (" + fmt(load / 1e3) + " kN) presses the rail " + fmt(1e3 * worst) +
                  " mm statically" + (on_deck ? " towards the deck" : "") + ", beyond the " + fmt(1e3 * kMaxTrackCompression) +
                  " mm of any track in service (ballasted: 0.5 to 3 mm): check the units of track.pad.k, track.ballast.k and "
                  "track.subgrade.k (N/m, not kN/m) and track.rail.I (m⁴)");
}

// Each span's f1, mass and static deflection, and the bridge's damping: what a unit slip gives.
void input_plausibility(const Scenario& sc, const model::Structure& s, std::vector<std::string>& out) {
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i) {
    const model::SpanParams& sp = sc.bridge.spans[i];
    const std::string span = "span " + std::to_string(i + 1) + " (" + fmt(sp.length) + " m)";
    const double f1 = span_f1(sc, i);
    const FrequencyLimits lim = fig_6_10_limits(sp.length);
    const double far = f1 < lim.lower ? lim.lower / f1 : f1 / lim.upper;
    // Fig. 6.10 is drawn for simply supported spans; a continuous deck is checked for a unit slip only.
    if ((f1 < lim.lower || f1 > lim.upper) && (!sc.bridge.continuous || far > 3.0)) {
      std::string w = span + ": f1 = " + fmt(f1) + " Hz as a simply supported beam, outside EN 1991-2 Fig. 6.10's " +
                      fmt(lim.lower) + " to " + fmt(lim.upper) + " Hz (a dynamic analysis is required, Fig. 6.9)";
      if (far > 3.0)
        w += f1 < lim.lower ? ", " + fmt(far, 2) + " times below: check the unit of bridge.EI (N·m², not kN·m²: 1000 x "
                                                   "too small gives f1 / 31.6) and of bridge.mass_per_m (kg/m)"
                            : ", " + fmt(far, 2) + " times above: check the unit of bridge.mass_per_m (kg/m, not t/m: "
                                                   "1000 x too small gives f1 x 31.6) and of bridge.EI (N·m²)";
      out.push_back(w);
    }
    const double m = sp.mass_per_m + sc.bridge.added_mass_per_m;
    if (m < kMinMassPerMetre)
      out.push_back(span + ": bridge.mass_per_m = " + fmt(m) + " kg/m, below the " + fmt(kMinMassPerMetre) +
                    " kg/m of any railway deck: check its unit (kg/m, not t/m)");
  }
  damping_plausibility(sc.bridge.damping, out);
  for (const auto& t : sc.trains) {
    double p = 0.0;
    for (const double x : t.load) p = std::max(p, std::abs(x));
    if (p > 0.0 && p < kMinHeaviestAxleN)
      out.push_back("train " + t.name + ": its heaviest axle carries " + fmt(p / 1e3) + " kN, below the " +
                    fmt(kMinHeaviestAxleN / 1e3) + " kN of any railway train: check the unit of its axle "
                    "loads (kN, not t: 17 t is 167 kN); every response scales with them");
    axle_gap_plausibility(t, out);
  }
  // The heaviest axle at each span's middle, statically, bearings included.
  double heaviest = 0.0;
  for (const auto& t : sc.trains)
    for (const double p : t.load) heaviest = std::max(heaviest, std::abs(p));
  heaviest *= sc.settings.load_factor;
  if (!(heaviest > 0.0)) return;
  Eigen::SimplicialLDLT<SparseMatrix> lk(s.K);
  if (lk.info() != Eigen::Success) return;  // an unsupported structure reports its own error
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i) {
    const double L = sc.bridge.spans[i].length;
    const model::PointCoupling mid = s.deck_point(i, 0.5 * L);
    Vector f = Vector::Zero(s.K.rows());
    for (std::size_t q = 0; q < 4; ++q)
      if (mid.dofs[q] >= 0) f[mid.dofs[q]] += heaviest * mid.N[q];
    const double w = std::abs(mid.value(lk.solve(f)));
    if (w > L / kMaxDeflectionRatio)
      out.push_back("span " + std::to_string(i + 1) + " (" + fmt(L) + " m): the heaviest axle (" + fmt(heaviest / 1e3) +
                    " kN) at its middle deflects it " + fmt(1e3 * w) + " mm statically, L/" + fmt(L / w, 3) +
                    ", beyond L/" + fmt(kMaxDeflectionRatio) +
                    ": no railway deck is that flexible; check the units of bridge.EI (N·m²), bridge.bearings.k (N/m) "
                    "and the axle loads (kN in train files)");
  }
  if (s.has_track) track_plausibility(sc, s, lk, heaviest, out);
}

}  // namespace

std::vector<std::string> model_warnings(const Scenario& sc, const model::Structure& s, const std::vector<double>& speeds) {
  std::vector<std::string> out;
  element_warnings(sc, s, out);
  low_speed_warnings(sc, speeds, out);
  input_plausibility(sc, s, out);
  return out;
}

std::vector<std::string> scenario_warnings(const Scenario& sc, const std::vector<double>& speeds) {
  std::vector<std::string> out = accuracy_warnings(sc, speeds);
  for (auto& w : model_warnings(sc, model::build_structure(sc.bridge, sc.track), speeds)) out.push_back(std::move(w));
  return out;
}

std::vector<std::string> response_warnings(const Scenario& sc, const std::vector<double>& max_disp) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < sc.stations.size() && i < max_disp.size(); ++i) {
    const StationSpec& st = sc.stations[i];
    if (!st.on_deck || st.span >= sc.bridge.spans.size()) continue;
    const double L = sc.bridge.spans[st.span].length;
    if (max_disp[i] > L / kMaxDeflectionRatio)
      out.push_back("station " + st.name + " deflects " + fmt(1e3 * max_disp[i]) + " mm, L/" + fmt(L / max_disp[i], 3) +
                    " of its " + fmt(L) + " m span, beyond L/" + fmt(kMaxDeflectionRatio) +
                    ": not a railway bridge's response; check the inputs' units (the warnings above) before using it");
  }
  return out;
}

}  // namespace viaduct::study
