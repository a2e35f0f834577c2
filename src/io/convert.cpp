// FlatScenario -> study::Scenario, sweep variants, train files.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <toml.hpp>

#include "flat_items.hpp"
#include "toml_file.hpp"

#include "viaduct/io/profile.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/tradeoff.hpp"
#include "viaduct/study/vehicles.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace detail {
std::vector<std::size_t> item_indices(const FlatScenario& f, const std::string& head) {
  std::set<std::size_t> idx;
  const std::string pre = head + "[";
  for (const auto& kv : f.values) {
    if (kv.first.compare(0, pre.size(), pre) != 0) continue;
    idx.insert(static_cast<std::size_t>(std::stoul(kv.first.substr(pre.size()))));
  }
  return {idx.begin(), idx.end()};
}
}  // namespace detail
using detail::item_indices;

namespace {

std::string conv_num(double v) { return format_number(v, 12); }

[[noreturn]] void bad(const Value& v, const std::string& msg) { throw InputError(v.where, msg); }

double get_number(const FlatScenario& f, const std::string& key) { return f.at(key).x; }

// A number-or-list key expanded to n values.
std::vector<double> per_span(const FlatScenario& f, const std::string& key, std::size_t n) {
  const Value& v = f.at(key);
  if (v.type != ValueType::number_list) return std::vector<double>(n, v.x);
  if (v.xs.size() != n)
    bad(v, "needs one value or one per span (" + std::to_string(n) + "), got " + std::to_string(v.xs.size()));
  return v.xs;
}

// Where an error of a section's is_valid() belongs: the key of the section whose last component
// starts the message ("pad.k must be > 0 ..." -> track.pad.k), else the section's first key with a
// line.
const SourceLocation& where_of(const FlatScenario& f, const std::string& section, const std::string& why) {
  const Value* fallback = nullptr;
  const std::string pre = section + ".";
  for (const auto& [key, v] : f.values) {
    if (key.compare(0, pre.size(), pre) != 0) continue;
    const std::string field = key.substr(pre.size());
    if (why.compare(0, field.size() + 1, field + " ") == 0) return v.where;
    if (!fallback || (fallback->where.line == 0 && v.where.line > 0)) fallback = &v;
  }
  if (fallback) return fallback->where;
  static const SourceLocation none;
  return none;
}

// The spans (per-span lists) and the checks that involve several keys; the scalar keys were set
// by their schema setters.
void finish_bridge(const FlatScenario& f, model::BridgeParams& b) {
  const Value& lens = f.at("bridge.span_lengths");
  if (lens.xs.empty()) bad(lens, "needs at least one span");
  const auto EI = per_span(f, "bridge.EI", lens.xs.size());
  const auto m = per_span(f, "bridge.mass_per_m", lens.xs.size());
  for (std::size_t i = 0; i < lens.xs.size(); ++i) b.spans.push_back({lens.xs[i], EI[i], m[i]});
  if (!b.bearings.rigid && !(b.bearings.k > 0.0))
    bad(f.at("bridge.bearings.k"), "must be > 0 [N/m] when bridge.bearings.rigid = false, got " + conv_num(b.bearings.k));
  if (b.damping.kind == model::DampingKind::rayleigh) {
    if (!(b.damping.f1_hz > 0.0)) bad(f.at("bridge.damping.f1_hz"), "must be > 0 Hz for Rayleigh damping");
    if (!(b.damping.f2_hz > b.damping.f1_hz))
      bad(f.at("bridge.damping.f2_hz"), "must be > bridge.damping.f1_hz for Rayleigh damping");
  }
  std::string why;
  if (!b.is_valid(&why)) throw InputError(where_of(f, "bridge", why), why);
}

// The rail's E·I and ρ·A, then the track's checks.
void finish_track(const FlatScenario& f, model::TrackParams& t) {
  t.rail_EI = get_number(f, "track.rail.E") * get_number(f, "track.rail.I");
  t.rail_mass_per_m = get_number(f, "track.rail.density") * get_number(f, "track.rail.A");
  std::string why;
  if (!t.is_valid(&why)) throw InputError(where_of(f, "track", why), why);
}

// "hslm:A1-A10", "hslm:A4" or "hslm:A1,A5,A9": the Eurocode HSLM-A trains by number.
std::vector<load::Train> hslm_trains(const std::string& entry, const Value& where) {
  const std::string spec = entry.substr(5);
  auto number = [&](const std::string& s) {
    if (s.size() < 2 || (s[0] != 'A' && s[0] != 'a') || s.find_first_not_of("0123456789", 1) != std::string::npos ||
        s.size() > 3)
      bad(where, "'" + entry + "': HSLM trains are named A1 to A10 (\"hslm:A1-A10\", \"hslm:A4\", \"hslm:A1,A5\")");
    const int n = std::stoi(s.substr(1));
    if (n < 1 || n > 10) bad(where, "'" + entry + "': HSLM trains are A1 to A10, not A" + std::to_string(n));
    return n;
  };
  std::vector<int> numbers;
  std::stringstream ss(spec);
  for (std::string part; std::getline(ss, part, ',');) {
    const auto dash = part.find('-');
    if (dash == std::string::npos) {
      numbers.push_back(number(part));
    } else {
      const int a = number(part.substr(0, dash)), b = number(part.substr(dash + 1));
      if (b < a) bad(where, "'" + entry + "': the range must go up (A1-A10)");
      for (int n = a; n <= b; ++n) numbers.push_back(n);
    }
  }
  if (numbers.empty()) bad(where, "'" + entry + "': name the trains (\"hslm:A1-A10\")");
  std::vector<load::Train> out;
  for (int n : numbers) out.push_back(load::hslm_a("HSLM-A" + std::to_string(n), load::hslm_a_row(n)));
  return out;
}

std::vector<double> speeds_of(const FlatScenario& f) {
  const bool list = f.has("sweep.speeds_kmh");
  const bool kmh = f.has("sweep.speed_min_kmh") || f.has("sweep.speed_max_kmh") || f.has("sweep.speed_step_kmh");
  const bool mps = f.has("sweep.speed_min_mps") || f.has("sweep.speed_max_mps") || f.has("sweep.n_speeds");
  if (int(list) + int(kmh) + int(mps) > 1)
    throw InputError(where_of(f, "sweep", ""),
                     "give speeds one way only: speeds_kmh, or speed_min/max/step_kmh, or speed_min/max_mps with n_speeds "
                     "(on the command line, --unset the keys of the other way)");
  std::vector<double> v;
  if (list) {
    for (double s : f.at("sweep.speeds_kmh").xs) v.push_back(s / 3.6);
  } else if (kmh) {
    const double a = get_number(f, "sweep.speed_min_kmh"), b = get_number(f, "sweep.speed_max_kmh"),
                 s = get_number(f, "sweep.speed_step_kmh");
    if (b < a) bad(f.at("sweep.speed_max_kmh"), "must be >= sweep.speed_min_kmh");
    const double n_steps = std::floor((b - a) / s + 1e-9);  // checked before it becomes an integer
    if (!(n_steps <= 1000000)) bad(f.at("sweep.speed_step_kmh"), "gives more than a million speeds");
    const auto n = static_cast<long>(n_steps);
    for (long i = 0; i <= n; ++i) v.push_back((a + static_cast<double>(i) * s) / 3.6);
  } else if (mps) {
    const double a = get_number(f, "sweep.speed_min_mps"), b = get_number(f, "sweep.speed_max_mps");
    const double n_speeds = get_number(f, "sweep.n_speeds");
    if (n_speeds > 1000000) bad(f.at("sweep.n_speeds"), "must be at most a million speeds");
    const int n = static_cast<int>(n_speeds);
    if (b < a) bad(f.at("sweep.speed_max_mps"), "must be >= sweep.speed_min_mps");
    for (int i = 0; i < n; ++i) v.push_back(n == 1 ? a : a + (b - a) * i / (n - 1));
  }
  // Speeds near the largest double overflow in the arithmetic above: refused, never inf.
  for (double x : v)
    if (!std::isfinite(x)) throw InputError(where_of(f, "sweep", ""), "the speeds are too large to compute (" + conv_num(x) + " m/s)");
  return v;
}

// A deck station `s` repeated along its span of length L about `every` apart: round(L/every)
// equal parts (at least 1, at most 1000), named <name>_<x>m with x to two decimals, or to one
// more than the spacing needs when they are closer than 1 cm (neighbours never share a name).
std::vector<study::StationSpec> stations_along(const Value& every, const study::StationSpec& s, double L) {
  const double n_real = std::round(L / every.x);
  if (!(n_real <= 1000.0))
    bad(every, "would place " + conv_num(n_real + 1) + " stations along the " + conv_num(L) + " m span (at most 1001): raise it");
  const int n = std::max(1, static_cast<int>(n_real));
  const int decimals = std::max(2, static_cast<int>(std::ceil(-std::log10(L / n))) + 1);
  std::vector<study::StationSpec> out;
  for (int k = 0; k <= n; ++k) {
    study::StationSpec a = s;
    a.x_local = k == n ? L : L * k / n;
    char buf[48];
    std::snprintf(buf, sizeof buf, "_%.*fm", decimals, a.x_local);
    a.name = s.name + buf;
    out.push_back(std::move(a));
  }
  return out;
}

// The [[stations]] entries, each checked at its keys.
// Stations along a span (every_m) go to `along` (load effects only).
std::vector<study::StationSpec> stations_of(const FlatScenario& f, const model::BridgeParams& bridge, bool has_track,
                                            std::vector<study::StationSpec>& along_out) {
  std::vector<study::StationSpec> out;
  std::set<std::string> names;
  for (std::size_t i : item_indices(f, "stations")) {
    const std::string pre = "stations[" + std::to_string(i) + "].";
    study::StationSpec s;
    const Value& name = f.at(pre + "name");
    s.name = name.s;
    if (s.name.empty() || s.name.find_first_of(", \"\n") != std::string::npos)
      bad(name, "station names must be non-empty without spaces, commas or quotes");
    if (!names.insert(s.name).second) bad(name, "duplicate station name '" + s.name + "'");
    if (f.has(pre + "span")) {
      const Value& span = f.at(pre + "span");
      if (span.x > static_cast<double>(bridge.spans.size()))
        bad(span, "span " + conv_num(span.x) + " does not exist (the bridge has " + std::to_string(bridge.spans.size()) + ")");
      s.on_deck = true;
      s.span = static_cast<std::size_t>(span.x) - 1;
      const double L = bridge.spans[s.span].length;
      const bool at = f.has(pre + "at"), x = f.has(pre + "x"), along = f.has(pre + "every_m");
      if (int(at) + int(x) + int(along) != 1)
        bad(span, "a deck station needs exactly one of 'at' (fraction), 'x' (metres) or 'every_m' (stations along the span)");
      if (along) s.x_local = 0.0;
      else if (at) s.x_local = f.at(pre + "at").x * L;
      else {
        s.x_local = f.at(pre + "x").x;
        if (s.x_local > L) bad(f.at(pre + "x"), "must be <= the span length " + conv_num(L) + " m");
      }
      if (f.has(pre + "track_x")) bad(f.at(pre + "track_x"), "a station is on a span or on the track, not both");
      if (f.has(pre + "fibre_m")) {
        const Value& y = f.at(pre + "fibre_m");
        if (!(std::abs(y.x) <= 10.0) || y.x == 0.0)
          bad(y, "the fibre's distance from the neutral axis must be non-zero and within 10 m of it (a deck is not deeper), got " + conv_num(y.x));
        s.fibre_m = y.x;
      }
      if (along) {  // the stations along the span, each checked for a unique name
        for (study::StationSpec& a : stations_along(f.at(pre + "every_m"), s, L)) {
          if (!names.insert(a.name).second) bad(name, "station '" + a.name + "' (along the span) repeats a station name");
          along_out.push_back(std::move(a));
        }
        continue;
      }
    } else if (f.has(pre + "track_x")) {
      s.on_deck = false;
      s.x_track = f.at(pre + "track_x").x;
      if (!has_track) bad(f.at(pre + "track_x"), "a rail station needs a track section in the scenario");
      if (f.has(pre + "every_m")) bad(f.at(pre + "every_m"), "stations along a span need 'span', not 'track_x'");
      if (f.has(pre + "fibre_m")) bad(f.at(pre + "fibre_m"), "strain is a deck output: fibre_m needs a deck station (span)");
    } else {
      bad(name, "station needs 'span' (with 'at' or 'x') or 'track_x'");
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace

// The vehicle keys that combine: the sprung spec (all or none), the irregularity's source, and the
// trains each vehicle model needs.
void vehicles_of(const FlatScenario& f, study::Scenario& sc) {
  auto given = [&](const char* key) { return f.has(key) && !f.defaulted.count(key); };
  study::VehicleSettings& vs = sc.settings.vehicle;
  const bool has_mu = given("train.unsprung_mass_kg"), has_k = given("train.suspension_stiffness_N_m");
  if (has_mu != has_k)
    bad(f.at(has_mu ? "train.unsprung_mass_kg" : "train.suspension_stiffness_N_m"),
        std::string("needs ") + (has_mu ? "train.suspension_stiffness_N_m" : "train.unsprung_mass_kg") + " too (a sprung mass per axle)");
  if (has_mu)
    vs.sprung = load::SprungSpec{f.at("train.unsprung_mass_kg").x, f.at("train.suspension_stiffness_N_m").x,
                                 f.at("train.suspension_damping_Ns_m").x};
  const Value& model = f.at("train.vehicle");
  for (const auto& t : sc.trains) {
    if (vs.model == study::VehicleModel::multibody && t.coaches.empty())
      bad(model, "multibody needs trains of coaches (train files of kind \"coaches\"); '" + t.name + "' is a list of axles");
    if (vs.model == study::VehicleModel::sprung && !vs.sprung && t.coaches.empty())
      bad(model, "sprung: '" + t.name + "' is a list of axles: give train.unsprung_mass_kg and train.suspension_stiffness_N_m");
  }
  if (vs.model != study::VehicleModel::forces && f.at("analysis.superposition").s == "unit-response")
    bad(f.at("analysis.superposition"), "unit-response composes constant axle loads: it cannot take train.vehicle = \"" +
                                            model.s + "\" (use \"direct\")");
  if (vs.model != study::VehicleModel::forces && f.at("analysis.method").s == "ida") {
    // (a preset sets a cut-off of its own)
    if (!(f.at("modal.n_modes").x > 0.0) && !(f.at("modal.max_frequency_hz").x > 0.0) && f.at("analysis.preset").s.empty())
      bad(f.at("analysis.method"), "ida with vehicles integrates the structure's modes: give modal.max_frequency_hz (or "
                                   "modal.n_modes); every mode would bring the kHz modes whose steps IDA is meant to avoid "
                                   "(60-200 Hz: docs/vehicles.md)");
    if (vs.contact == study::ContactModel::rigid)
      bad(f.at("train.contact"), "rigid under a wheel with mass is an index-3 constraint IDA does not take: use \"hertz\" "
                                 "with analysis.method = \"ida\"");
    if (vs.sprung && !(vs.sprung->unsprung_mass > 0.0))
      bad(f.at("train.unsprung_mass_kg"), "must be > 0 [kg] with analysis.method = \"ida\" (a massless wheel is an "
                                          "algebraic equation IDA is not given)");
  }
  study::IrregularitySettings& irr = sc.settings.irregularity;
  if (given("irregularity.profile") && !f.at("irregularity.profile").s.empty()) {
    const Value& p = f.at("irregularity.profile");
    if (!irr.spectrum.empty()) bad(p, "give a measured profile or irregularity.spectrum, not both");
    try {
      irr.measured = std::make_shared<const load::RailProfile>(read_rail_profile(p.s));
    } catch (const InputError& e) {
      bad(p, e.what());
    }
    irr.measured_file = p.s;
  }
  if (irr.taper > irr.run_in)
    bad(f.at("irregularity.taper_m"), "must not exceed irregularity.run_in_m (" + conv_num(irr.run_in) + " m): the profile fades in on the run-in");
  if (irr.lambda_min >= irr.lambda_max)
    bad(f.at("irregularity.min_wavelength_m"), "must be below irregularity.max_wavelength_m (" + conv_num(irr.lambda_max) + " m)");
  if (irr.enabled() && vs.model == study::VehicleModel::forces)
    bad(f.at(irr.measured ? "irregularity.profile" : "irregularity.spectrum"),
        "moving forces do not see the rail's profile: set train.vehicle = \"sprung\" or \"multibody\"");
  // What needs the model's load path: a measured profile must cover it, a track's end transition
  // must end before the bridge (checked again per sweep variant when the model is prepared).
  if (vs.model != study::VehicleModel::forces && (irr.measured || sc.track)) {
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    try {
      study::require_transition(s, vs.end_transition);
    } catch (const InputError& e) {
      bad(f.at("train.end_transition_m"), e.what());
    }
    if (irr.measured) try {
        study::rail_profile(s, irr);
      } catch (const InputError& e) {
        bad(f.at("irregularity.profile"), e.what());
      }
  }
}

void require_method_built(const Value& method_key, const solve::MethodTraits& traits) {
  if (!traits.built) bad(method_key, traits.not_built);
}

study::Scenario to_scenario(const FlatScenario& f) {
  study::Scenario sc;
  bool has_track = false;
  for (const auto& kv : f.values)
    if (kv.first.compare(0, 6, "track.") == 0) has_track = true;
  if (has_track) sc.track.emplace();
  // A missing required key of the model's sections is reported first, the first in schema order.
  for (const KeySpec& spec : scenario_schema()) {
    const bool model_key = spec.key.compare(0, 7, "bridge.") == 0 || spec.key.compare(0, 6, "train.") == 0 ||
                           (has_track && spec.key.compare(0, 6, "track.") == 0);
    if (model_key && spec.required() && !f.has(spec.key)) (void)f.at(spec.key);  // throws: required key is missing
  }
  // Every key that sets one field, through its schema setter; a required key that is missing is
  // an error, an optional one without default keeps the field's value.
  for (const KeySpec& spec : scenario_schema()) {
    if (!spec.set || (!has_track && spec.key.compare(0, 6, "track.") == 0)) continue;
    if (f.has(spec.key) || spec.required()) spec.set(sc, f.at(spec.key));
  }
  finish_bridge(f, sc.bridge);
  if (has_track) finish_track(f, *sc.track);
  try {
    model::check_model_size(sc.bridge, sc.track);
  } catch (const InputError& e) {
    // The message starts with the key it blames: reported at that key's line.
    const std::string why = e.what();
    const std::string key = why.substr(0, why.find(' '));
    if (!f.has(key)) throw;
    throw InputError(f.at(key).where, why.substr(key.size() + 1));
  }

  // Trains.
  const Value& files = f.at("train.files");
  if (files.ss.empty()) bad(files, "needs at least one train file");
  for (const auto& p : files.ss) {
    if (is_builtin_train(p)) {
      for (auto& t : hslm_trains(p, files)) sc.trains.push_back(std::move(t));
      continue;
    }
    try {
      sc.trains.push_back(read_train_file(p));
    } catch (const InputError& e) {
      throw InputError(files.where, e.what());
    }
  }

  vehicles_of(f, sc);

  // Settings: the preset first, explicit keys on top of it.
  auto& st = sc.settings;
  const Value& preset = f.at("analysis.preset");
  if (!preset.s.empty()) {
    // The preset first, explicit keys on top of it.
    study::RunSettings p;
    try {
      p = study::preset_settings(preset.s, sc);
    } catch (const InputError& e) {
      bad(preset, e.what());
    }
    auto given = [&](const char* key) { return f.has(key) && !f.defaulted.count(key); };
    if (!given("analysis.method")) st.method = p.method;
    if (!given("analysis.dt")) st.dt = p.dt;
    if (!given("modal.n_modes")) st.modal.n_modes = p.modal.n_modes;
    if (!given("modal.max_frequency_hz")) st.modal.max_frequency_hz = p.modal.max_frequency_hz;
    if (!given("modal.static_correction")) st.modal.static_correction = p.modal.static_correction;
    if (!given("modal.damping_vectors")) st.modal.damping_vectors = p.modal.damping_vectors;
  }
  // (a massless wheel's rigid contact is an algebraic equation, which takes the correction)
  const bool wheel_mass = st.vehicle.model == study::VehicleModel::multibody ||
                          (st.vehicle.sprung ? st.vehicle.sprung->unsprung_mass > 0.0 : true);
  if (st.vehicle.model != study::VehicleModel::forces && st.vehicle.contact == study::ContactModel::rigid && wheel_mass &&
      st.method == study::Method::modal && st.modal.static_correction)
    bad(f.at("train.contact"), "rigid under a wheel with mass on the modal fast path takes no static correction (the rail under a wheel that follows it "
                               "would need the contact forces' second derivative): set modal.static_correction = false, or use "
                               "\"hertz\" or analysis.method = \"newmark\"");
  require_method_built(f.at("analysis.method"), solve::method_traits(st.method));
  {
    // The scheme's rules at the key they blame (NewmarkOptions::is_valid names beta, gamma or alpha).
    std::string why;
    if (!st.newmark.is_valid(&why)) {
      std::string key = "analysis.alpha";
      for (const char* field : {"beta", "gamma"})
        if (why.rfind(std::string("NewmarkOptions::") + field + " ", 0) == 0) key = std::string("analysis.") + field;
      throw InputError(f.at(key).where, why);
    }
  }
  if (st.filter.enabled) {
    std::string why;
    if (!st.filter.cheby.is_valid(1.0 / st.dt, &why)) {
      // The key of the field the message names ("Cheby1Spec::order = 13: ..."); the band edges
      // against fs name filter.high_hz, which analysis.dt limits too.
      std::string key = "filter.high_hz";
      for (const char* field : {"order", "ripple_db", "low_hz"})
        if (why.rfind(std::string("Cheby1Spec::") + field + " ", 0) == 0) key = std::string("filter.") + field;
      throw InputError(f.at(key).where, why);
    }
  }

  // The comfort check's low-pass, designed as the filter's (study::VehicleHistory::max_floor_acc).
  if (st.vehicle.model != study::VehicleModel::forces && st.vehicle.comfort_lowpass_hz > 0.0) {
    signal::Cheby1Spec spec = st.filter.cheby;
    spec.band = signal::BandType::lowpass;
    spec.high_hz = st.vehicle.comfort_lowpass_hz;
    std::string why;
    if (!spec.is_valid(1.0 / st.dt, &why)) throw InputError(f.at("train.comfort_lowpass_hz").where, why);
  }

  sc.stations = stations_of(f, sc.bridge, has_track, sc.effect_stations);
  if (sc.stations.empty() && !sc.effect_stations.empty())
    bad(f.at("stations[0].every_m"), "stations along a span give load effects only: add a station with 'at', 'x' or "
                                     "'track_x' (the accelerations and deflections of a sweep are taken there)");
  if (sc.stations.empty()) throw InputError(SourceLocation{f.path, 0, "stations"}, "at least one [[stations]] entry is required");

  sc.sweep_speeds = speeds_of(f);
  return sc;
}


std::vector<study::Variant> sweep_variants(const FlatScenario& flat, bool isolate_failures) {
  struct Axis {
    std::string key, label;
    std::vector<double> factors;
    SourceLocation where;  // the [[sweep.variants]] entry's key
  };
  std::vector<Axis> axes;
  // A sampled study's variants are its samples (sampled_study, sample_variant): the other
  // commands see its reference.
  const bool sampled = flat.has("sweep.mode") && flat.at("sweep.mode").s == "sample";
  for (std::size_t i : sampled ? std::vector<std::size_t>{} : item_indices(flat, "sweep.variants")) {
    const std::string pre = "sweep.variants[" + std::to_string(i) + "].";
    Axis a;
    a.key = flat.at(pre + "key").s;
    a.where = flat.at(pre + "key").where;
    a.label = flat.at(pre + "label").s.empty() ? a.key : flat.at(pre + "label").s;
    a.factors = flat.at(pre + "factors").xs;
    if (a.factors.empty()) bad(flat.at(pre + "factors"), "needs at least one factor");
    if (!flat.has(a.key)) bad(flat.at(pre + "key"), "'" + a.key + "' is not a key of this scenario");
    axes.push_back(a);
  }
  auto label_of = [](const Axis& a, double f) {
    std::ostringstream os;
    os << a.label << " x" << f;
    return os.str();
  };
  std::vector<study::Variant> out;
  auto make = [&](const std::vector<std::pair<std::size_t, double>>& settings) {
    FlatScenario v = flat;
    std::string label;
    for (const auto& [ai, factor] : settings) label += (label.empty() ? "" : ", ") + label_of(axes[ai], factor);
    // One entry per varied key (two entries of sweep.variants may vary the same key).
    std::vector<std::pair<std::string, double>> factors;
    for (const Axis& a : axes)
      if (std::none_of(factors.begin(), factors.end(), [&](const auto& kf) { return kf.first == a.key; }))
        factors.emplace_back(a.key, 1.0);
    for (const auto& [ai, factor] : settings)
      for (auto& kf : factors)
        if (kf.first == axes[ai].key) kf.second *= factor;
    try {
      for (const auto& [ai, factor] : settings) scale_key(v, axes[ai].key, factor, axes[ai].where);
      return study::Variant{label.empty() ? "reference" : label, to_scenario(v), "", factors};
    } catch (const InputError& e) {
      const std::string why = settings.empty() ? std::string(e.what()) : "variant '" + label + "': " + e.what();
      if (!isolate_failures || out.empty()) throw InputError(why);
      return study::Variant{label, out.front().scenario, why, factors};  // the reference's trains and speeds
    }
  };
  out.push_back(make({}));
  if (axes.empty() || flat.at("sweep.mode").s == "reference") return out;
  if (flat.at("sweep.mode").s == "grid") {
    std::vector<std::size_t> idx(axes.size(), 0);
    while (true) {
      std::vector<std::pair<std::size_t, double>> s;
      for (std::size_t a = 0; a < axes.size(); ++a)
        if (axes[a].factors[idx[a]] != 1.0) s.emplace_back(a, axes[a].factors[idx[a]]);
      if (!s.empty()) out.push_back(make(s));
      std::size_t a = 0;
      while (a < axes.size() && ++idx[a] == axes[a].factors.size()) idx[a++] = 0;
      if (a == axes.size()) break;
    }
  } else {
    for (std::size_t a = 0; a < axes.size(); ++a)
      for (double factor : axes[a].factors)
        if (factor != 1.0) out.push_back(make({{a, factor}}));
  }
  return out;
}

// ---------------------------------------------------------------- train files

namespace {

load::Train train_from_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open train file");
  load::Train t;
  t.name = fs::path(path).stem().string();
  std::string line;
  int ln = 0;
  bool header = false;
  std::vector<int> lines;  // of each axle
  while (std::getline(in, line)) {
    ++ln;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    if (!header) {
      std::string h = line;
      h.erase(std::remove_if(h.begin(), h.end(), ::isspace), h.end());
      if (h != "position_m,load_kN")
        throw InputError(SourceLocation{path, ln, ""}, "train CSV header must be 'position_m,load_kN', got '" + line + "'");
      header = true;
      continue;
    }
    std::stringstream ss(line);
    std::string a, b, extra;
    if (!std::getline(ss, a, ',') || !std::getline(ss, b, ',') || std::getline(ss, extra, ','))
      throw InputError(SourceLocation{path, ln, ""}, "expected two columns position_m,load_kN");
    try {
      std::size_t pa = 0, pb = 0;
      const double x = std::stod(a, &pa), p = std::stod(b, &pb);
      if (a.find_first_not_of(" \t", pa) != std::string::npos || b.find_first_not_of(" \t", pb) != std::string::npos)
        throw std::invalid_argument("trailing text");
      t.offset.push_back(x);
      t.load.push_back(p * 1e3);
      lines.push_back(ln);
    } catch (const std::exception&) {
      throw InputError(SourceLocation{path, ln, ""}, "not a number in '" + line + "'");
    }
  }
  if (t.offset.empty()) throw InputError(SourceLocation{path, ln, ""}, "train CSV has no axles");
  // Positions may start anywhere: make them offsets behind the first axle.
  const double x0 = t.offset.front();
  for (std::size_t i = 0; i < t.offset.size(); ++i) {
    t.offset[i] -= x0;
    if (i > 0 && t.offset[i] < t.offset[i - 1])
      throw InputError(SourceLocation{path, lines[i], ""},
                       "axle positions must be listed head to tail, not decreasing (axle " + std::to_string(i + 1) + ")");
  }
  try {
    t.validate();
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return t;
}

// A component file (train, coach) parsed, or InputError naming it (`what`: "train", "vehicle").
detail::TomlFile parse_component(const std::string& path, const char* what) {
  if (!fs::exists(path)) throw InputError(std::string(what) + " file not found: " + path);
  try {
    return detail::parse_toml_file(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(std::string("TOML syntax error: ") + e.what());
  }
}

}  // namespace

load::CoachSpec read_coach_file(const std::string& path) {
  const detail::TomlFile parsed = parse_component(path, "vehicle");
  const toml::value& root = parsed.root;
  auto where = [&](const std::string& key) {
    return SourceLocation{path, root.contains(key) ? parsed.line_of(root.at(key)) : 1, key};
  };
  load::CoachSpec c;
  // Key, field name in CoachSpec (as its validate() names it), field.
  const std::vector<std::tuple<const char*, const char*, double*>> fields = {
      {"body_mass_kg", "body_mass", &c.body_mass},
      {"body_pitch_inertia_kgm2", "body_pitch_inertia", &c.body_pitch_inertia},
      {"bogie_spacing_m", "bogie_spacing", &c.bogie_spacing},
      {"bogie_mass_kg", "bogie_mass", &c.bogie_mass},
      {"bogie_pitch_inertia_kgm2", "bogie_pitch_inertia", &c.bogie_pitch_inertia},
      {"wheelbase_m", "wheelbase", &c.wheelbase},
      {"wheelset_mass_kg", "wheelset_mass", &c.wheelset_mass},
      {"primary_stiffness_N_m", "primary_k", &c.primary_k},
      {"primary_damping_Ns_m", "primary_c", &c.primary_c},
      {"secondary_stiffness_N_m", "secondary_k", &c.secondary_k},
      {"secondary_damping_Ns_m", "secondary_c", &c.secondary_c},
      {"length_m", "length", &c.length}};
  for (const auto& kv : root.as_table()) {
    const std::string& k = kv.first;
    if (k == "name" || k == "kind" || k == "notes" || k == "source") continue;
    if (std::none_of(fields.begin(), fields.end(), [&](const auto& t) { return k == std::get<0>(t); }))
      throw InputError(where(k), "unknown vehicle key");
  }
  if (!root.contains("kind") || !root.at("kind").is_string() || root.at("kind").as_string().str != "coach")
    throw InputError(where("kind"), "must be \"coach\" (a body on two bogies of two wheelsets)");
  c.name = root.contains("name") && root.at("name").is_string() ? root.at("name").as_string().str : fs::path(path).stem().string();
  for (const auto& [key, field, dst] : fields) {
    if (!root.contains(key)) throw InputError(where(key), "required");
    const auto& v = root.at(key);
    if (v.is_integer()) *dst = static_cast<double>(v.as_integer());
    else if (v.is_floating()) *dst = v.as_floating();
    else throw InputError(where(key), "must be a number");
  }
  try {
    c.validate();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    const auto at = msg.find("': ");
    const std::string rest = at == std::string::npos ? msg : msg.substr(at + 3);
    for (const auto& [key, field, dst] : fields)
      if (rest.rfind(std::string(field) + " = ", 0) == 0) throw InputError(where(key), rest.substr(std::string(field).size() + 3));
    throw InputError(path + ": " + msg);
  }
  return c;
}

std::string coach_file_of(const std::string& train_path) {
  if (fs::path(train_path).extension() == ".csv") return "";
  try {
    const detail::TomlFile parsed = parse_component(train_path, "train");
    const toml::value& root = parsed.root;
    if (!root.contains("kind") || !root.at("kind").is_string() || root.at("kind").as_string().str != "coaches") return "";
    if (!root.contains("vehicle") || !root.at("vehicle").is_string()) return "";
    return (fs::path(train_path).parent_path() / root.at("vehicle").as_string().str).lexically_normal().string();
  } catch (const std::exception&) {
    return "";  // the train's own reading reports what is wrong with it
  }
}

load::Train read_train_file(const std::string& path) {
  if (fs::path(path).extension() == ".csv") return train_from_csv(path);
  const detail::TomlFile parsed = parse_component(path, "train");
  const toml::value& root = parsed.root;
  // The keys of each kind (name, kind and notes belong to all): a key of another kind is an error,
  // not silently ignored.
  static const std::map<std::string, std::set<std::string>> keys_of = {
      {"hslm", {"hslm_number", "n_coaches", "coach_length", "bogie_spacing", "axle_load_kN"}},
      {"regular", {"n_axles", "spacing", "axle_load_kN"}},
      {"axles", {"csv"}},
      {"coaches", {"vehicle", "n_coaches", "articulated"}}};
  auto where = [&](const std::string& key) {
    return SourceLocation{path, root.contains(key) ? parsed.line_of(root.at(key)) : 0, key};
  };
  const std::string kind_name = root.contains("kind") && root.at("kind").is_string() ? root.at("kind").as_string().str : "";
  for (const auto& kv : root.as_table()) {
    const std::string& k = kv.first;
    if (k == "name" || k == "kind" || k == "notes") continue;
    std::string owner;
    for (const auto& [kind, keys] : keys_of)
      if (keys.count(k)) owner += (owner.empty() ? "" : " or ") + kind;
    if (owner.empty()) throw InputError(where(k), "unknown train key");
    if (keys_of.count(kind_name) && !keys_of.at(kind_name).count(k))
      throw InputError(where(k), "belongs to " + owner + " trains, not to kind = \"" + kind_name + "\"");
  }
  auto number = [&](const std::string& key) -> double {
    if (!root.contains(key)) throw InputError(where(key), "required for this kind of train");
    const auto& v = root.at(key);
    if (v.is_integer()) return static_cast<double>(v.as_integer());
    if (v.is_floating()) return v.as_floating();
    throw InputError(where(key), "must be a number");
  };
  // A whole number in [lo, hi], checked before it becomes an int.
  auto whole = [&](const std::string& key, double lo, double hi) -> int {
    const double v = number(key);
    if (!(v == std::floor(v) && v >= lo && v <= hi))
      throw InputError(where(key), "must be a whole number from " + format_number(lo) + " to " + format_number(hi) + ", got " +
                                       format_number(v));
    return static_cast<int>(v);
  };
  auto string = [&](const std::string& key) -> std::string {
    if (!root.contains(key)) throw InputError(where(key), "required");
    if (!root.at(key).is_string()) throw InputError(where(key), "must be a string");
    return root.at(key).as_string().str;
  };
  const std::string name = root.contains("name") ? string("name") : fs::path(path).stem().string();
  const std::string kind = string("kind");
  try {
    if (kind == "hslm") {
      load::HslmRow row;
      if (root.contains("hslm_number")) {
        row = load::hslm_a_row(whole("hslm_number", 1, 10));
      } else {
        row.n_coaches = whole("n_coaches", 1, 1000);
        row.coach_length = number("coach_length");
        row.bogie_spacing = number("bogie_spacing");
        row.axle_load = number("axle_load_kN") * 1e3;
      }
      return load::hslm_a(name, row);
    }
    if (kind == "regular")
      return load::regular_train(name, whole("n_axles", 1, static_cast<double>(load::kMaxAxles)), number("spacing"),
                                 number("axle_load_kN") * 1e3);
    if (kind == "coaches") {
      const std::string vehicle = (fs::path(path).parent_path() / string("vehicle")).lexically_normal().string();
      load::CoachSpec coach;
      try {
        coach = read_coach_file(vehicle);
      } catch (const InputError& e) {
        throw InputError(where("vehicle"), e.what());
      }
      bool articulated = false;
      if (root.contains("articulated")) {
        if (!root.at("articulated").is_boolean()) throw InputError(where("articulated"), "must be true or false");
        articulated = root.at("articulated").as_boolean();
      }
      if (articulated)
        return load::articulated_train(name, coach, whole("n_coaches", 1, static_cast<double>(load::kMaxAxles / 2 - 1)));
      return load::coach_train(name, coach, whole("n_coaches", 1, static_cast<double>(load::kMaxAxles / 4)));
    }
    if (kind == "axles") {
      load::Train t = train_from_csv((fs::path(path).parent_path() / string("csv")).lexically_normal().string());
      t.name = name;
      return t;
    }
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.compare(0, path.size(), path) == 0) throw;
    throw InputError(path + ": " + msg);
  }
  throw InputError(where("kind"), "must be hslm, regular, axles or coaches, got '" + kind + "'");
}

}  // namespace viaduct::io
