// The dynamic check's plan from the [assess] keys, and its tables and report (assessment.hpp).
#include "viaduct/io/assessment.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <sstream>

#include "viaduct/core/thread_pool.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/guards.hpp"

namespace viaduct::io {

namespace {

std::string rfmt(double x, int sig = 4) { return study::shown_number(x, sig); }

double number_or(const FlatScenario& f, const std::string& key, double fallback) {
  return f.has(key) ? f.at(key).x : fallback;
}

// Where a key that is not set belongs: the line of another [assess] key given in the scenario, else
// the scenario itself.
SourceLocation assess_location(const FlatScenario& flat, const std::string& scenario, const std::string& key) {
  for (const auto& [k, v] : flat.values)
    if (key_is_under(k, "assess") && !flat.defaulted.count(k) && v.where.line > 0) return {v.where.file, v.where.line, key};
  return {scenario, 0, key};
}

study::AssessConfig read_assess_config(const FlatScenario& flat, const std::string& scenario) {
  study::AssessConfig c;
  for (const char* key : {"assess.line_speed_kmh", "assess.deck_type"})
    if (!flat.has(key))
      throw InputError(assess_location(flat, scenario, key),
                       "viaduct assess needs this key (the line's maximum speed and the deck type of EN 1991-2 Table 6.6)");
  c.line_speed = flat.at("assess.line_speed_kmh").x / 3.6;
  c.deck = study::deck_type_of(flat.at("assess.deck_type").s);
  c.edition = study::edition_of(flat.at("assess.edition").s);
  c.track = flat.at("assess.track").s;
  c.acc_limit = number_or(flat, "assess.acceleration_limit_mps2", c.track == "direct" ? 5.0 : 3.5);
  c.speed_factor = flat.at("assess.speed_factor").x;
  c.v_max = c.speed_factor * c.line_speed;
  c.v_min = number_or(flat, "assess.speed_min_kmh", std::min(100.0, 0.5 * c.line_speed * 3.6)) / 3.6;
  if (c.v_min > c.v_max)
    throw InputError(flat.at("assess.speed_min_kmh").where, "the lowest speed is above assess.speed_factor = " +
                                                                format_number(c.speed_factor, 6) + " times the line speed (" +
                                                                format_number(c.v_max * 3.6, 6) + " km/h)");
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
  if (flat.has("assess.ballast_width_m")) c.ballast_width = flat.at("assess.ballast_width_m").x;
  c.ballast_depth = flat.at("assess.ballast_depth_m").x;
  c.density_nominal = flat.at("assess.ballast_density_kgpm3").x;
  c.density_min = flat.at("assess.ballast_density_min_kgpm3").x;
  c.density_saturated = flat.at("assess.ballast_density_saturated_kgpm3").x;
  c.depth_increase = flat.at("assess.ballast_depth_increase").x;
  if (c.density_min > c.density_saturated)
    throw InputError(flat.at("assess.ballast_density_min_kgpm3").where, "the minimum density is above the saturated one");
  c.alpha = flat.at("assess.lm71_alpha").x;
  c.careful = flat.at("assess.track_maintenance").s == "careful";
  c.deflection_ratio = flat.at("assess.deflection_limit_ratio").x;
  c.rotation_limit = flat.at("assess.end_rotation_limit_rad").x;
  if (flat.has("assess.determinant_length_m")) c.determinant_length = flat.at("assess.determinant_length_m").x;
  c.comfort_level = flat.at("assess.comfort_level").s;
  c.comfort_limit = number_or(flat, "assess.comfort_limit_mps2", study::comfort_limit_of(c.comfort_level));
  c.unloading_limit = flat.at("assess.unloading_ratio_limit").x;
  if (flat.has("assess.comfort_deflection_ratio")) c.comfort_deflection_ratio = flat.at("assess.comfort_deflection_ratio").x;
  return c;
}

void set_string(FlatScenario& flat, const std::string& key, const std::string& value) {
  Value v;
  v.type = ValueType::string;
  v.s = value;
  v.where = SourceLocation{"assess", 0, key};
  flat.values[key] = v;
  flat.defaulted.erase(key);
}

// Adds `delta` [kg/m] to every span's mass per metre; InputError when a span's mass would not be positive.
void add_mass(FlatScenario& flat, double delta) {
  Value v = flat.at("bridge.mass_per_m");
  if (v.type == ValueType::number_list) {
    for (double& m : v.xs) m += delta;
  } else {
    v.x += delta;
  }
  const std::vector<double> ms = v.type == ValueType::number_list ? v.xs : std::vector<double>{v.x};
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
void plan_damping_and_cutoff(FlatScenario& flat, const study::AssessConfig& c, study::AssessPlan& p) {
  const study::Scenario nominal = to_scenario(flat);
  double longest = 0.0;
  for (const auto& s : nominal.bridge.spans) longest = std::max(longest, s.length);
  p.span_for_damping = longest;
  p.zeta_table = study::damping_lower_bound(c.deck, longest);
  p.zeta_extra = c.interaction_damping ? study::additional_damping(longest) : 0.0;
  p.zeta_given = c.damping_ratio.has_value();
  p.zeta = p.zeta_given ? *c.damping_ratio : p.zeta_table + p.zeta_extra;
  set_string(flat, "bridge.damping.kind", "modal");
  set_number(flat, "bridge.damping.ratio", p.zeta);
  p.deck_modes = deck_modes_of(nominal);
  if (p.deck_modes.empty()) throw SolverError("assess: the model has no deck bending mode");
  p.f1 = p.deck_modes.front().frequency_hz;
  // f3 of the member (A2.4.4.2.1(4)): each span of a chain on its own, a continuous deck whole;
  // the cut-off the largest of the members' (one filter for every station: the conservative one).
  p.members = study::member_frequencies(nominal.bridge, nominal.track);
  const study::MemberFrequencies* gov = &p.members.front();
  for (const auto& m : p.members) {
    if (m.cutoff > gov->cutoff) gov = &m;
    if (m.f3_order != 3)
      p.notes.push_back((m.span ? "span " + std::to_string(m.span) : std::string("the deck")) +
                        (m.f3_order == 0 ? ": fewer than three bending modes found, f3 not used in its cut-off"
                                         : ": no third bending mode told apart; its third deck mode (order " +
                                               std::to_string(m.f3_order) + ") taken as f3"));
  }
  p.f3 = gov->f3;
  p.f3_span = gov->span;
  p.f_cut = std::max(study::cutoff_frequency(p.f1, 0.0), gov->cutoff);
  // A step fixed by the scenario (no preset, or analysis.dt given) cannot resolve a cut-off beyond
  // its Nyquist frequency: say why, a unit slip first. (A preset takes its step from the cut-off.)
  const double dt = nominal.settings.dt;
  const bool step_fixed = flat.at("analysis.preset").s.empty() || (flat.has("analysis.dt") && !flat.defaulted.count("analysis.dt"));
  if (step_fixed && dt > 0.0 && p.f_cut >= 0.5 / dt) {
    std::string msg = "the cut-off max(30 Hz, 1.5 f1, f3) = " + format_number(p.f_cut, 4) + " Hz (f1 " + format_number(p.f1, 4) +
                      " Hz, f3 " + format_number(p.f3, 4) + " Hz) is beyond the Nyquist frequency " + format_number(0.5 / dt, 4) +
                      " Hz of the time step: take a smaller analysis.dt";
    for (const auto& w : study::scenario_warnings(nominal, {}))
      if (w.find("check the unit") != std::string::npos) msg += "; but first: " + w;
    throw InputError(flat.has("analysis.dt") ? flat.at("analysis.dt").where : assess_location(flat, flat.path, "analysis.dt"), msg);
  }
  set_string(flat, "filter.band", "lowpass");
  flat.values["filter.enabled"].b = true;
  set_number(flat, "filter.high_hz", p.f_cut);
}

// HSLM-A1…A10, HSLM-B for spans under 7 m (N and d from the keys), then the scenario's other trains.
std::vector<load::Train> assessment_trains(const FlatScenario& flat, const study::Scenario& sc, study::AssessPlan& p) {
  const study::Edition ed = p.config.edition;
  std::vector<load::Train> out;
  for (int i = 1; i <= 10; ++i) out.push_back(load::hslm_a("HSLM-A" + std::to_string(i), load::hslm_a_row(i)));
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& s : sc.bridge.spans) shortest = std::min(shortest, s.length);
  if (sc.bridge.continuous && shortest < 7.0)
    p.notes.push_back("HSLM-B not run: " + study::cite(ed, study::Clause::hslm_b) + " asks for it on simply supported spans under 7 m; this deck is continuous "
                      "(HSLM-A1…A10 cover it)");
  if (!sc.bridge.continuous && shortest < 7.0) {
    if (!flat.has("assess.hslm_b_n") || !flat.has("assess.hslm_b_spacing_m"))
      throw InputError(assess_location(flat, flat.path, "assess.hslm_b_n"),
                       "a span of " + format_number(shortest, 4) +
                           " m is under 7 m: " + study::cite(ed, study::Clause::hslm_b) + " asks for HSLM-B; give assess.hslm_b_n and "
                           "assess.hslm_b_spacing_m read from the figure for this span (viaduct does not carry it)");
    const int n = static_cast<int>(flat.at("assess.hslm_b_n").x);
    out.push_back(load::regular_train("HSLM-B", n, flat.at("assess.hslm_b_spacing_m").x, 170e3));
    p.notes.push_back("HSLM-B: " + std::to_string(n) + " forces of 170 kN every " +
                      format_number(flat.at("assess.hslm_b_spacing_m").x, 4) + " m (from the scenario, " + study::cite_brief(ed, study::Clause::hslm_b) + ")");
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

// The mass cases and what each adds to bridge.mass_per_m [kg/m] (6.4.6.3.2). With the bed's width:
// the minimum density for the lower bound, the saturated density with the depth increased for the
// upper, against the ballast bridge.mass_per_m includes (assess.ballast_mass_per_m, else the
// nominal density's). Without: the included ballast (the key, else the track model's vibrating
// ballast, which is far below a real bed's) times the factors, said in a note.
std::vector<std::pair<std::string, double>> ballast_bounds(const study::AssessConfig& c, const study::Scenario& nominal,
                                                           study::AssessPlan& p) {
  if (c.ballast_width) {
    const double w = *c.ballast_width, d = c.ballast_depth;
    p.ballast_nominal = c.ballast >= 0.0 ? c.ballast : c.density_nominal * d * w;
    p.ballast_lower = c.density_min * d * w;
    p.ballast_upper = c.density_saturated * (1.0 + c.depth_increase) * d * w;
    p.ballast_basis = "bed " + format_number(w, 4) + " m wide, " + format_number(d, 4) + " m deep: lower " +
                      format_number(c.density_min, 5) + " kg/m³ (minimum density), upper " + format_number(c.density_saturated, 5) +
                      " kg/m³ (saturated) with the depth +" + format_number(100 * c.depth_increase, 3) +
                      " %; included in bridge.mass_per_m " + format_number(p.ballast_nominal, 6) + " kg/m (" +
                      (c.ballast >= 0.0 ? std::string("assess.ballast_mass_per_m") : format_number(c.density_nominal, 5) + " kg/m³") + ")";
    return {{"mass lower", p.ballast_lower - p.ballast_nominal}, {"mass upper", p.ballast_upper - p.ballast_nominal}};
  }
  double ballast = c.ballast;
  if (ballast < 0.0) {  // not given: the modelled track's ballast, or none
    ballast = nominal.track ? nominal.track->ballast_mass / nominal.track->sleeper_spacing : 0.0;
    p.notes.push_back(nominal.track ? "ballast mass per metre taken from the track model's vibrating ballast: " + format_number(ballast, 6) +
                                          " kg/m, far below a real bed's (the bounds then move the mass by " +
                                          format_number(100 * (c.ballast_upper - c.ballast_lower) * ballast / nominal.bridge.spans.front().mass_per_m, 2) +
                                          " %); give assess.ballast_width_m (and the bed's depth and densities) for " +
                                          study::cite(c.edition, study::Clause::mass) + "'s bounds"
                                    : "no ballast mass given (assess.ballast_mass_per_m or assess.ballast_width_m): one mass case, not bounded");
  }
  if (!(ballast > 0.0) || c.ballast_lower == c.ballast_upper) return {{"nominal", 0.0}};
  p.ballast_nominal = ballast, p.ballast_lower = c.ballast_lower * ballast, p.ballast_upper = c.ballast_upper * ballast;
  p.ballast_basis = "the included ballast " + format_number(ballast, 6) + " kg/m × " + format_number(c.ballast_lower, 4) + " and × " +
                    format_number(c.ballast_upper, 4) + " (assess.ballast_lower_factor, assess.ballast_upper_factor)";
  return {{"mass lower", (c.ballast_lower - 1.0) * ballast}, {"mass upper", (c.ballast_upper - 1.0) * ballast}};
}

// Every span that no deck station of `sc` lies on gets three: at a quarter, the middle and three
// quarters of it (span<k>_L4, span<k>_mid, span<k>_3L4; the quarter points for the second bending
// mode, whose node is the middle). The deck's accelerations and deflections are checked on every
// span (EN 1990 A2.4.4.2.1, A2.4.4.3), not only on those the scenario names. Returns the names.
std::vector<std::string> add_span_stations(study::Scenario& sc) {
  std::vector<bool> covered(sc.bridge.spans.size(), false);
  for (const auto& st : sc.stations)
    if (st.on_deck && st.span < covered.size()) covered[st.span] = true;
  auto taken = [&](const std::string& name) {
    return std::any_of(sc.stations.begin(), sc.stations.end(), [&](const study::StationSpec& s) { return s.name == name; });
  };
  std::vector<std::string> added;
  for (std::size_t k = 0; k < covered.size(); ++k) {
    if (covered[k]) continue;
    for (const auto& [suffix, at] : {std::pair<const char*, double>{"L4", 0.25}, {"mid", 0.5}, {"3L4", 0.75}}) {
      study::StationSpec st;
      st.name = "span" + std::to_string(k + 1) + "_" + suffix;
      while (taken(st.name)) st.name += "_";
      st.span = k;
      st.x_local = at * sc.bridge.spans[k].length;
      sc.stations.push_back(st);
      added.push_back(st.name);
    }
  }
  return added;
}

// The mass variants (lower and upper bound, or one nominal case), each with every train and its speeds.
void plan_variants(FlatScenario& flat, const study::AssessConfig& c, study::AssessPlan& p, int threads) {
  const study::Scenario nominal = to_scenario(flat);
  const std::vector<load::Train> trains = assessment_trains(flat, nominal, p);
  // Each mass case's change of bridge.mass_per_m [kg/m].
  const std::vector<std::pair<std::string, double>> bounds = ballast_bounds(c, nominal, p);
  const double m0 = nominal.bridge.spans.front().mass_per_m;
  // Each train's distance on its own thread (0.3 s of sincos for Old Guadiana's eleven trains);
  // a failure (parallel_for's bodies must not throw) rethrown after, the first in the trains' order.
  p.train_distance.assign(trains.size(), 0.0);
  std::vector<std::exception_ptr> failed(trains.size());
  parallel_for(trains.size(), std::max(1, std::min(threads, static_cast<int>(trains.size()))), [&](std::size_t t, int) {
    try {
      p.train_distance[t] = load::characteristic_distance(trains[t]);
    } catch (...) {
      failed[t] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  for (const auto& [label, delta] : bounds) {
    FlatScenario f = flat;
    if (delta != 0.0) add_mass(f, delta);
    study::Variant v;
    v.label = label;
    v.scenario = to_scenario(f);
    v.scenario.trains = trains;
    const std::vector<std::string> added = add_span_stations(v.scenario);
    if (!added.empty() && p.variants.empty()) {
      std::string names;
      for (const auto& n : added) names += (names.empty() ? "" : ", ") + n;
      p.notes.push_back("stations added by the assessment where no deck station lies on a span (every span's deck is checked): " + names +
                        "; give [[stations]] to choose the points");
    }
    v.factors = {{"mass", v.scenario.bridge.spans.front().mass_per_m / m0}};
    v.train_speeds = study::assessment_train_speeds(p.train_distance, v.scenario, c, p.f_cut);
    v.scenario.sweep_speeds = v.train_speeds.front();
    p.variants.push_back(std::move(v));
  }
  // The nominal model at every speed any train runs: what check, run and sweep would warn of.
  std::vector<double> speeds;
  for (const auto& s : p.variants.front().train_speeds) speeds.insert(speeds.end(), s.begin(), s.end());
  study::Scenario sc = nominal;
  sc.trains = trains;
  p.warnings = study::scenario_warnings(sc, speeds);
  if (p.zeta_given)  // the damping is the assessment's key, which replaced the bridge's
    for (std::string& w : p.warnings)
      if (w.rfind("bridge.damping.ratio = ", 0) == 0) w.replace(0, 20, "assess.damping_ratio");
  if (c.edition != study::Edition::en2003)  // the warnings name the 2003 figure: cite the edition's
    for (std::string& w : p.warnings)
      for (const auto& [was, clause] : {std::pair<std::string, study::Clause>{"EN 1991-2 Fig. 6.10", study::Clause::frequency_limits},
                                         {"Fig. 6.9)", study::Clause::flow_chart}})
        if (const std::size_t at = w.find(was); at != std::string::npos)
          w.replace(at, was.size(), study::cite(c.edition, clause) + (was.back() == ')' ? ")" : ""));
}

void write_checks_csv(const std::string& path, const std::vector<study::AssessCheck>& checks) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& k : checks)
    rows.push_back({k.check, k.quantity, table_cell(k.value), table_cell(k.limit), study::quantity_unit(k.quantity),
                    table_cell(k.utilisation(), 6), k.verdict, k.variant, k.train, table_cell(k.speed * 3.6, 6), k.clause});
  write_table_csv(path, {"check", "quantity", "value", "limit", "unit", "utilisation", "result", "variant", "train", "speed_kmh", "clause"},
                      rows);
}

void write_increments_csv(const std::string& path, const std::vector<study::AssessIncrement>& inc) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& i : inc)
    rows.push_back({i.variant, i.train, i.quantity, table_cell(i.dynamic), table_cell(i.quasi_static),
                    table_cell(i.phi(), 6), table_cell(i.speed * 3.6, 6)});
  write_table_csv(path, {"variant", "train", "quantity", "max_abs_dynamic", "max_abs_quasi_static", "phi_dyn", "speed_kmh"}, rows);
}


// mass_cases.csv: what each mass case sets, so that any of its cases can be run again alone
// (viaduct run --set bridge.mass_per_m=... --set bridge.damping.ratio=... --set filter.high_hz=...).
void write_mass_cases_csv(const std::string& path, const study::AssessPlan& p) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& v : p.variants)
    for (std::size_t k = 0; k < v.scenario.bridge.spans.size(); ++k)
      rows.push_back({v.label, std::to_string(k + 1), table_cell(v.scenario.bridge.spans[k].mass_per_m),
                      table_cell(p.zeta), table_cell(p.f_cut)});
  write_table_csv(path, {"variant", "span", "mass_per_m_kgpm", "damping_ratio", "cutoff_hz"}, rows);
}

struct ReportInput {
  const study::AssessConfig& c;
  const study::AssessPlan& p;
  const study::SweepResult& r;
  const std::vector<study::AssessCheck>& checks;
  const std::vector<study::AssessIncrement>& inc;
  const FlatScenario& flat;
  const study::Scenario& nominal;
  std::string command_line;
  bool figures = false;
  const study::LayoutSensitivity* layout = nullptr;
};

// How a verdict ranks in the summary: what fails first, what is not checked last.
int verdict_rank(const std::string& v) {
  if (v == "FAIL" || v == "UPLIFT") return 0;
  if (v == "dynamic governs") return 1;
  if (v.rfind("limit to give", 0) == 0) return 2;
  if (v.rfind("not checked", 0) == 0) return 4;
  return 3;
}

// A force, moment, shear or reaction of a half-deck model carries one rail line's share.
bool per_rail_line(const std::string& quantity, double load_factor) {
  if (load_factor == 1.0) return false;
  for (const char* s : {"_moment_Nm", "_shear_N", "_reaction_N"}) {
    const std::string suffix(s);
    if (quantity.size() >= suffix.size() && quantity.compare(quantity.size() - suffix.size(), suffix.size(), suffix) == 0)
      return true;
  }
  return false;
}

// One line per check type, the failing ones first (the table follows in the same order).
void report_verdict_lines(std::ostringstream& o, const std::vector<const study::AssessCheck*>& sorted) {
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i, fails = 0;
    const study::AssessCheck* worst = sorted[i];
    for (; j < sorted.size() && sorted[j]->check == sorted[i]->check; ++j) {
      fails += verdict_rank(sorted[j]->verdict) == 0;
      const double u = sorted[j]->utilisation(), w = worst->utilisation();
      if (verdict_rank(sorted[j]->verdict) < verdict_rank(worst->verdict) || (std::isfinite(u) && (!std::isfinite(w) || u > w)))
        worst = sorted[j];
    }
    const std::size_t n = j - i;
    o << "- **" << sorted[i]->verdict << "**: " << sorted[i]->check;
    if (verdict_rank(worst->verdict) == 4) {
      o << " (" << worst->clause << ")\n";
    } else {
      o << ": " << (fails ? std::to_string(fails) + " of " + std::to_string(n) + " fail" : std::to_string(n) + " row" + (n > 1 ? "s" : ""))
        << "; the " << (fails ? "worst " : "largest ") << worst->quantity << " = " << study::shown_value(worst->quantity, worst->value);
      if (std::isfinite(worst->limit))
        o << " against " << study::shown_value(worst->quantity, worst->limit) << " (utilisation " << rfmt(worst->utilisation(), 3) << ")";
      if (!worst->train.empty()) o << ", " << worst->train;
      if (std::isfinite(worst->speed)) o << " at " << rfmt(worst->speed * 3.6) << " km/h";
      if (!worst->variant.empty()) o << ", " << worst->variant;
      o << ".\n";
    }
    i = j;
  }
}

void report_summary(std::ostringstream& o, const ReportInput& in) {
  std::size_t fails = 0, dyn = 0;
  for (const auto& k : in.checks) fails += k.verdict == "FAIL" || k.verdict == "UPLIFT", dyn += k.verdict == "dynamic governs";
  std::size_t open = 0;  // rows without a verdict: not checked, or their limit to be given
  for (const auto& k : in.checks) open += verdict_rank(k.verdict) == 2 || verdict_rank(k.verdict) == 4;
  o << "## Summary\n\n";
  // The static rows (LM71, the 2D model's unchecked ones) do not make an assessment: the dynamic cases do.
  const bool none_ran = in.r.rows.empty();
  if (none_ran) o << "**No check could be made: every case failed to run (failures.csv).**";
  else o << (fails ? "**" + std::to_string(fails) + " check(s) fail.**" : std::string("**Every limit check made passes.**"));
  if (!in.r.failures.empty() && !none_ran)
    o << " **" << in.r.failures.size() << " case(s) failed to run (failures.csv): the checks leave them out.**";
  if (open) o << " " << open << " row(s) are not checked or wait for their limit (below).";
  if (dyn) o << " In " << dyn << " quantit" << (dyn > 1 ? "ies" : "y") << " the dynamic effect of the trains exceeds Φ × LM71: design with it (" << study::cite_brief(in.c.edition, study::Clause::design_effect) << ").";
  o << "\n\n";
  if (!in.p.warnings.empty()) {
    o << "**Warnings: read them before the numbers** (a unit slip or a model outside its validity gives a report that looks "
         "like any other):\n\n";
    for (const auto& w : in.p.warnings) o << "- **warning**: " << w << "\n";
    o << "\n";
  }
  // Check types in the order of their worst verdict, rows within a type as formed.
  std::vector<std::string> types;
  std::map<std::string, int> rank;
  for (const auto& k : in.checks) {
    if (!rank.count(k.check)) types.push_back(k.check), rank[k.check] = 9;
    rank[k.check] = std::min(rank[k.check], verdict_rank(k.verdict));
  }
  std::stable_sort(types.begin(), types.end(), [&](const std::string& a, const std::string& b) { return rank[a] < rank[b]; });
  std::vector<const study::AssessCheck*> sorted;
  for (const auto& t : types)
    for (const auto& k : in.checks)
      if (k.check == t) sorted.push_back(&k);
  report_verdict_lines(o, sorted);
  const double lf = in.nominal.settings.load_factor;
  o << "\n| check | quantity | value | limit | utilisation | result | governing train | speed [km/h] | mass | clause |\n"
       "|---|---|---:|---:|---:|---|---|---:|---|---|\n";
  for (const study::AssessCheck* k : sorted) {
    const std::string mark = per_rail_line(k->quantity, lf) ? " †" : "";
    o << "| " << k->check << " | " << k->quantity << " | " << study::shown_value(k->quantity, k->value) << mark << " | "
      << study::shown_value(k->quantity, k->limit) << mark << " | " << rfmt(k->utilisation(), 3) << " | " << k->verdict << " | "
      << (k->train.empty() ? "—" : k->train) << " | " << rfmt(k->speed * 3.6, 4) << " | " << (k->variant.empty() ? "—" : k->variant)
      << " | " << k->clause << " |\n";
  }
  if (lf != 1.0)
    o << "\n† per rail line / half deck: the model carries one rail line with each axle load × " << rfmt(lf)
      << " (train.load_factor); a whole deck under both rails carries " << rfmt(1.0 / lf) << " × these forces and moments. "
      << "Deflections, rotations and accelerations are the deck's.\n";
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
  const study::AssessConfig& c = in.c;
  const study::AssessPlan& p = in.p;
  std::size_t n_cases = in.r.summary.n_cases;
  o << "\n## Inputs of the check\n\n";
  const study::Edition ed = c.edition;
  o << "- **Trains** (" << study::cite(ed, study::Clause::trains) << "): HSLM-A1…A10";
  for (const auto& t : p.real_trains) o << ", " << t;
  o << ". Axle loads × " << rfmt(in.nominal.settings.load_factor) << " (train.load_factor).\n";
  o << "- **Speeds** (" << study::cite_brief(ed, study::Clause::speeds) << "): " << rfmt(c.v_min * 3.6) << " to " << rfmt(c.v_max * 3.6) << " km/h (" << rfmt(c.speed_factor) << " × the line speed "
    << rfmt(c.line_speed * 3.6) << " km/h) every " << rfmt(c.step * 3.6) << " km/h, refined to " << rfmt(c.fine_step * 3.6)
    << " km/h within ±" << rfmt(100 * c.band) << " % of each resonance speed f·d/j (j ≤ " << c.harmonics
    << ", f each deck bending frequency below the cut-off, d the train's characteristic distance): " << n_cases << " cases.\n";
  if (p.zeta_given)
    o << "- **Damping**: ζ = " << rfmt(100 * p.zeta) << " % (assess.damping_ratio, instead of " << study::cite_brief(ed, study::Clause::damping) << ").\n";
  else
    o << "- **Damping** (" << study::cite_brief(ed, study::Clause::damping) << ", " << study::deck_type_name(c.deck) << ", L = " << rfmt(p.span_for_damping) << " m, the longest span): "
      << rfmt(100 * p.zeta_table) << " %" << (p.zeta_extra > 0 ? " + Δζ = " + rfmt(100 * p.zeta_extra) + " % (" + study::cite_brief(ed, study::Clause::interaction_damping) + ": interaction not modelled)" : "")
      << " = **" << rfmt(100 * p.zeta) << " %** in every deck mode.\n";
  o << "- **Mass** (" << study::cite_brief(ed, study::Clause::mass) << "):";
  for (const auto& v : p.variants) o << " " << v.label << " " << rfmt(v.scenario.bridge.spans.front().mass_per_m, 6) << " kg/m;";
  if (p.ballast_upper > 0.0)
    o << " ballast " << rfmt(p.ballast_lower, 5) << " kg/m (lower) and " << rfmt(p.ballast_upper, 5) << " kg/m (upper), "
      << p.ballast_basis << ";";
  o << " the lower bound governs accelerations, the upper bound the lowest resonance speeds.\n";
  o << "- **Frequencies** (" << study::cite(ed, study::Clause::cut_off) << "): f1 = " << rfmt(p.f1) << " Hz (the structure); f3 = " << rfmt(p.f3)
    << " Hz, the third bending mode of the member (" << (p.f3_span ? "span " + std::to_string(p.f3_span) + " modelled alone on its bearings with its track" : std::string("the continuous deck"))
    << "): cut-off max(30, 1.5 f1, f3) = **" << rfmt(p.f_cut) << " Hz**, applied as a Chebyshev I low-pass to accelerations.";
  if (p.members.size() > 1) {
    o << " Members:";
    for (const auto& m : p.members) o << " span " << m.span << " f1 " << rfmt(m.f1) << " Hz, f3 " << rfmt(m.f3) << " Hz;";
    o << " the highest cut-off filters every station.";
  }
  o << "\n";
  o << "- **Limits**: deck acceleration " << rfmt(c.acc_limit) << " m/s² (" << c.track << " track); deflection span/"
    << rfmt(c.deflection_ratio) << "; end rotation " << rfmt(c.rotation_limit * 1e3) << " mrad; LM71 α = " << rfmt(c.alpha) << ", "
    << (c.careful ? "Φ2 (careful maintenance)" : "Φ3 (standard maintenance)") << " with Lφ = "
    << (c.determinant_length ? rfmt(*c.determinant_length) + " m (assess.determinant_length_m)"
        : in.nominal.bridge.continuous ? rfmt(study::assessment_determinant_length("", in.nominal, c)) + " m (" + study::cite_brief(ed, study::Clause::determinant_length) + ", continuous over n spans: to confirm)"
                                       : "each quantity's span length (" + study::cite_brief(ed, study::Clause::determinant_length) + ")")
    << ".\n";
  if (in.nominal.settings.vehicle.model != study::VehicleModel::forces)
    o << "- **Vehicle limits**: car-body vertical acceleration b_v " << rfmt(c.comfort_limit) << " m/s² (comfort level "
      << c.comfort_level << ", " << study::cite(ed, study::Clause::comfort_acceleration) << ": to confirm; assess.comfort_limit_mps2 overrides); wheel unloading "
      << "(P0 − Pmin)/P0 below " << rfmt(c.unloading_limit)
      << (c.unloading_limit < 1.0 ? " (assess.unloading_ratio_limit)" : " (every wheel keeps contact with the rail)") << ".\n";
  o << "- **Model and method**: " << in.nominal.bridge.spans.size() << (in.nominal.bridge.continuous ? " span(s) of one continuous deck, " : " span(s), ")
    << (in.nominal.track ? "with" : "without")
    << " track; " << (in.nominal.settings.method == study::Method::modal ? "modal superposition" : "direct integration") << ", dt = "
    << rfmt(in.nominal.settings.dt * 1e3) << " ms; trains " << vehicle_line(in.nominal.settings) << ".\n";
}

// The model as run: spans, bearings, track, damping and the half-deck convention.
void report_model(std::ostringstream& o, const ReportInput& in) {
  const study::Scenario& sc = in.nominal;
  const model::BridgeParams& b = sc.bridge;
  o << "\n## Model\n\n" << (b.continuous ? "One continuous deck over " + std::to_string(b.spans.size()) + " spans"
                                           : std::to_string(b.spans.size()) + " simply supported span(s)")
    << ", Bernoulli–Euler beam elements of about " << rfmt(b.element_size) << " m.\n\n"
    << "| span | L [m] | EI [N·m²] | mass [kg/m] | mass includes the track |\n|---:|---:|---:|---:|---|\n";
  for (std::size_t k = 0; k < b.spans.size(); ++k)
    o << "| " << k + 1 << " | " << rfmt(b.spans[k].length) << " | " << rfmt(b.spans[k].EI) << " | " << rfmt(b.spans[k].mass_per_m, 6)
      << " | " << (sc.track ? (b.mass_includes_track ? "yes (the track's mass taken off the deck)" : "no (the track's added)") : "no track modelled")
      << " |\n";
  o << "\n- **Bearings**: "
    << (b.bearings.rigid ? std::string("rigid") : "k = " + rfmt(b.bearings.k) + " N/m, c = " + rfmt(b.bearings.c) + " N·s/m")
    << (b.bearings.rotational_k > 0 ? ", rotational spring " + rfmt(b.bearings.rotational_k) + " N·m/rad at the ends" : std::string())
    << (b.added_mass_per_m > 0 ? "; added mass " + rfmt(b.added_mass_per_m) + " kg/m" : std::string()) << ".\n";
  if (sc.track) {
    const model::TrackParams& t = *sc.track;
    o << "- **Track** (discrete, three layers): rail EI " << rfmt(t.rail_EI) << " N·m², " << rfmt(t.rail_mass_per_m) << " kg/m; sleepers every "
      << rfmt(t.sleeper_spacing) << " m, " << rfmt(t.sleeper_mass) << " kg per rail seat; ballast " << rfmt(t.ballast_mass)
      << " kg per rail seat; pad k " << rfmt(t.pad.k) << " N/m, c " << rfmt(t.pad.c) << " N·s/m; ballast k " << rfmt(t.ballast.k)
      << " N/m, c " << rfmt(t.ballast.c) << " N·s/m; on the deck k " << rfmt(t.subgrade_on_bridge.k) << " N/m, c "
      << rfmt(t.subgrade_on_bridge.c) << " N·s/m; " << rfmt(t.mass_per_m(), 5) << " kg/m in all.\n";
  } else {
    o << "- **Track**: not modelled (the axle loads act on the deck).\n";
  }
  o << "- **Damping**: ζ = " << rfmt(100 * in.p.zeta) << " % in every deck mode ("
    << (in.p.zeta_given ? std::string("assess.damping_ratio")
                        : study::cite(in.c.edition, study::Clause::damping) +
                              (in.p.zeta_extra > 0 ? " + " + study::cite_brief(in.c.edition, study::Clause::interaction_damping) : std::string()))
    << ")" << (sc.track ? "; the track's dashpots besides" : "") << ".\n";
  const double lf = sc.settings.load_factor;
  o << "- **Convention**: "
    << (lf == 1.0 ? std::string("the model carries whole axle loads (train.load_factor = 1): forces and moments are the deck's.")
                  : "the model is " + std::string(lf == 0.5 ? "half a deck under one rail line" : "a share of the deck") +
                        " (train.load_factor = " + rfmt(lf) + "): every force, moment, shear and reaction is per rail line / half deck (†).")
    << "\n";
}

// The deck modes of the nominal model, and the resonance speeds v = f·d/j of each train.
void report_modes(std::ostringstream& o, const ReportInput& in) {
  o << "\n## Deck modes and resonance speeds\n\n| mode | f [Hz] | kind | span | bending order | deck mass share | below the cut-off |\n"
       "|---:|---:|---|---:|---:|---:|---|\n";
  for (std::size_t m = 0; m < in.p.deck_modes.size(); ++m) {
    const model::DeckMode& d = in.p.deck_modes[m];
    o << "| " << m + 1 << " | " << rfmt(d.frequency_hz) << " | " << model::mode_kind(d.deck_share) << " | " << d.bending.span << " | "
      << d.bending.order << " | " << rfmt(d.deck_share, 3) << " | " << (d.frequency_hz <= in.p.f_cut ? "yes" : "no") << " |\n";
  }
  const std::vector<study::ResonanceSpeed> rs = study::resonance_speeds(in.p);
  o << "\nResonance speeds v = f·d/j (" << study::cite_brief(in.c.edition, study::Clause::speeds) << ") within " << rfmt(in.c.v_min * 3.6) << "–" << rfmt(in.c.v_max * 3.6)
    << " km/h, d the train's characteristic distance, j ≤ " << in.c.harmonics << " (mode: j):\n\n| train | d [m] | speeds [km/h] |\n|---|---:|---|\n";
  for (std::size_t i = 0; i < rs.size();) {
    std::size_t j = i;
    o << "| " << rs[i].train << " | " << rfmt(rs[i].distance) << " | ";
    for (; j < rs.size() && rs[j].train == rs[i].train; ++j)
      o << (j > i ? ", " : "") << rfmt(rs[j].speed * 3.6) << " (" << rs[j].mode << ": " << rs[j].harmonic << ")";
    o << " |\n";
    i = j;
  }
  if (rs.empty()) o << "| — | — | none in the range |\n";
}

// EN 1991-2 Fig. 6.9 answered for the bridge, with Fig. 6.10's limits per member.
void report_flow(std::ostringstream& o, const ReportInput& in) {
  const study::DynamicAnalysisNeed d = study::dynamic_analysis_need(in.p, in.nominal);
  const study::Edition ed = in.c.edition;
  o << "\n## Is a dynamic analysis required? (" << study::cite(ed, study::Clause::flow_chart) << "; to confirm against the text)\n\n";
  for (const auto& s : d.steps) o << "1. " << s.question << " — " << s.answer << "\n";
  o << "\n**" << d.conclusion << ".**\n\nThe limits of the first natural frequency n0 (" << study::cite(ed, study::Clause::frequency_limits) << "):\n\n"
       "| member | L [m] | n0 [Hz] | lower [Hz] | upper [Hz] | within |\n|---|---:|---:|---:|---:|---|\n";
  for (const auto& m : d.members)
    o << "| " << (m.span ? "span " + std::to_string(m.span) : std::string("deck (L = Lφ, to confirm)")) << " | " << rfmt(m.length) << " | " << rfmt(m.f1)
      << " | " << rfmt(m.lower) << " | " << rfmt(m.upper) << " | "
      << (m.length < 4.0 || m.length > 100.0 ? "outside the figure's 4–100 m" : m.within() ? "yes" : "no") << " |\n";
}

void report_details(std::ostringstream& o, const ReportInput& in) {
  o << "\n## Deck acceleration per train (" << study::cite_brief(in.c.edition, study::Clause::deck_acceleration) << ")\n\n| train | max acc. [m/s²] | station | speed [km/h] | mass |\n|---|---:|---|---:|---|\n";
  std::map<std::string, const study::EnvelopeRow*> worst;
  std::vector<std::string> order;
  for (const auto& row : in.r.rows) {
    auto& w = worst[row.train];
    if (!w) order.push_back(row.train);
    if (!w || row.max_abs_acc > w->max_abs_acc) w = &row;
  }
  for (const auto& t : order)
    o << "| " << t << " | " << rfmt(worst[t]->max_abs_acc) << " | " << worst[t]->station << " | " << rfmt(worst[t]->speed * 3.6)
      << " | " << worst[t]->variant << " |\n";
  if (in.figures) o << "\n![Envelope over trains and masses, the governing train at each peak](envelope.png)\n";
  o << "\n## Dynamic increments φ′dyn (" << study::cite_brief(in.c.edition, study::Clause::increments) << ")\n\nThe largest over trains, speeds and masses, per quantity "
       "(every train in phi_dyn.csv):\n\n| quantity | φ′dyn | train | speed [km/h] | mass | max dynamic | max quasi-static |\n|---|---:|---|---:|---|---:|---:|\n";
  std::map<std::string, const study::AssessIncrement*> top;
  std::vector<std::string> qs;
  for (const auto& i : in.inc) {
    auto& t = top[i.quantity];
    if (!t) qs.push_back(i.quantity);
    if (!t || i.phi() > t->phi()) t = &i;
  }
  for (const auto& q : qs)
    o << "| " << q << " | " << rfmt(top[q]->phi(), 3) << " | " << top[q]->train << " | " << rfmt(top[q]->speed * 3.6) << " | "
      << top[q]->variant << " | " << study::shown_value(q, top[q]->dynamic) << " | " << study::shown_value(q, top[q]->quasi_static) << " |\n";
  if (in.figures) o << "\n![φ′dyn per quantity](phi_dyn.png)\n";
  if (in.figures && !in.nominal.effect_stations.empty())
    o << "\n![Moment and shear along the span: envelopes per train, the dynamic design effect and Φ × LM71 × α "
         "(stations[].every_m)](load_effects_along.png)\n";
}

// Edition 2023: the values the check takes are the 2003 edition's; each one the 2023 text may
// revise is a key, listed with the value taken and where the 2023 text has it.
void report_edition_values(std::ostringstream& o, const ReportInput& in) {
  const study::AssessConfig& c = in.c;
  if (c.edition != study::Edition::en2023) return;
  using study::Clause;
  const auto cite = [](Clause k) { return study::cite(study::Edition::en2023, k); };
  o << "\n## Values under EN 1991-2:2023\n\nThe clauses above are the 2023 edition's where viaduct knows them (HSLM-A: Fig. 8.12 "
       "and Table 8.4; the determinant length: Table 8.2); the others name the 2003 clause, to confirm against the 2023 text. "
       "The values are the 2003 edition's: where the 2023 text revises one, give its value in the key.\n\n"
       "| value | taken | key | 2023 clause |\n|---|---|---|---|\n";
  const study::AssessPlan& p = in.p;
  o << "| damping ratio | " << rfmt(100 * p.zeta) << " %" << (p.zeta_given ? " (the key's)" : " [2003: Table 6.6" + std::string(p.zeta_extra > 0 ? " + Eq. 6.13]" : "]"))
    << " | assess.damping_ratio | " << cite(Clause::damping) << " |\n";
  o << "| deck acceleration limit | " << rfmt(c.acc_limit) << " m/s² | assess.acceleration_limit_mps2 | " << cite(Clause::deck_acceleration) << " |\n";
  o << "| vertical deflection limit | span/" << rfmt(c.deflection_ratio) << " | assess.deflection_limit_ratio | " << cite(Clause::deformation) << " |\n";
  o << "| deck end rotation limit | " << rfmt(c.rotation_limit * 1e3) << " mrad | assess.end_rotation_limit_rad | " << cite(Clause::deformation) << " |\n";
  o << "| determinant length Lφ | " << (c.determinant_length ? rfmt(*c.determinant_length) + " m (the key's)" : std::string("as in the limits above [2003: Table 6.2]"))
    << " | assess.determinant_length_m | " << cite(Clause::determinant_length) << " |\n";
  o << "| mass bounds (ballast) | lower × " << rfmt(c.ballast_lower) << ", upper × " << rfmt(c.ballast_upper)
    << (c.ballast_width ? " (the bed's densities and depth)" : "") << " | assess.ballast_* | " << cite(Clause::mass) << " |\n";
  o << "| car-body acceleration b_v | " << rfmt(c.comfort_limit) << " m/s² | assess.comfort_limit_mps2 | " << cite(Clause::comfort_acceleration) << " |\n";
  o << "| comfort by deck deflection L/δ | " << (c.comfort_deflection_ratio ? rfmt(*c.comfort_deflection_ratio) : std::string("not given"))
    << " | assess.comfort_deflection_ratio | " << cite(Clause::comfort_deflection) << " |\n";
  o << "| highest speed | " << rfmt(c.speed_factor) << " × the line speed | assess.speed_factor | " << cite(Clause::speeds) << " |\n";
}

void report_notes(std::ostringstream& o, const ReportInput& in) {
  report_edition_values(o, in);
  o << "\n## Notes and items to confirm\n\n";
  for (const auto& n : in.p.notes) o << "- " << n << "\n";
  o << "- To confirm against the text of the standard: φ″ (" << study::cite_brief(in.c.edition, study::Clause::irregularities) << ") in the design effect; the deflection and end-rotation "
       "limits (given by assess.deflection_limit_ratio and assess.end_rotation_limit_rad).\n";
  if (in.nominal.settings.vehicle.model == study::VehicleModel::forces)
    o << "- Passenger comfort and wheel unloading are checked with vehicle models only (train.vehicle = \"sprung\" or "
         "\"multibody\", docs/vehicles.md): with moving forces there are no car bodies and no contact forces.\n";
  else
    o << "- The car-body acceleration checked is the largest on each body's floor at its centre and above its bogie centres "
         "(EN 12299's floor positions: bounce plus pitch times the half bogie spacing; a sprung mass's own), "
      << (in.nominal.settings.vehicle.comfort_lowpass_hz > 0.0
              ? "low-passed at " + rfmt(in.nominal.settings.vehicle.comfort_lowpass_hz) + " Hz (train.comfort_lowpass_hz)"
              : std::string("unfiltered (train.comfort_lowpass_hz sets a low-pass)"))
      << ". To confirm: the comfort limits of " << study::cite_brief(in.c.edition, study::Clause::comfort_acceleration) << ".\n";
  if (!in.r.failures.empty()) o << "- **" << in.r.failures.size() << " case(s) failed** (failures.csv): the checks above leave them out.\n";
  o << "\n## Provenance\n\nScenario `" << in.flat.path << "`; " << version() << " (commit " << git_commit() << "); command `"
    << in.command_line << "`. Tables: checks.csv, envelope.csv, load_effects.csv, phi_dyn.csv, mass_cases.csv, governing.csv, failures.csv"
    << (in.r.vehicles.empty() ? "" : ", vehicles.csv (the vehicles' extremes per case)") << "; "
       "manifest.toml holds the resolved scenario and the checksums of its files.\n";
}

void report_layout(std::ostringstream& o, const study::LayoutSensitivity& ls, const study::Scenario& sc) {
  if (!ls.near) return;
  o << "\n## Sleeper layout at the joints (docs/model.md)\n\nSpans " << ls.span_a << " and " << ls.span_b
    << " have bending modes of the same order " << rfmt(100 * ls.split, 2)
    << " % apart: coupled through the track, which span dominates the lower mode depends on where the sleepers sit at the "
       "joints, and the per-span peaks with it (their sum and the resonance speeds do not). The governing acceleration case ("
    << ls.train << ", " << rfmt(ls.speed * 3.6) << " km/h, " << ls.variant << ") with the sleepers moved (track.first_sleeper_offset):\n\n| offset [m] |";
  for (const auto& st : sc.stations) o << " " << st.name << " [m/s²] |";
  o << "\n|---:|";
  for (std::size_t i = 0; i < sc.stations.size(); ++i) o << "---:|";
  o << "\n";
  for (std::size_t k = 0; k < ls.offsets.size(); ++k) {
    o << "| " << rfmt(ls.offsets[k], 3) << " |";
    for (double a : ls.peaks[k]) o << " " << rfmt(a) << " |";
    o << "\n";
  }
  o << "| spread |";
  for (std::size_t j = 0; j < sc.stations.size(); ++j) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const auto& row : ls.peaks) lo = std::min(lo, row[j]), hi = std::max(hi, row[j]);
    o << " " << rfmt(100 * (hi / lo - 1), 3) << " % |";
  }
  o << "\n\nA check near its limit should hold for every layout: give the built one with track.first_sleeper_offset.\n";
}

std::string report_text(const ReportInput& in) {
  std::ostringstream o;
  o << "# Dynamic assessment (" << (in.c.edition == study::Edition::en2023 ? "EN 1991-2:2023 Section 8, EN 1990:2023 Annex A.2" : "EN 1991-2 6.4, EN 1990 A2") << "): " << (in.nominal.title.empty() ? in.flat.path : in.nominal.title) << "\n\n";
  report_summary(o, in);
  report_inputs(o, in);
  report_model(o, in);
  report_modes(o, in);
  report_flow(o, in);
  report_details(o, in);
  if (in.layout) report_layout(o, *in.layout, in.nominal);
  report_notes(o, in);
  return o.str();
}

}  // namespace

study::AssessPlan plan_assessment(FlatScenario& flat, const std::string& scenario, int threads) {
  study::AssessPlan p;
  p.config = read_assess_config(flat, scenario);
  plan_damping_and_cutoff(flat, p.config, p);
  plan_variants(flat, p.config, p, threads);
  return p;
}

void write_assessment_tables(const std::string& out, const study::AssessResult& r, int n_threads) {
  const auto& variants = r.plan.variants;
  write_envelope_csv(out + "/envelope.csv", r.sweep.rows, variants);
  write_quantities_csv(out + "/load_effects.csv", r.sweep.quantities, variants, n_threads);
  write_governing_csv(out + "/governing.csv", study::governing(r.sweep.rows));
  write_failures_csv(out + "/failures.csv", r.sweep.failures);
  write_checks_csv(out + "/checks.csv", r.checks);
  write_increments_csv(out + "/phi_dyn.csv", r.increments);
  write_mass_cases_csv(out + "/mass_cases.csv", r.plan);
  if (!r.sweep.vehicles.empty()) write_vehicle_envelope_csv(out + "/vehicles.csv", r.sweep.vehicles, variants);
}

// Columns named `names`, of the kinds `kinds` ('t' text, 'n' number).
std::vector<TableColumn> assess_columns(const std::vector<std::string>& names, const std::string& kinds) {
  std::vector<TableColumn> c(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    c[i].name = names[i];
    c[i].kind = kinds[i] == 't' ? TableColumn::Kind::text : TableColumn::Kind::number;
  }
  return c;
}

std::vector<TableColumn> assessment_check_columns(const std::vector<study::AssessCheck>& checks) {
  std::vector<TableColumn> c = assess_columns(
      {"check", "quantity", "value", "limit", "unit", "utilisation", "result", "variant", "train", "speed_kmh", "clause"},
      "ttnntntttnt");
  for (const auto& k : checks) {
    c[0].cells.push_back(k.check), c[1].cells.push_back(k.quantity), c[2].values.push_back(k.value);
    c[3].values.push_back(k.limit), c[4].cells.push_back(study::quantity_unit(k.quantity)), c[5].values.push_back(k.utilisation());
    c[6].cells.push_back(k.verdict), c[7].cells.push_back(k.variant), c[8].cells.push_back(k.train);
    c[9].values.push_back(k.speed * 3.6), c[10].cells.push_back(k.clause);
  }
  return c;
}

std::vector<TableColumn> assessment_increment_columns(const std::vector<study::AssessIncrement>& inc) {
  std::vector<TableColumn> c = assess_columns(
      {"variant", "train", "quantity", "max_abs_dynamic", "max_abs_quasi_static", "phi_dyn", "speed_kmh"}, "tttnnnn");
  for (const auto& i : inc) {
    c[0].cells.push_back(i.variant), c[1].cells.push_back(i.train), c[2].cells.push_back(i.quantity);
    c[3].values.push_back(i.dynamic), c[4].values.push_back(i.quasi_static), c[5].values.push_back(i.phi());
    c[6].values.push_back(i.speed * 3.6);
  }
  return c;
}

std::string assessment_report(const study::AssessResult& r, const FlatScenario& flat, const std::string& command_line,
                              bool figures) {
  ReportInput in{r.plan.config, r.plan, r.sweep, r.checks, r.increments, flat, r.nominal(), command_line, figures, &r.layout};
  return report_text(in);
}

}  // namespace viaduct::io
