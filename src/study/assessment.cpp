// The dynamic check as a workflow (assessment.hpp): the runs, the statics and every check.
#include "viaduct/study/assessment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/study/guards.hpp"

namespace viaduct::study {

double comfort_limit_of(const std::string& level) {
  if (level == "very-good") return 1.0;
  if (level == "good") return 1.3;
  return 2.0;  // "acceptable" (the schema admits no other)
}

std::vector<std::vector<double>> assessment_train_speeds(const std::vector<double>& distances, const Scenario& sc,
                                                         const AssessConfig& c, double f_cut) {
  std::vector<double> freqs;
  for (const auto& m : model::deck_bending_modes(model::build_structure(sc.bridge, sc.track), 6))
    if (m.frequency_hz <= f_cut) freqs.push_back(m.frequency_hz);
  std::vector<std::vector<double>> out;
  for (const double d : distances) {
    std::vector<double> res;
    for (double f : freqs)
      for (int j = 1; j <= c.harmonics && d > 0.0; ++j) res.push_back(f * d / j);
    out.push_back(study::assessment_speeds(c.v_min, c.v_max, c.step, c.fine_step, res, c.band));
  }
  return out;
}

namespace {

std::vector<AssessIncrement> assess_increments(const std::vector<QuantityRow>& rows) {
  std::vector<AssessIncrement> out;
  std::map<std::string, std::size_t> at;
  for (const auto& r : rows) {
    const std::string key = r.variant + '\n' + r.train + '\n' + r.quantity;
    auto it = at.find(key);
    if (it == at.end()) {
      it = at.emplace(key, out.size()).first;
      out.push_back({r.variant, r.train, r.quantity, -1.0, r.quasi_static.max_abs(), r.speed});
    }
    AssessIncrement& inc = out[it->second];
    if (r.dynamic.max_abs() > inc.dynamic) inc.dynamic = r.dynamic.max_abs(), inc.speed = r.speed;
  }
  return out;
}

// The span (0-based) a quantity belongs to: span<k>_… or a deck station's span, the station
// whose name is the quantity's longest prefix ("S1_mid_moment_Nm" is S1_mid's, not S1's).
std::size_t span_of(const std::string& quantity, const Scenario& sc) {
  if (quantity.rfind("span", 0) == 0) return static_cast<std::size_t>(std::max(1, std::atoi(quantity.c_str() + 4)) - 1);
  const StationSpec* best = nullptr;
  for (const auto* list : {&sc.stations, &sc.effect_stations})
    for (const auto& st : *list)
      if (st.on_deck && quantity.rfind(st.name + "_", 0) == 0 && (!best || st.name.size() > best->name.size())) best = &st;
  return best ? best->span : 0;
}

}  // namespace

namespace {

std::string flow_num(double x, int sig = 4) { return format_number(x, sig); }

// A clause whose value is to confirm: "(to confirm)" after a known clause (a 2023 one not known
// says so in its reference already).
std::string cite_to_confirm(Edition e, Clause c) { return cite(e, c) + (clause_known(e, c) ? " (to confirm)" : ""); }

// The boxes of Fig. 6.9 after "V <= 200 km/h? yes" for a chain of simply supported spans.
void simple_spans_flow(DynamicAnalysisNeed& d, const Scenario& sc, Edition ed) {
  const std::string fig = cite_brief(ed, Clause::frequency_limits);
  auto ask = [&](const std::string& q, const std::string& a) { d.steps.push_back({q, a}); };
  ask("Simple structure (note 1)?", "taken as yes: simply supported beams (skew and the bearings' flexibility to confirm)");
  std::string shorter;
  for (std::size_t i = 0; i < sc.bridge.spans.size(); ++i)
    if (sc.bridge.spans[i].length < 40.0) shorter += (shorter.empty() ? "" : ", ") + std::to_string(i + 1);
  if (shorter.empty()) {
    ask("L >= 40 m?", "yes: every span");
    d.required = false;
    d.conclusion = "a dynamic analysis is not required by the chart (every span is 40 m or longer): use Φ with the static "
                   "analysis; the dynamic analysis below is a check beyond it";
    return;
  }
  ask("L >= 40 m?", "no: span(s) " + shorter + " shorter");
  std::string outside, inside;
  for (const auto& m : d.members) {
    const std::string what = "span " + std::to_string(m.span) + " n0 = " + flow_num(m.f1) + " Hz in [" + flow_num(m.lower) + ", " +
                             flow_num(m.upper) + "] Hz";
    std::string& into = m.within() ? inside : outside;
    into += (into.empty() ? "" : "; ") + (m.within() ? what : "span " + std::to_string(m.span) + " n0 = " + flow_num(m.f1) +
                                                                   " Hz outside [" + flow_num(m.lower) + ", " + flow_num(m.upper) + "] Hz");
  }
  if (!outside.empty()) {
    ask("n0 within the limits of " + fig + "?", "no: " + outside);
    d.required = true;
    d.conclusion = "a dynamic analysis is required (" + cite_brief(ed, Clause::flow_chart) + ": n0 outside the limits of " + fig + ")";
    return;
  }
  ask("n0 within the limits of " + fig + "?", "yes: " + inside);
  ask("n_T > 1.2 n0 (first torsional frequency, note 4)?", "not answered: a 2D model has no torsion");
  const std::string annex_f = cite_brief(ed, Clause::speed_frequency_ratio);
  ask("v/n0 <= (v/n0)lim (" + annex_f + ", notes 2 and 3)?", "not answered: the tables of " + annex_f + " are not carried");
  d.required = true;
  d.conclusion = "not decided: the chart's torsion and " + annex_f + " boxes are beyond a 2D model; the dynamic analysis below answers "
                 "for them";
}

}  // namespace

DynamicAnalysisNeed dynamic_analysis_need(const AssessPlan& p, const Scenario& sc) {
  DynamicAnalysisNeed d;
  for (const auto& m : p.members) {
    DynamicAnalysisNeed::Member x;
    x.span = m.span;
    x.f1 = m.f1;
    // a continuous deck: its determinant length (our reading of 6.4.4 for other than simply
    // supported spans; to confirm)
    x.length = m.span > 0 ? sc.bridge.spans[static_cast<std::size_t>(m.span - 1)].length
                          : assessment_determinant_length("", sc, p.config);
    const FrequencyLimits lim = fig_6_10_limits(x.length);
    x.lower = lim.lower, x.upper = lim.upper;
    d.members.push_back(x);
  }
  const double v = p.config.line_speed * 3.6;
  if (v > 200.0) {
    d.steps.push_back({"V <= 200 km/h?", "no: the line speed is " + flow_num(v) + " km/h"});
    d.required = true;
    d.conclusion = "a dynamic analysis is required (" + cite_brief(p.config.edition, Clause::dynamic_analysis) + "): the line speed exceeds 200 km/h";
    return d;
  }
  d.steps.push_back({"V <= 200 km/h?", "yes: the line speed is " + flow_num(v) + " km/h"});
  if (sc.bridge.continuous) {
    d.steps.push_back({"Continuous bridge (note 5)?", "yes"});
    d.required = false;
    d.conclusion = "a dynamic analysis is not required by the chart for a continuous bridge at V <= 200 km/h (note 5: to "
                   "confirm against the text); the dynamic analysis below is a check beyond it";
    return d;
  }
  d.steps.push_back({"Continuous bridge (note 5)?", "no: " + std::to_string(sc.bridge.spans.size()) + " simply supported span(s)"});
  simple_spans_flow(d, sc, p.config.edition);
  return d;
}

std::vector<ResonanceSpeed> resonance_speeds(const AssessPlan& p) {
  std::vector<ResonanceSpeed> out;
  if (p.variants.empty()) return out;
  const AssessConfig& c = p.config;
  const std::vector<load::Train>& trains = p.variants.front().scenario.trains;
  if (p.train_distance.size() != trains.size())
    throw std::logic_error("resonance_speeds: the plan has " + std::to_string(p.train_distance.size()) +
                           " characteristic distances for " + std::to_string(trains.size()) + " trains");
  for (std::size_t i = 0; i < trains.size(); ++i) {
    const load::Train& t = trains[i];
    const double d = p.train_distance[i];
    if (!(d > 0.0)) continue;
    for (std::size_t m = 0; m < p.deck_modes.size(); ++m) {
      const double f = p.deck_modes[m].frequency_hz;
      if (f > p.f_cut) continue;
      for (int j = 1; j <= c.harmonics; ++j) {
        const double v = f * d / j;
        if (v >= c.v_min * (1 - 1e-12) && v <= c.v_max * (1 + 1e-12))
          out.push_back({t.name, d, f, static_cast<int>(m + 1), j, v});
      }
    }
  }
  return out;
}

std::string quantity_unit(const std::string& quantity) {
  static const std::vector<std::pair<std::string, std::string>> units = {
      {"_acc_mps2", "m/s2"}, {"_disp_m", "m"}, {"_moment_Nm", "N m"}, {"_reaction_N", "N"}, {"_shear_N", "N"},
      {"_rot_rad", "rad"},   {"_strain_ue", "ue"}, {"_hz", "Hz"},     {"_mm_per_3m", "mm/3m"}};
  for (const auto& [suffix, unit] : units)
    if (quantity.size() >= suffix.size() && quantity.compare(quantity.size() - suffix.size(), suffix.size(), suffix) == 0)
      return unit;
  return "-";
}

// Lφ of a quantity (6.4.5.3, Table 6.2): assess.determinant_length_m when given; on a continuous
// deck Table 6.2 for girders continuous over n spans (k × the mean span, not below the longest;
// to confirm); else its span's length.
double assessment_determinant_length(const std::string& quantity, const Scenario& sc, const AssessConfig& c) {
  if (c.determinant_length) return *c.determinant_length;
  if (sc.bridge.continuous) {
    std::vector<double> spans;
    for (const auto& s : sc.bridge.spans) spans.push_back(s.length);
    return continuous_determinant_length(spans);
  }
  return sc.bridge.spans[std::min(span_of(quantity, sc), sc.bridge.spans.size() - 1)].length;
}

namespace {

// A rotation the end-rotation limit applies to (A2.4.4.2.3: at the deck's ends): every span end
// of simply supported spans; the first and last supports of a continuous deck.
bool assess_end_rotation(const std::string& quantity, const Scenario& sc) {
  if (!sc.bridge.continuous) return true;
  return quantity == "support1_rot_rad" || quantity == "support" + std::to_string(sc.bridge.spans.size() + 1) + "_rot_rad";
}

// A deck station over a rigid bearing (a span's end): its deflection and acceleration are zero by
// construction, so they get no check rows (the report says so).
bool on_rigid_support(const std::string& station, const Scenario& sc) {
  if (!sc.bridge.bearings.rigid) return false;
  for (const auto* list : {&sc.stations, &sc.effect_stations})
    for (const auto& st : *list)
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
  InfluenceLines il;
  std::vector<EffectPeak> lm71;
  std::vector<double> permanent;  // per quantity: a bearing's permanent load [N], else 0
};

Statics statics_of(const Scenario& nominal, const AssessConfig& c) {
  RunSettings rs = nominal.settings;
  rs.method = Method::newmark;  // no modes needed for static lines
  const PreparedModel pm = prepare_model(model::build_structure(nominal.bridge, nominal.track),
                                                       nominal.stations, rs, false, true, nominal.effect_stations);
  Statics st;
  st.il = influence_lines(pm);
  st.lm71 = lm71_extremes(st.il, c.alpha, nominal.settings.load_factor);
  st.permanent.assign(st.il.names.size(), 0.0);
  const std::size_t n_disp = st.il.names.size() - pm.effects.size();
  for (std::size_t j = 0; j < pm.effects.size(); ++j)
    if (pm.effects[j].bearing >= 0)
      st.permanent[n_disp + j] = pm.structure.bearings[static_cast<std::size_t>(pm.effects[j].bearing)].permanent;
  return st;
}

// The design-effect, deformation and uplift rows of one quantity.
void quantity_checks(std::size_t q, const Statics& st, const std::vector<AssessIncrement>& inc,
                     const std::vector<QuantityRow>& rows, const Scenario& sc, const AssessConfig& c,
                     const AssessPlan& p, std::vector<AssessCheck>& out) {
  const std::string& name = st.il.names[q];
  const double L = sc.bridge.spans[std::min(span_of(name, sc), sc.bridge.spans.size() - 1)].length;
  const double L_phi = assessment_determinant_length(name, sc, c);
  const double Phi = c.careful ? phi2(L_phi) : phi3(L_phi);
  const double phi2nd = phi_irregularities(L_phi, c.v_max, p.f1);
  const double lm = Phi * st.lm71[q].max_abs();
  // (1 + φ′dyn + φ″/2) × the train's static effect, the worst train and mass (6.4.6.5(3)).
  AssessCheck d{"dynamic design effect vs LM71", name, 0.0, lm, "", "", "", std::numeric_limits<double>::quiet_NaN(),
          cite(c.edition, Clause::design_effect)};
  const AssessIncrement* dyn_max = nullptr;
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
  const bool rot = ends_with(name, "_rot_rad") && assess_end_rotation(name, sc);
  if (disp || rot) {
    const double limit = disp ? L / c.deflection_ratio : c.rotation_limit;
    const std::string what = disp ? "vertical deflection" : "deck end rotation";
    const std::string clause = cite(c.edition, Clause::deformation) + " (limit to confirm)";
    AssessCheck dy{what + ", trains (dynamic)", name, dyn_max->dynamic, limit, "", dyn_max->variant, dyn_max->train, dyn_max->speed, clause};
    AssessCheck sl{what + ", LM71 x Phi", name, lm, limit, "", "", "LM71", std::numeric_limits<double>::quiet_NaN(), clause};
    for (AssessCheck* k : {&dy, &sl}) {
      k->verdict = k->value <= limit ? "pass" : "FAIL";
      out.push_back(*k);
    }
  }
  if (st.permanent[q] > 0.0) {  // a bearing: the traffic's largest pull against the permanent load
    AssessCheck u{"bearing uplift", name, 0.0, st.permanent[q], "", "", "", std::numeric_limits<double>::quiet_NaN(),
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
void vehicle_checks(const SweepResult& r, const AssessConfig& c, std::vector<AssessCheck>& out) {
  const VehicleRow *body = nullptr, *unload = nullptr;
  for (const auto& v : r.vehicles) {
    if (!v.peaks.present) continue;
    if (!body || v.peaks.max_floor_acc > body->peaks.max_floor_acc) body = &v;
    if (!unload || v.peaks.max_unloading_ratio > unload->peaks.max_unloading_ratio) unload = &v;
  }
  if (!body) return;
  AssessCheck b{"passenger comfort (car body)", body->peaks.floor_body + "_floor_acc_mps2", body->peaks.max_floor_acc, c.comfort_limit, "",
          body->variant, body->train, body->speed, cite(c.edition, Clause::comfort_acceleration) + " " + c.comfort_level + (clause_known(c.edition, Clause::comfort_acceleration) ? " (to confirm)" : "")};
  b.verdict = b.value <= b.limit ? "pass" : "FAIL";
  out.push_back(b);
  AssessCheck u{"wheel unloading (P0 - Pmin)/P0", "unloading_ratio", unload->peaks.max_unloading_ratio, c.unloading_limit, "",
          unload->variant, unload->train, unload->speed,
          c.unloading_limit < 1.0 ? "assess.unloading_ratio_limit (the project's)" : "contact kept (1: a wheel leaves the rail)"};
  u.verdict = u.value < u.limit ? "pass" : "FAIL";
  out.push_back(u);
}

// Passenger comfort by deck deflection (EN 1990 A2.4.4.3.2): per span, the largest deflection
// under LM71 × Φ with α = 1 against L / (L/δ), L/δ the figure's value (the key) times 0.7 for one
// or two simply supported spans or two continuous spans, 0.9 for three or more continuous spans,
// divided by the comfort level's b_v (to confirm against the text).
void comfort_deflection_checks(const Statics& st, const Scenario& sc, const AssessConfig& c, std::vector<AssessCheck>& out) {
  const std::size_t n = sc.bridge.spans.size();
  const double factor = n >= 3 ? (sc.bridge.continuous ? 0.9 : 1.0) : 0.7;
  const double b_v = c.comfort_limit;
  for (std::size_t k = 0; k < n; ++k) {
    const double L = sc.bridge.spans[k].length;
    AssessCheck a{"passenger comfort, deck deflection", "", -1.0, std::numeric_limits<double>::quiet_NaN(), "", "", "LM71 x Phi, alpha = 1",
                  std::numeric_limits<double>::quiet_NaN(), cite_to_confirm(c.edition, Clause::comfort_deflection)};
    for (std::size_t q = 0; q < st.il.names.size(); ++q) {
      const std::string& name = st.il.names[q];
      if (!ends_with(name, "_disp_m") || span_of(name, sc) != k || on_rigid_support(name.substr(0, name.size() - 7), sc)) continue;
      const double L_phi = assessment_determinant_length(name, sc, c);
      const double delta = (c.careful ? phi2(L_phi) : phi3(L_phi)) * st.lm71[q].max_abs() / c.alpha;
      if (delta > a.value) a.value = delta, a.quantity = name;
    }
    if (a.quantity.empty()) continue;  // no deflection station on this span
    if (c.comfort_deflection_ratio) {
      a.limit = L * b_v / (*c.comfort_deflection_ratio * factor);
      a.verdict = a.value <= a.limit ? "pass" : "FAIL";
    } else {
      a.verdict = "limit to give (assess.comfort_deflection_ratio)";
    }
    out.push_back(a);
  }
}

// What a 2D model cannot check, said rather than left out (EN 1990 A2.4.4.2.2 and A2.4.4.2.4).
void unchecked_rows(Edition ed, std::vector<AssessCheck>& out) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.push_back({"deck twist", "deck_twist_mm_per_3m", nan, nan, "not checked (2D model)", "", "", nan,
                 cite_to_confirm(ed, Clause::twist)});
  out.push_back({"lateral vibration, first lateral frequency", "lateral_f1_hz", nan, 1.2, "not checked (2D model)", "", "", nan,
                 cite(ed, Clause::lateral) + ": at least 1.2 Hz" + (clause_known(ed, Clause::lateral) ? " (to confirm)" : "")});
}

std::vector<AssessCheck> all_checks(const SweepResult& r, const Statics& st, const std::vector<AssessIncrement>& inc,
                              const Scenario& sc, const AssessConfig& c, const AssessPlan& p) {
  std::vector<AssessCheck> out;
  for (const auto& g : governing(r.rows)) {
    if (on_rigid_support(g.station, sc)) continue;  // no motion there: no row
    AssessCheck a{"deck acceleration", g.station + "_acc_mps2", g.acc.value, c.acc_limit, "", g.acc.variant, g.acc.train,
            g.acc.speed, cite(c.edition, Clause::deck_acceleration)};
    a.verdict = a.value <= a.limit ? "pass" : "FAIL";
    out.push_back(a);
  }
  for (std::size_t q = 0; q < st.il.names.size(); ++q) quantity_checks(q, st, inc, r.quantities, sc, c, p, out);
  comfort_deflection_checks(st, sc, c, out);
  vehicle_checks(r, c, out);
  unchecked_rows(c.edition, out);
  return out;
}

LayoutSensitivity layout_sensitivity(const AssessPlan& p, const std::vector<AssessCheck>& checks, int threads) {
  LayoutSensitivity ls;
  const Variant* gov = nullptr;
  const AssessCheck* acc = nullptr;
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
  // Four layouts, each its own model (its modes and reduction) and run: on the assessment's
  // threads, each layout's row where it belongs; the first failure (in the layouts' order) is
  // thrown as the loop over them threw it.
  const double d = gov->scenario.track->sleeper_spacing;
  constexpr std::size_t n_layouts = 4;
  std::vector<std::vector<double>> rows(n_layouts);
  std::vector<std::exception_ptr> failed(n_layouts);
  parallel_for(n_layouts, std::max(1, std::min(threads, static_cast<int>(n_layouts))), [&](std::size_t k, int) {
    try {
      Scenario sc = gov->scenario;
      sc.track->first_sleeper_offset = d * static_cast<double>(k) / 4.0;
      const PreparedModel pm = prepare_model(sc, false);
      for (const auto& pk : peaks(simulate(pm, *train, ls.speed, sc.settings))) rows[k].push_back(pk.max_abs_acc);
    } catch (...) {
      failed[k] = std::current_exception();
    }
  });
  for (std::size_t k = 0; k < n_layouts; ++k) {
    if (failed[k]) std::rethrow_exception(failed[k]);
    ls.offsets.push_back(d * static_cast<double>(k) / 4.0);
    ls.peaks.push_back(rows[k]);
  }
  return ls;
}

AssessResult run_assessment_impl(AssessPlan plan, const AssessOptions& o) {
  AssessResult res;
  SweepOptions so;
  so.threads = o.threads;
  so.progress = o.progress;
  so.load_effects = true;
  so.cancel = o.cancel;
  res.sweep = run_sweep(plan.variants, so);
  const Scenario& nominal = plan.variants.front().scenario;
  const Statics st = statics_of(nominal, plan.config);
  for (const auto& s : nominal.stations)
    if (on_rigid_support(s.name, nominal))
      plan.notes.push_back("station " + s.name + " sits on a rigid bearing: its deflection and acceleration are zero by construction "
                           "and get no check rows (its moment, shear and strain do)");
  res.increments = assess_increments(res.sweep.quantities);
  res.checks = all_checks(res.sweep, st, res.increments, nominal, plan.config, plan);
  if (o.layout) res.layout = layout_sensitivity(plan, res.checks, o.threads);
  res.plan = std::move(plan);
  return res;
}

}  // namespace

AssessResult run_assessment(AssessPlan plan, const AssessOptions& options) {
  if (plan.variants.empty()) throw InputError("assessment: a plan without mass cases");
  if (options.threads < 1) throw InputError("threads must be >= 1");
  return run_assessment_impl(std::move(plan), options);
}

std::string shown_number(double x, int significant) { return std::isfinite(x) ? format_number(x, significant) : "—"; }

// A value in the unit a reader expects (mm, kN, kN·m, mrad, m/s², µε), from the quantity's suffix.
std::string shown_value(const std::string& quantity, double x) {
  static const std::vector<std::tuple<std::string, double, std::string>> units = {
      {"_acc_mps2", 1.0, " m/s²"}, {"_disp_m", 1e3, " mm"}, {"_moment_Nm", 1e-3, " kN·m"},
      {"_reaction_N", 1e-3, " kN"}, {"_shear_N", 1e-3, " kN"}, {"_rot_rad", 1e3, " mrad"}, {"_strain_ue", 1.0, " µε"}, {"_hz", 1.0, " Hz"}};
  if (!std::isfinite(x)) return shown_number(x);
  for (const auto& [suffix, factor, unit] : units)
    if (ends_with(quantity, suffix)) return shown_number(x * factor) + unit;
  return shown_number(x);
}

}  // namespace viaduct::study
