// viaduct assess: the EN 1991-2 §6.4 / EN 1990 A2 dynamic check of a scenario's bridge
// (docs/assess.md). The numbers of the standard live in study/assess.hpp, the runs in
// study::run_sweep with load effects, the static effects of trains and LM71 in study/influence.hpp;
// this file puts them together and writes the tables and report.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/assess.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/study/influence.hpp"
#include "viaduct/study/sweep.hpp"

#ifndef VIADUCT_SOURCE_DIR
#define VIADUCT_SOURCE_DIR ""
#endif
#ifndef VIADUCT_INSTALLED_SCRIPTS
#define VIADUCT_INSTALLED_SCRIPTS ""
#endif

namespace viaduct::cli {

namespace {

struct AssessOptions {
  bool plots = true;
};

// The [assess] keys, resolved.
struct Config {
  double line_speed = 0.0;  // [m/s]
  study::DeckType deck = study::DeckType::prestressed;
  std::string track = "ballasted";
  double acc_limit = 3.5;  // [m/s²]
  double v_min = 0.0, v_max = 0.0, step = 0.0, fine_step = 0.0, band = 0.03;  // [m/s], [-]
  int harmonics = 4;
  std::optional<double> damping_ratio;
  bool interaction_damping = true;
  double ballast = 0.0, ballast_lower = 1.0, ballast_upper = 1.3;  // [kg/m], [-]
  double alpha = 1.0;
  bool careful = true;
  double deflection_ratio = 600.0, rotation_limit = 6.5e-3;
  std::optional<double> determinant_length;  // [m] assess.determinant_length_m: Lφ of every quantity
  // With vehicle models (train.vehicle sprung or multibody): passenger comfort and wheel unloading.
  std::string comfort_level = "very-good";
  double comfort_limit = 1.0;     // [m/s²] b_v, EN 1990 A2.4.4.3.1 Table A2.9 (to confirm)
  double unloading_limit = 1.0;   // [-] (P0 − P_min)/P0: 1, the wheels keep contact
};

// [m/s²] The vertical acceleration inside the coach b_v of a level of comfort (EN 1990
// A2.4.4.3.1, Table A2.9; to confirm against the text).
double comfort_limit_of(const std::string& level) {
  if (level == "very-good") return 1.0;
  if (level == "good") return 1.3;
  return 2.0;  // "acceptable" (the schema admits no other)
}

// What the assessment decided before running: damping, cut-off, trains, masses (for the report).
struct Plan {
  double span_for_damping = 0.0, zeta_table = 0.0, zeta_extra = 0.0, zeta = 0.0;
  bool zeta_given = false;
  double f1 = 0.0, f3 = 0.0, f_cut = 0.0;
  std::vector<model::DeckMode> deck_modes;  // of the nominal model
  std::vector<std::string> notes;           // what the report must say (defaults taken, limits)
  std::vector<study::Variant> variants;
  std::vector<std::string> real_trains;
};

double number_or(const io::FlatScenario& f, const std::string& key, double fallback) {
  return f.has(key) ? f.at(key).x : fallback;
}

// Where a key that is not set belongs: the line of another [assess] key given in the scenario, else
// the scenario itself.
SourceLocation assess_location(const io::FlatScenario& flat, const std::string& scenario, const std::string& key) {
  for (const auto& [k, v] : flat.values)
    if (io::key_is_under(k, "assess") && !flat.defaulted.count(k) && v.where.line > 0) return {v.where.file, v.where.line, key};
  return {scenario, 0, key};
}

Config read_config(const io::FlatScenario& flat, const std::string& scenario) {
  Config c;
  for (const char* key : {"assess.line_speed_kmh", "assess.deck_type"})
    if (!flat.has(key))
      throw InputError(assess_location(flat, scenario, key),
                       "viaduct assess needs this key (the line's maximum speed and the deck type of EN 1991-2 Table 6.6)");
  c.line_speed = flat.at("assess.line_speed_kmh").x / 3.6;
  c.deck = study::deck_type_of(flat.at("assess.deck_type").s);
  c.track = flat.at("assess.track").s;
  c.acc_limit = number_or(flat, "assess.acceleration_limit_mps2", c.track == "direct" ? 5.0 : 3.5);
  c.v_max = 1.2 * c.line_speed;
  c.v_min = number_or(flat, "assess.speed_min_kmh", std::min(100.0, 0.5 * c.line_speed * 3.6)) / 3.6;
  if (c.v_min > c.v_max)
    throw InputError(flat.at("assess.speed_min_kmh").where,
                     "the lowest speed is above 1.2 times the line speed (" + format_number(c.v_max * 3.6, 6) + " km/h)");
  c.step = flat.at("assess.speed_step_kmh").x / 3.6;
  c.fine_step = flat.at("assess.refine_step_kmh").x / 3.6;
  c.band = flat.at("assess.refine_band").x;
  c.harmonics = static_cast<int>(flat.at("assess.harmonics").x);
  if (flat.has("assess.damping_ratio")) c.damping_ratio = flat.at("assess.damping_ratio").x;
  c.interaction_damping = flat.at("assess.interaction_damping").b;
  c.ballast = number_or(flat, "assess.ballast_mass_per_m", -1.0);
  c.ballast_lower = flat.at("assess.ballast_lower_factor").x;
  c.ballast_upper = flat.at("assess.ballast_upper_factor").x;
  if (c.ballast_lower > c.ballast_upper)
    throw InputError(flat.at("assess.ballast_lower_factor").where, "the lower-bound factor is above the upper-bound one");
  c.alpha = flat.at("assess.lm71_alpha").x;
  c.careful = flat.at("assess.track_maintenance").s == "careful";
  c.deflection_ratio = flat.at("assess.deflection_limit_ratio").x;
  c.rotation_limit = flat.at("assess.end_rotation_limit_rad").x;
  if (flat.has("assess.determinant_length_m")) c.determinant_length = flat.at("assess.determinant_length_m").x;
  c.comfort_level = flat.at("assess.comfort_level").s;
  c.comfort_limit = number_or(flat, "assess.comfort_limit_mps2", comfort_limit_of(c.comfort_level));
  c.unloading_limit = flat.at("assess.unloading_ratio_limit").x;
  return c;
}

void set_string(io::FlatScenario& flat, const std::string& key, const std::string& value) {
  io::Value v;
  v.type = io::ValueType::string;
  v.s = value;
  v.where = SourceLocation{"assess", 0, key};
  flat.values[key] = v;
  flat.defaulted.erase(key);
}

// Adds `delta` [kg/m] to every span's mass per metre; InputError when a span's mass would not be positive.
void add_mass(io::FlatScenario& flat, double delta) {
  io::Value v = flat.at("bridge.mass_per_m");
  if (v.type == io::ValueType::number_list) {
    for (double& m : v.xs) m += delta;
  } else {
    v.x += delta;
  }
  const std::vector<double> ms = v.type == io::ValueType::number_list ? v.xs : std::vector<double>{v.x};
  for (double m : ms)
    if (!(m > 0.0))
      throw InputError(flat.has("assess.ballast_mass_per_m") ? flat.at("assess.ballast_mass_per_m").where
                                                              : assess_location(flat, flat.path, "assess.ballast_lower_factor"),
                       "the lower-bound mass of a span would not be positive: the ballast is more than the deck's mass");
  flat.values["bridge.mass_per_m"] = v;
}

// The nominal model's deck bending modes (the first six).
std::vector<model::DeckMode> deck_modes_of(const study::Scenario& sc) {
  return model::deck_bending_modes(model::build_structure(sc.bridge, sc.track), 6);
}

// Damping (Table 6.6 + Δζ, or the key), the cut-off and filter, on the flat scenario.
void plan_damping_and_cutoff(io::FlatScenario& flat, const Config& c, Plan& p) {
  const study::Scenario nominal = io::to_scenario(flat);
  double longest = 0.0;
  for (const auto& s : nominal.bridge.spans) longest = std::max(longest, s.length);
  p.span_for_damping = longest;
  p.zeta_table = study::damping_lower_bound(c.deck, longest);
  p.zeta_extra = c.interaction_damping ? study::additional_damping(longest) : 0.0;
  p.zeta_given = c.damping_ratio.has_value();
  p.zeta = p.zeta_given ? *c.damping_ratio : p.zeta_table + p.zeta_extra;
  set_string(flat, "bridge.damping.kind", "modal");
  io::set_number(flat, "bridge.damping.ratio", p.zeta);
  p.deck_modes = deck_modes_of(nominal);
  if (p.deck_modes.empty()) throw SolverError("assess: the model has no deck bending mode");
  p.f1 = p.deck_modes.front().frequency_hz;
  p.f3 = p.deck_modes.size() >= 3 ? p.deck_modes[2].frequency_hz : 0.0;
  if (p.deck_modes.size() < 3) p.notes.push_back("fewer than three deck bending modes found: f3 not used in the cut-off");
  p.f_cut = study::cutoff_frequency(p.f1, p.f3);
  set_string(flat, "filter.band", "lowpass");
  flat.values["filter.enabled"].b = true;
  io::set_number(flat, "filter.high_hz", p.f_cut);
}

// HSLM-A1…A10, HSLM-B for spans under 7 m (N and d from the keys), then the scenario's other trains.
std::vector<load::Train> assessment_trains(const io::FlatScenario& flat, const study::Scenario& sc, Plan& p) {
  std::vector<load::Train> out;
  for (int i = 1; i <= 10; ++i) out.push_back(load::hslm_a("HSLM-A" + std::to_string(i), load::hslm_a_row(i)));
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& s : sc.bridge.spans) shortest = std::min(shortest, s.length);
  if (sc.bridge.continuous && shortest < 7.0)
    p.notes.push_back("HSLM-B not run: EN 1991-2 6.4.6.1.1 asks for it on simply supported spans under 7 m; this deck is continuous "
                      "(HSLM-A1…A10 cover it)");
  if (!sc.bridge.continuous && shortest < 7.0) {
    if (!flat.has("assess.hslm_b_n") || !flat.has("assess.hslm_b_spacing_m"))
      throw InputError(assess_location(flat, flat.path, "assess.hslm_b_n"),
                       "a span of " + format_number(shortest, 4) +
                           " m is under 7 m: EN 1991-2 6.4.6.1.1 asks for HSLM-B; give assess.hslm_b_n and "
                           "assess.hslm_b_spacing_m read from Fig. E.4 for this span (viaduct does not carry the figure)");
    const int n = static_cast<int>(flat.at("assess.hslm_b_n").x);
    out.push_back(load::regular_train("HSLM-B", n, flat.at("assess.hslm_b_spacing_m").x, 170e3));
    p.notes.push_back("HSLM-B: " + std::to_string(n) + " forces of 170 kN every " +
                      format_number(flat.at("assess.hslm_b_spacing_m").x, 4) + " m (from the scenario, Fig. E.4)");
  }
  for (const auto& t : sc.trains) {
    const bool listed = std::any_of(out.begin(), out.end(), [&](const load::Train& x) { return x.name == t.name; });
    if (!listed) {
      out.push_back(t);
      p.real_trains.push_back(t.name);
    }
  }
  return out;
}

// Each train's speeds: the grid, refined around f·d/j for the variant's deck modes below the cut-off.
std::vector<std::vector<double>> train_speeds(const std::vector<load::Train>& trains, const study::Scenario& sc,
                                              const Config& c, double f_cut) {
  std::vector<double> freqs;
  for (const auto& m : deck_modes_of(sc))
    if (m.frequency_hz <= f_cut) freqs.push_back(m.frequency_hz);
  std::vector<std::vector<double>> out;
  for (const auto& t : trains) {
    const double d = load::characteristic_distance(t);
    std::vector<double> res;
    for (double f : freqs)
      for (int j = 1; j <= c.harmonics && d > 0.0; ++j) res.push_back(f * d / j);
    out.push_back(study::assessment_speeds(c.v_min, c.v_max, c.step, c.fine_step, res, c.band));
  }
  return out;
}

// The mass variants (lower and upper bound, or one nominal case), each with every train and its speeds.
void plan_variants(io::FlatScenario& flat, const Config& c, Plan& p) {
  const study::Scenario nominal = io::to_scenario(flat);
  double ballast = c.ballast;
  if (ballast < 0.0) {  // not given: the modelled track's ballast, or none
    ballast = nominal.track ? nominal.track->ballast_mass / nominal.track->sleeper_spacing : 0.0;
    p.notes.push_back(nominal.track ? "ballast mass per metre taken from the track model: " + format_number(ballast, 6) + " kg/m"
                                    : "no ballast mass given (assess.ballast_mass_per_m): one mass case, not bounded");
  }
  const std::vector<load::Train> trains = assessment_trains(flat, nominal, p);
  std::vector<std::pair<std::string, double>> bounds = {{"nominal", 1.0}};
  if (ballast > 0.0 && c.ballast_lower != c.ballast_upper)
    bounds = {{"mass lower", c.ballast_lower}, {"mass upper", c.ballast_upper}};
  const double m0 = nominal.bridge.spans.front().mass_per_m;
  for (const auto& [label, factor] : bounds) {
    io::FlatScenario f = flat;
    if (factor != 1.0) add_mass(f, (factor - 1.0) * ballast);
    study::Variant v;
    v.label = label;
    v.scenario = io::to_scenario(f);
    v.scenario.trains = trains;
    v.factors = {{"mass", v.scenario.bridge.spans.front().mass_per_m / m0}};
    v.train_speeds = train_speeds(trains, v.scenario, c, p.f_cut);
    v.scenario.sweep_speeds = v.train_speeds.front();
    p.variants.push_back(std::move(v));
  }
}

}  // namespace
}  // namespace viaduct::cli

namespace viaduct::cli {
namespace {

// One row of checks.csv and of the report's summary.
struct Check {
  std::string check, quantity;
  double value = 0.0, limit = 0.0;  // in the quantity's unit (its name's suffix)
  std::string verdict, variant, train;
  double speed = std::numeric_limits<double>::quiet_NaN();  // [m/s] the governing case's (NaN: none)
  std::string clause;
  double utilisation() const { return limit > 0.0 ? value / limit : std::numeric_limits<double>::quiet_NaN(); }
};

// The worst φ′dyn of one (variant, train, quantity) over the speeds.
struct Increment {
  std::string variant, train, quantity;
  double dynamic = 0.0, quasi_static = 0.0, speed = 0.0;  // max |.|, [m/s] where the dynamic peak is
  double phi() const { return quasi_static > 0.0 ? dynamic / quasi_static - 1.0 : std::numeric_limits<double>::quiet_NaN(); }
};

std::vector<Increment> increments(const std::vector<study::QuantityRow>& rows) {
  std::vector<Increment> out;
  std::map<std::string, std::size_t> at;
  for (const auto& r : rows) {
    const std::string key = r.variant + '\n' + r.train + '\n' + r.quantity;
    auto it = at.find(key);
    if (it == at.end()) {
      it = at.emplace(key, out.size()).first;
      out.push_back({r.variant, r.train, r.quantity, -1.0, r.quasi_static.max_abs(), r.speed});
    }
    Increment& inc = out[it->second];
    if (r.dynamic.max_abs() > inc.dynamic) inc.dynamic = r.dynamic.max_abs(), inc.speed = r.speed;
  }
  return out;
}

// The span (0-based) a quantity belongs to: span<k>_… or a deck station's span.
std::size_t span_of(const std::string& quantity, const study::Scenario& sc) {
  if (quantity.rfind("span", 0) == 0) return static_cast<std::size_t>(std::max(1, std::atoi(quantity.c_str() + 4)) - 1);
  for (const auto& st : sc.stations)
    if (st.on_deck && quantity.rfind(st.name + "_", 0) == 0) return st.span;
  return 0;
}

// Lφ of a quantity (6.4.5.3, Table 6.2): assess.determinant_length_m when given; on a continuous
// deck Table 6.2 for girders continuous over n spans (k × the mean span, not below the longest;
// to confirm); else its span's length.
double determinant_length(const std::string& quantity, const study::Scenario& sc, const Config& c) {
  if (c.determinant_length) return *c.determinant_length;
  if (sc.bridge.continuous) {
    std::vector<double> spans;
    for (const auto& s : sc.bridge.spans) spans.push_back(s.length);
    return study::continuous_determinant_length(spans);
  }
  return sc.bridge.spans[std::min(span_of(quantity, sc), sc.bridge.spans.size() - 1)].length;
}

// A rotation the end-rotation limit applies to (A2.4.4.2.3: at the deck's ends): every span end
// of simply supported spans; the first and last supports of a continuous deck.
bool deck_end_rotation(const std::string& quantity, const study::Scenario& sc) {
  if (!sc.bridge.continuous) return true;
  return quantity == "support1_rot_rad" || quantity == "support" + std::to_string(sc.bridge.spans.size() + 1) + "_rot_rad";
}

// A deck station over a rigid bearing (a span's end): its deflection and acceleration are zero by
// construction, so they get no check rows (the report says so).
bool on_rigid_support(const std::string& station, const study::Scenario& sc) {
  if (!sc.bridge.bearings.rigid) return false;
  for (const auto& st : sc.stations)
    if (st.on_deck && st.name == station) {
      const double L = sc.bridge.spans[st.span].length;
      return std::abs(st.x_local) <= 1e-9 * L || std::abs(st.x_local - L) <= 1e-9 * L;
    }
  return false;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Everything the checks need besides the sweep: the nominal model's influence lines, LM71 and
// the permanent bearing loads.
struct Statics {
  study::InfluenceLines il;
  std::vector<study::EffectPeak> lm71;
  std::vector<double> permanent;  // per quantity: a bearing's permanent load [N], else 0
};

Statics statics_of(const study::Scenario& nominal, const Config& c) {
  study::RunSettings rs = nominal.settings;
  rs.method = study::Method::newmark;  // no modes needed for static lines
  const study::PreparedModel pm = study::prepare_model(model::build_structure(nominal.bridge, nominal.track),
                                                       nominal.stations, rs, false, true);
  Statics st;
  st.il = study::influence_lines(pm);
  st.lm71 = study::lm71_extremes(st.il, c.alpha, nominal.settings.load_factor);
  st.permanent.assign(st.il.names.size(), 0.0);
  const std::size_t n_disp = st.il.names.size() - pm.effects.size();
  for (std::size_t j = 0; j < pm.effects.size(); ++j)
    if (pm.effects[j].bearing >= 0)
      st.permanent[n_disp + j] = pm.structure.bearings[static_cast<std::size_t>(pm.effects[j].bearing)].permanent;
  return st;
}

// The design-effect, deformation and uplift rows of one quantity.
void quantity_checks(std::size_t q, const Statics& st, const std::vector<Increment>& inc,
                     const std::vector<study::QuantityRow>& rows, const study::Scenario& sc, const Config& c,
                     const Plan& p, std::vector<Check>& out) {
  const std::string& name = st.il.names[q];
  const double L = sc.bridge.spans[std::min(span_of(name, sc), sc.bridge.spans.size() - 1)].length;
  const double L_phi = determinant_length(name, sc, c);
  const double Phi = c.careful ? study::phi2(L_phi) : study::phi3(L_phi);
  const double phi2nd = study::phi_irregularities(L_phi, c.v_max, p.f1);
  const double lm = Phi * st.lm71[q].max_abs();
  // (1 + φ′dyn + φ″/2) × the train's static effect, the worst train and mass (6.4.6.5(3)).
  Check d{"dynamic design effect vs LM71", name, 0.0, lm, "", "", "", std::numeric_limits<double>::quiet_NaN(),
          "EN 1991-2 6.4.6.5(3)"};
  const Increment* dyn_max = nullptr;
  for (const auto& i : inc) {
    if (i.quantity != name) continue;
    const double e = (1.0 + i.phi() + 0.5 * phi2nd) * i.quasi_static;
    if (std::isfinite(e) && e > d.value) d.value = e, d.variant = i.variant, d.train = i.train, d.speed = i.speed;
    if (!dyn_max || i.dynamic > dyn_max->dynamic) dyn_max = &i;
  }
  if (!dyn_max) return;  // no case of this quantity ran: nothing to check (failures.csv says why)
  if (lm > 0.0) {
    d.verdict = d.value > lm ? "dynamic governs" : "LM71 governs";
    out.push_back(d);
  }
  const bool disp = ends_with(name, "_disp_m") && !on_rigid_support(name.substr(0, name.size() - 7), sc);
  const bool rot = ends_with(name, "_rot_rad") && deck_end_rotation(name, sc);
  if (disp || rot) {
    const double limit = disp ? L / c.deflection_ratio : c.rotation_limit;
    const std::string what = disp ? "vertical deflection" : "deck end rotation";
    const std::string clause = "EN 1990 A2.4.4.2.3 (limit to confirm)";
    Check dy{what + ", trains (dynamic)", name, dyn_max->dynamic, limit, "", dyn_max->variant, dyn_max->train, dyn_max->speed, clause};
    Check sl{what + ", LM71 x Phi", name, lm, limit, "", "", "LM71", std::numeric_limits<double>::quiet_NaN(), clause};
    for (Check* k : {&dy, &sl}) {
      k->verdict = k->value <= limit ? "pass" : "FAIL";
      out.push_back(*k);
    }
  }
  if (st.permanent[q] > 0.0) {  // a bearing: the traffic's largest pull against the permanent load
    Check u{"bearing uplift", name, 0.0, st.permanent[q], "", "", "", std::numeric_limits<double>::quiet_NaN(),
            sc.bridge.continuous ? "permanent load (static solve of the deck's weight) vs the traffic's negative force"
                                 : "permanent load g m L / 2 vs the traffic's negative force"};
    for (const auto& r : rows)
      if (r.quantity == name && -r.dynamic.min > u.value)
        u.value = -r.dynamic.min, u.variant = r.variant, u.train = r.train, u.speed = r.speed;
    u.verdict = u.value < u.limit ? "pass" : "UPLIFT";
    out.push_back(u);
  }
}

// With vehicle models: the largest car-body floor acceleration against the comfort limit, and the
// largest wheel unloading against its limit (a lost contact is an unloading of 1), each with the
// case that governs it.
void vehicle_checks(const study::SweepResult& r, const Config& c, std::vector<Check>& out) {
  const study::VehicleRow *body = nullptr, *unload = nullptr;
  for (const auto& v : r.vehicles) {
    if (!v.peaks.present) continue;
    if (!body || v.peaks.max_floor_acc > body->peaks.max_floor_acc) body = &v;
    if (!unload || v.peaks.max_unloading_ratio > unload->peaks.max_unloading_ratio) unload = &v;
  }
  if (!body) return;
  Check b{"passenger comfort (car body)", body->peaks.floor_body + "_floor_acc_mps2", body->peaks.max_floor_acc, c.comfort_limit, "",
          body->variant, body->train, body->speed, "EN 1990 A2.4.4.3.1, Table A2.9 " + c.comfort_level + " (to confirm)"};
  b.verdict = b.value <= b.limit ? "pass" : "FAIL";
  out.push_back(b);
  Check u{"wheel unloading (P0 - Pmin)/P0", "unloading_ratio", unload->peaks.max_unloading_ratio, c.unloading_limit, "",
          unload->variant, unload->train, unload->speed,
          c.unloading_limit < 1.0 ? "assess.unloading_ratio_limit (the project's)" : "contact kept (1: a wheel leaves the rail)"};
  u.verdict = u.value < u.limit ? "pass" : "FAIL";
  out.push_back(u);
}

std::vector<Check> all_checks(const study::SweepResult& r, const Statics& st, const std::vector<Increment>& inc,
                              const study::Scenario& sc, const Config& c, const Plan& p) {
  std::vector<Check> out;
  for (const auto& g : study::governing(r.rows)) {
    if (on_rigid_support(g.station, sc)) continue;  // no motion there: no row
    Check a{"deck acceleration", g.station + "_acc_mps2", g.acc.value, c.acc_limit, "", g.acc.variant, g.acc.train,
            g.acc.speed, "EN 1990 A2.4.4.2.1(4)"};
    a.verdict = a.value <= a.limit ? "pass" : "FAIL";
    out.push_back(a);
  }
  for (std::size_t q = 0; q < st.il.names.size(); ++q) quantity_checks(q, st, inc, r.quantities, sc, c, p, out);
  vehicle_checks(r, c, out);
  return out;
}

void write_checks_csv(const std::string& path, const std::vector<Check>& checks) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& k : checks)
    rows.push_back({k.check, k.quantity, io::table_cell(k.value), io::table_cell(k.limit), io::table_cell(k.utilisation(), 6),
                    k.verdict, k.variant, k.train, io::table_cell(k.speed * 3.6, 6), k.clause});
  io::write_table_csv(path, {"check", "quantity", "value", "limit", "utilisation", "result", "variant", "train", "speed_kmh", "clause"},
                      rows);
}

void write_increments_csv(const std::string& path, const std::vector<Increment>& inc) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& i : inc)
    rows.push_back({i.variant, i.train, i.quantity, io::table_cell(i.dynamic), io::table_cell(i.quasi_static),
                    io::table_cell(i.phi(), 6), io::table_cell(i.speed * 3.6, 6)});
  io::write_table_csv(path, {"variant", "train", "quantity", "max_abs_dynamic", "max_abs_quasi_static", "phi_dyn", "speed_kmh"}, rows);
}


// mass_cases.csv: what each mass case sets, so that any of its cases can be run again alone
// (viaduct run --set bridge.mass_per_m=... --set bridge.damping.ratio=... --set filter.high_hz=...).
void write_mass_cases_csv(const std::string& path, const Plan& p) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& v : p.variants)
    for (std::size_t k = 0; k < v.scenario.bridge.spans.size(); ++k)
      rows.push_back({v.label, std::to_string(k + 1), io::table_cell(v.scenario.bridge.spans[k].mass_per_m),
                      io::table_cell(p.zeta), io::table_cell(p.f_cut)});
  io::write_table_csv(path, {"variant", "span", "mass_per_m_kgpm", "damping_ratio", "cutoff_hz"}, rows);
}

std::string fmt(double x, int sig = 4) { return std::isfinite(x) ? format_number(x, sig) : "—"; }

// A value in the unit a reader expects (mm, kN, kN·m, mrad, m/s², µε), from the quantity's suffix.
std::string shown(const std::string& quantity, double x) {
  static const std::vector<std::tuple<std::string, double, std::string>> units = {
      {"_acc_mps2", 1.0, " m/s²"}, {"_disp_m", 1e3, " mm"}, {"_moment_Nm", 1e-3, " kN·m"},
      {"_reaction_N", 1e-3, " kN"}, {"_shear_N", 1e-3, " kN"}, {"_rot_rad", 1e3, " mrad"}, {"_strain_ue", 1.0, " µε"}};
  for (const auto& [suffix, factor, unit] : units)
    if (ends_with(quantity, suffix)) return fmt(x * factor) + unit;
  return fmt(x);
}

struct LayoutSensitivity;

struct ReportInput {
  const Config& c;
  const Plan& p;
  const study::SweepResult& r;
  const std::vector<Check>& checks;
  const std::vector<Increment>& inc;
  const io::FlatScenario& flat;
  const study::Scenario& nominal;
  std::string command_line;
  bool figures = false;
  const LayoutSensitivity* layout = nullptr;
};

void report_summary(std::ostringstream& o, const ReportInput& in) {
  std::size_t fails = 0, dyn = 0;
  for (const auto& k : in.checks) fails += k.verdict == "FAIL" || k.verdict == "UPLIFT", dyn += k.verdict == "dynamic governs";
  o << "## Summary\n\n";
  if (in.checks.empty()) o << "**No check could be made: every case failed to run (failures.csv).**";
  else o << (fails ? "**" + std::to_string(fails) + " check(s) fail.**" : std::string("**Every limit check passes.**"));
  if (!in.r.failures.empty() && !in.checks.empty())
    o << " **" << in.r.failures.size() << " case(s) failed to run (failures.csv): the checks leave them out.**";
  if (dyn) o << " In " << dyn << " quantit" << (dyn > 1 ? "ies" : "y") << " the dynamic effect of the trains exceeds Φ × LM71: design with it (6.4.6.5(3)).";
  o << "\n\n| check | quantity | value | limit | utilisation | result | governing train | speed [km/h] | mass | clause |\n"
       "|---|---|---:|---:|---:|---|---|---:|---|---|\n";
  for (const auto& k : in.checks)
    o << "| " << k.check << " | " << k.quantity << " | " << shown(k.quantity, k.value) << " | " << shown(k.quantity, k.limit)
      << " | " << fmt(k.utilisation(), 3) << " | " << k.verdict << " | " << (k.train.empty() ? "—" : k.train) << " | "
      << fmt(k.speed * 3.6, 4) << " | " << (k.variant.empty() ? "—" : k.variant) << " | " << k.clause << " |\n";
  if (in.figures) o << "\n![Peak deck acceleration against speed, every train, with the limit](acc_vs_speed.png)\n";
}

// How the trains ran: the vehicle model, its contact and the rail profile (docs/vehicles.md).
std::string vehicle_line(const study::RunSettings& st) {
  const study::VehicleSettings& v = st.vehicle;
  if (v.model == study::VehicleModel::forces) return "as moving axle loads (train.vehicle = \"forces\")";
  std::string s = std::string("as ") + study::vehicle_model_name(v.model) + " vehicles (docs/vehicles.md), " +
                  (v.contact == study::ContactModel::rigid ? "rigid" : "Hertz") + " contact" +
                  (v.release ? " released when it would pull" : " held (tensile forces reported)");
  const study::IrregularitySettings& irr = st.irregularity;
  if (irr.measured) s += ", measured rail profile " + irr.measured_file;
  else if (!irr.spectrum.empty()) s += ", random rail profile " + irr.spectrum + " (seed " + std::to_string(irr.seed) + ")";
  else s += ", smooth rail";
  if (st.method == study::Method::ida) s += ", IDA on the modes with the contact events located";
  return s;
}

void report_inputs(std::ostringstream& o, const ReportInput& in) {
  const Config& c = in.c;
  const Plan& p = in.p;
  std::size_t n_cases = in.r.summary.n_cases;
  o << "\n## Inputs of the check\n\n";
  o << "- **Trains** (EN 1991-2 6.4.6.1.1, Annex E): HSLM-A1…A10";
  for (const auto& t : p.real_trains) o << ", " << t;
  o << ". Axle loads × " << fmt(in.nominal.settings.load_factor) << " (train.load_factor).\n";
  o << "- **Speeds** (6.4.6.2): " << fmt(c.v_min * 3.6) << " to " << fmt(c.v_max * 3.6) << " km/h (1.2 × the line speed "
    << fmt(c.line_speed * 3.6) << " km/h) every " << fmt(c.step * 3.6) << " km/h, refined to " << fmt(c.fine_step * 3.6)
    << " km/h within ±" << fmt(100 * c.band) << " % of each resonance speed f·d/j (j ≤ " << c.harmonics
    << ", f each deck bending frequency below the cut-off, d the train's characteristic distance): " << n_cases << " cases.\n";
  if (p.zeta_given)
    o << "- **Damping**: ζ = " << fmt(100 * p.zeta) << " % (assess.damping_ratio, instead of Table 6.6).\n";
  else
    o << "- **Damping** (Table 6.6, " << study::deck_type_name(c.deck) << ", L = " << fmt(p.span_for_damping) << " m, the longest span): "
      << fmt(100 * p.zeta_table) << " %" << (p.zeta_extra > 0 ? " + Δζ = " + fmt(100 * p.zeta_extra) + " % (Fig. 6.8, Eq. 6.13: interaction not modelled)" : "")
      << " = **" << fmt(100 * p.zeta) << " %** in every deck mode.\n";
  o << "- **Mass** (6.4.6.3.2):";
  for (const auto& v : p.variants) o << " " << v.label << " " << fmt(v.scenario.bridge.spans.front().mass_per_m, 6) << " kg/m;";
  o << " the lower bound governs accelerations, the upper bound the lowest resonance speeds.\n";
  o << "- **Frequencies** (EN 1990 A2.4.4.2.1(4)): f1 = " << fmt(p.f1) << " Hz, f3 = " << fmt(p.f3) << " Hz: cut-off max(30, 1.5 f1, f3) = **"
    << fmt(p.f_cut) << " Hz**, applied as a Chebyshev I low-pass to accelerations.\n";
  o << "- **Limits**: deck acceleration " << fmt(c.acc_limit) << " m/s² (" << c.track << " track); deflection span/"
    << fmt(c.deflection_ratio) << "; end rotation " << fmt(c.rotation_limit * 1e3) << " mrad; LM71 α = " << fmt(c.alpha) << ", "
    << (c.careful ? "Φ2 (careful maintenance)" : "Φ3 (standard maintenance)") << " with Lφ = "
    << (c.determinant_length ? fmt(*c.determinant_length) + " m (assess.determinant_length_m)"
        : in.nominal.bridge.continuous ? fmt(determinant_length("", in.nominal, c)) + " m (Table 6.2, continuous over n spans: to confirm)"
                                       : std::string("each quantity's span length (Table 6.2)"))
    << ".\n";
  if (in.nominal.settings.vehicle.model != study::VehicleModel::forces)
    o << "- **Vehicle limits**: car-body vertical acceleration b_v " << fmt(c.comfort_limit) << " m/s² (comfort level "
      << c.comfort_level << ", EN 1990 A2.4.4.3.1 Table A2.9: to confirm; assess.comfort_limit_mps2 overrides); wheel unloading "
      << "(P0 − Pmin)/P0 below " << fmt(c.unloading_limit)
      << (c.unloading_limit < 1.0 ? " (assess.unloading_ratio_limit)" : " (every wheel keeps contact with the rail)") << ".\n";
  o << "- **Model and method**: " << in.nominal.bridge.spans.size() << (in.nominal.bridge.continuous ? " span(s) of one continuous deck, " : " span(s), ")
    << (in.nominal.track ? "with" : "without")
    << " track; " << (in.nominal.settings.method == study::Method::modal ? "modal superposition" : "direct integration") << ", dt = "
    << fmt(in.nominal.settings.dt * 1e3) << " ms; trains " << vehicle_line(in.nominal.settings) << ".\n";
}

void report_details(std::ostringstream& o, const ReportInput& in) {
  o << "\n## Deck acceleration per train (A2.4.4.2.1(4))\n\n| train | max acc. [m/s²] | station | speed [km/h] | mass |\n|---|---:|---|---:|---|\n";
  std::map<std::string, const study::EnvelopeRow*> worst;
  std::vector<std::string> order;
  for (const auto& row : in.r.rows) {
    auto& w = worst[row.train];
    if (!w) order.push_back(row.train);
    if (!w || row.max_abs_acc > w->max_abs_acc) w = &row;
  }
  for (const auto& t : order)
    o << "| " << t << " | " << fmt(worst[t]->max_abs_acc) << " | " << worst[t]->station << " | " << fmt(worst[t]->speed * 3.6)
      << " | " << worst[t]->variant << " |\n";
  if (in.figures) o << "\n![Envelope over trains and masses, the governing train at each peak](envelope.png)\n";
  o << "\n## Dynamic increments φ′dyn (6.4.6.5)\n\nThe largest over trains, speeds and masses, per quantity "
       "(every train in phi_dyn.csv):\n\n| quantity | φ′dyn | train | speed [km/h] | mass | max dynamic | max quasi-static |\n|---|---:|---|---:|---|---:|---:|\n";
  std::map<std::string, const Increment*> top;
  std::vector<std::string> qs;
  for (const auto& i : in.inc) {
    auto& t = top[i.quantity];
    if (!t) qs.push_back(i.quantity);
    if (!t || i.phi() > t->phi()) t = &i;
  }
  for (const auto& q : qs)
    o << "| " << q << " | " << fmt(top[q]->phi(), 3) << " | " << top[q]->train << " | " << fmt(top[q]->speed * 3.6) << " | "
      << top[q]->variant << " | " << shown(q, top[q]->dynamic) << " | " << shown(q, top[q]->quasi_static) << " |\n";
  if (in.figures) o << "\n![φ′dyn per quantity](phi_dyn.png)\n";
}

void report_notes(std::ostringstream& o, const ReportInput& in) {
  o << "\n## Notes and items to confirm\n\n";
  for (const auto& n : in.p.notes) o << "- " << n << "\n";
  o << "- To confirm against the text of the standard: φ″ (Annex C) in the design effect; the deflection and end-rotation "
       "limits (given by assess.deflection_limit_ratio and assess.end_rotation_limit_rad).\n";
  if (in.nominal.settings.vehicle.model == study::VehicleModel::forces)
    o << "- Passenger comfort and wheel unloading are checked with vehicle models only (train.vehicle = \"sprung\" or "
         "\"multibody\", docs/vehicles.md): with moving forces there are no car bodies and no contact forces.\n";
  else
    o << "- The car-body acceleration checked is the largest on each body's floor at its centre and above its bogie centres "
         "(EN 12299's floor positions: bounce plus pitch times the half bogie spacing; a sprung mass's own), "
      << (in.nominal.settings.vehicle.comfort_lowpass_hz > 0.0
              ? "low-passed at " + fmt(in.nominal.settings.vehicle.comfort_lowpass_hz) + " Hz (train.comfort_lowpass_hz)"
              : std::string("unfiltered (train.comfort_lowpass_hz sets a low-pass)"))
      << ". To confirm: the comfort limits of Table A2.9.\n";
  if (!in.r.failures.empty()) o << "- **" << in.r.failures.size() << " case(s) failed** (failures.csv): the checks above leave them out.\n";
  o << "\n## Provenance\n\nScenario `" << in.flat.path << "`; " << io::version() << " (commit " << io::git_commit() << "); command `"
    << in.command_line << "`. Tables: checks.csv, envelope.csv, load_effects.csv, phi_dyn.csv, mass_cases.csv, governing.csv, failures.csv"
    << (in.r.vehicles.empty() ? "" : ", vehicles.csv (the vehicles' extremes per case)") << "; "
       "manifest.toml holds the resolved scenario and the checksums of its files.\n";
}

// The sleeper layout at the joints (issue #20 part 3): identical spans coupled through the track
// have near-equal first modes, and which span dominates the lower one flips with where the
// sleepers sit; the per-span peaks follow, their sum and the resonance speeds do not.
struct LayoutSensitivity {
  bool near = false;        // two spans' modes of the same order within 2 %
  int span_a = 0, span_b = 0;
  double split = 0.0;       // their relative frequency difference
  std::string train, variant;
  double speed = 0.0;       // [m/s] the governing acceleration case
  std::vector<double> offsets;               // [m] track.first_sleeper_offset
  std::vector<std::vector<double>> peaks;    // [offset][station] max |acc| [m/s²]
};

LayoutSensitivity layout_sensitivity(const Plan& p, const std::vector<Check>& checks) {
  LayoutSensitivity ls;
  const study::Variant* gov = nullptr;
  const Check* acc = nullptr;
  for (const auto& k : checks)
    if (k.check == "deck acceleration" && (!acc || k.value > acc->value)) acc = &k;
  for (const auto& v : p.variants)
    if (acc && v.label == acc->variant) gov = &v;
  if (!gov || !gov->scenario.track) return ls;
  for (std::size_t i = 0; i < p.deck_modes.size() && !ls.near; ++i)
    for (std::size_t j = i + 1; j < p.deck_modes.size() && !ls.near; ++j) {
      const auto &a = p.deck_modes[i], &b = p.deck_modes[j];
      const double split = std::abs(b.frequency_hz - a.frequency_hz) / a.frequency_hz;
      if (a.bending.span != b.bending.span && a.bending.order == b.bending.order && split < 0.02)
        ls = {true, a.bending.span, b.bending.span, split, acc->train, acc->variant, acc->speed, {}, {}};
    }
  if (!ls.near) return ls;
  const load::Train* train = nullptr;
  for (const auto& t : gov->scenario.trains)
    if (t.name == ls.train) train = &t;
  if (!train) return ls;
  const double d = gov->scenario.track->sleeper_spacing;
  for (int k = 0; k < 4; ++k) {
    study::Scenario sc = gov->scenario;
    sc.track->first_sleeper_offset = d * k / 4.0;
    const study::PreparedModel pm = study::prepare_model(sc, false);
    std::vector<double> row;
    for (const auto& pk : study::peaks(study::simulate(pm, *train, ls.speed, sc.settings))) row.push_back(pk.max_abs_acc);
    ls.offsets.push_back(sc.track->first_sleeper_offset);
    ls.peaks.push_back(row);
  }
  return ls;
}

void report_layout(std::ostringstream& o, const LayoutSensitivity& ls, const study::Scenario& sc) {
  if (!ls.near) return;
  o << "\n## Sleeper layout at the joints (docs/model.md)\n\nSpans " << ls.span_a << " and " << ls.span_b
    << " have bending modes of the same order " << fmt(100 * ls.split, 2)
    << " % apart: coupled through the track, which span dominates the lower mode depends on where the sleepers sit at the "
       "joints, and the per-span peaks with it (their sum and the resonance speeds do not). The governing acceleration case ("
    << ls.train << ", " << fmt(ls.speed * 3.6) << " km/h, " << ls.variant << ") with the sleepers moved (track.first_sleeper_offset):\n\n| offset [m] |";
  for (const auto& st : sc.stations) o << " " << st.name << " [m/s²] |";
  o << "\n|---:|";
  for (std::size_t i = 0; i < sc.stations.size(); ++i) o << "---:|";
  o << "\n";
  for (std::size_t k = 0; k < ls.offsets.size(); ++k) {
    o << "| " << fmt(ls.offsets[k], 3) << " |";
    for (double a : ls.peaks[k]) o << " " << fmt(a) << " |";
    o << "\n";
  }
  o << "| spread |";
  for (std::size_t j = 0; j < sc.stations.size(); ++j) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const auto& row : ls.peaks) lo = std::min(lo, row[j]), hi = std::max(hi, row[j]);
    o << " " << fmt(100 * (hi / lo - 1), 3) << " % |";
  }
  o << "\n\nA check near its limit should hold for every layout: give the built one with track.first_sleeper_offset.\n";
}

std::string report_text(const ReportInput& in) {
  std::ostringstream o;
  o << "# Dynamic assessment (EN 1991-2 6.4, EN 1990 A2): " << (in.nominal.title.empty() ? in.flat.path : in.nominal.title) << "\n\n";
  report_summary(o, in);
  report_inputs(o, in);
  report_details(o, in);
  if (in.layout) report_layout(o, *in.layout, in.nominal);
  report_notes(o, in);
  return o.str();
}

// The figures, by scripts/plot/plot_assess.py (Python with matplotlib); false when it cannot run.
bool make_figures(const std::string& out, bool quiet) {
  // VIADUCT_PLOT_DIR, then the installed scripts, then the source tree the tool was built from.
  const char* env = std::getenv("VIADUCT_PLOT_DIR");
  std::string script;
  for (const std::string& dir : {std::string(env ? env : ""), std::string(VIADUCT_INSTALLED_SCRIPTS),
                                std::string(VIADUCT_SOURCE_DIR) + "/scripts/plot"})
    if (!dir.empty() && std::ifstream(dir + "/plot_assess.py").good()) {
      script = dir + "/plot_assess.py";
      break;
    }
  if (script.empty() || out.find('\'') != std::string::npos) return false;
  // The directory is still being written (its manifest comes last): the script need not check it.
  std::error_code ec;
  const std::string abs = std::filesystem::absolute(out, ec).lexically_normal().string();
  const std::string cmd = "VIADUCT_WRITING='" + (abs.size() > 1 && abs.back() == '/' ? abs.substr(0, abs.size() - 1) : abs) +
                          "' /usr/bin/python3 '" + script + "' '" + out + "'" + (quiet ? " >/dev/null 2>&1" : " >/dev/null");
  return std::system(cmd.c_str()) == 0;
}

void print_checks(const std::vector<Check>& checks) {
  std::printf("\n  %-38s %-24s %14s %14s %7s  %s\n", "check", "quantity", "value", "limit", "util.", "result");
  for (const auto& k : checks)
    std::printf("  %-38s %-24s %14s %14s %7s  %s\n", k.check.c_str(), k.quantity.c_str(), shown(k.quantity, k.value).c_str(),
                shown(k.quantity, k.limit).c_str(), fmt(k.utilisation(), 3).c_str(), k.verdict.c_str());
}

void declare_assess(po::options_description& d, AssessOptions& a) {
  d.add_options()("no-plots", po::bool_switch()->notifier([&a](bool v) { a.plots = !v; }),
                  "write report.md without running scripts/plot/plot_assess.py");
}

int run_assess(const Common& o, const AssessOptions& opts) {
  const auto t0 = std::chrono::steady_clock::now();
  io::FlatScenario flat = load_scenario(o);
  const Config c = read_config(flat, o.scenario);
  Plan p;
  plan_damping_and_cutoff(flat, c, p);
  plan_variants(flat, c, p);
  for (auto& v : p.variants) v.scenario.settings.ida.log = log_printer(o.quiet);
  make_out_dir(o.out);
  study::SweepOptions so;
  so.threads = o.threads;
  so.progress = progress_printer("assess", o.quiet);
  so.load_effects = true;
  const study::SweepResult r = study::run_sweep(p.variants, so);
  const study::Scenario& nominal = p.variants.front().scenario;
  const Statics st = statics_of(nominal, c);
  for (const auto& s : nominal.stations)
    if (on_rigid_support(s.name, nominal))
      p.notes.push_back("station " + s.name + " sits on a rigid bearing: its deflection and acceleration are zero by construction "
                        "and get no check rows (its moment, shear and strain do)");
  const std::vector<Increment> inc = increments(r.quantities);
  const std::vector<Check> checks = all_checks(r, st, inc, nominal, c, p);
  io::write_envelope_csv(o.out + "/envelope.csv", r.rows, p.variants);
  io::write_quantities_csv(o.out + "/load_effects.csv", r.quantities, p.variants);
  io::write_governing_csv(o.out + "/governing.csv", study::governing(r.rows));
  io::write_failures_csv(o.out + "/failures.csv", r.failures);
  write_checks_csv(o.out + "/checks.csv", checks);
  write_increments_csv(o.out + "/phi_dyn.csv", inc);
  write_mass_cases_csv(o.out + "/mass_cases.csv", p);
  if (!r.vehicles.empty()) io::write_vehicle_envelope_csv(o.out + "/vehicles.csv", r.vehicles, p.variants);
  io::Manifest m = start_manifest(o, "assess");
  m.as_run = io::settings_as_run(nominal.settings);
  m.extra = {{"acceleration_limit_mps2", format_number(c.acc_limit)}, {"cutoff_hz", format_number(p.f_cut)},
             {"damping_ratio", format_number(p.zeta)}, {"line_speed_kmh", format_number(c.line_speed * 3.6)},
             {"n_cases", std::to_string(r.summary.n_cases)}, {"n_failed", std::to_string(r.summary.n_failed)},
             {"threads", std::to_string(o.threads)}};
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  const LayoutSensitivity layout = layout_sensitivity(p, checks);
  const bool figures = opts.plots && make_figures(o.out, o.quiet);
  ReportInput in{c, p, r, checks, inc, flat, nominal, o.command_line, figures, &layout};
  io::write_text_file(o.out + "/report.md", report_text(in));
  if (!o.quiet) {
    std::printf("assessment: %zu cases (%zu mass case%s), %zu failed, %.1f s; cut-off %.1f Hz, damping %.3f %%\n", r.summary.n_cases,
                p.variants.size(), p.variants.size() > 1 ? "s" : "", r.summary.n_failed, r.summary.wall_s, p.f_cut, 100 * p.zeta);
    print_checks(checks);
    if (layout.near && !layout.peaks.empty()) {
      double spread = 0.0;
      for (std::size_t j = 0; j < layout.peaks.front().size(); ++j) {
        double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
        for (const auto& row : layout.peaks) lo = std::min(lo, row[j]), hi = std::max(hi, row[j]);
        spread = std::max(spread, hi / lo - 1.0);
      }
      std::printf("\nspans %d and %d: modes %.2f %% apart; the governing peak moves by up to %.1f %% with the sleeper layout "
                  "(report.md, track.first_sleeper_offset)\n",
                  layout.span_a, layout.span_b, 100 * layout.split, 100 * spread);
    }
    std::printf("\nwrote %s/report.md%s, checks.csv, envelope.csv, load_effects.csv, phi_dyn.csv\n", o.out.c_str(),
                figures ? " (with figures)" : "");
  }
  if (opts.plots && !figures)
    print_warnings("assess", {"figures not made (needs /usr/bin/python3 with matplotlib and scripts/plot/plot_assess.py): report.md "
                              "has the tables only; make them with scripts/plot/plot_assess.py " + o.out});
  return sweep_exit_code("assess", o.scenario, r);
}

}  // namespace

Command assess_command() {
  Command c;
  c.name = "assess";
  c.summary = "the EN 1991-2 dynamic check: HSLM and real trains, speeds to 1.2 x line speed, checks (report.md)";
  c.usage_and_samples =
      "Runs the dynamic check of EN 1991-2 6.4 / EN 1990 A2 on the scenario's bridge (docs/assess.md):\n"
      "HSLM-A1..A10 and the scenario's other trains, speeds up to 1.2 x assess.line_speed_kmh refined\n"
      "around every resonance, damping from Table 6.6 (+ Eq. 6.13), lower and upper mass bounds, the\n"
      "frequency cut-off max(30 Hz, 1.5 f1, f3). Writes OUT/report.md (with PNGs by\n"
      "scripts/plot/plot_assess.py), checks.csv (value, limit, utilisation, governing case, clause),\n"
      "envelope.csv, load_effects.csv, phi_dyn.csv, mass_cases.csv (what each mass case sets), governing.csv,\n"
      "failures.csv and manifest.toml. With vehicle models (train.vehicle = sprung or multibody) also\n"
      "vehicles.csv and two more checks: passenger comfort (car-body acceleration against\n"
      "assess.comfort_level's b_v, EN 1990 A2.4.4.3.1) and wheel unloading (assess.unloading_ratio_limit).\n"
      "The scenario's damping, filter and sweep keys are replaced by the assessment's.\n\n"
      "Sample runs:\n"
      "  viaduct assess scenarios/hslm-simply-supported.toml --set assess.speed_step_kmh=20 --set assess.refine_band=0 --no-plots --out out/assess-hslm\n";
  bind(c, declare_assess, run_assess);
  return c;
}

}  // namespace viaduct::cli
