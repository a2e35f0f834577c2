#pragma once
// Synthetic fitting problems with known parameters, shared by the unit tests and the recovery
// benchmark (tools/bench/fit_recovery.cpp).
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "viaduct/study/fit.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::test {

using namespace viaduct::study;

// A 12 m simply supported span (EI, mass, modal damping from the values), three 100 kN axles,
// deck stations at L/2 and L/4, Newmark 2 ms, accelerations filtered 1-30 Hz.
// values: [EI, damping ratio, (mass per metre), (bearing damping: no effect on rigid bearings)]
inline Scenario small_scenario(const std::vector<double>& v) {
  Scenario sc;
  model::SpanParams span;
  span.length = 12.0;
  span.EI = v.at(0);
  span.mass_per_m = v.size() > 2 ? v[2] : 10000.0;
  sc.bridge.spans = {span};
  sc.bridge.element_size = 0.5;
  sc.bridge.damping.ratio = v.at(1);
  if (v.size() > 3) sc.bridge.bearings.c = v[3];
  sc.trains = {load::regular_train("t", 3, 8.0, 100e3)};
  sc.stations = {{"mid", true, 0, 6.0, 0.0}, {"quarter", true, 0, 3.0, 0.0}};
  sc.settings.dt = 2e-3;
  sc.settings.free_vibration_s = 1.5;
  sc.settings.filter.cheby.low_hz = 1.0;
  sc.settings.filter.cheby.high_hz = 30.0;
  sc.run_speed = 30.0;
  return sc;
}

// The "measurement": the model at `truth`, unfiltered accelerations at both stations, 500 Hz,
// the logger started 0.7 s before the train arrived (t0 = 5 s), Gaussian noise of `noise` x the
// peak; the train at `speed` [m/s].
inline FitRecord synthetic_record(const std::vector<double>& truth, double noise, unsigned seed = 3, double speed = 30.0) {
  const Scenario sc = small_scenario(truth);
  RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  rs.free_vibration_s = 3.0;  // rings past the record's end, as a real bridge does
  const PreparedModel pm = prepare_model(sc);
  const RunResult r = simulate(pm, sc.trains[0], speed, rs);
  FitRecord rec;
  rec.name = "synthetic";
  rec.speed = speed;
  rec.fs_hz = 500.0;
  rec.t0_s = 5.0;
  const double lead = 0.7;
  const Index n = static_cast<Index>((lead + r.t[r.t.size() - 1] - 1.0) * rec.fs_hz);
  std::mt19937 rng(seed);
  for (std::size_t s = 0; s < 2; ++s) {
    const Vector& a = r.stations[s].acc;
    std::normal_distribution<double> nd(0.0, noise * r.stations[0].acc.cwiseAbs().maxCoeff());
    FitChannel ch;
    ch.name = s == 0 ? "mid_acc_mps2" : "quarter_acc_mps2";
    ch.station = s == 0 ? "mid" : "quarter";
    ch.samples.resize(n);
    for (Index j = 0; j < n; ++j) {
      const double tm = static_cast<double>(j) / rec.fs_hz - lead;  // model time: one record sample per model step
      const auto i = static_cast<Index>(std::lround(tm / 2e-3));
      const double v = (tm >= 0 && i < a.size()) ? a[i] : 0.0;
      ch.samples[j] = v + nd(rng);
    }
    rec.channels.push_back(ch);
  }
  return rec;
}

inline FitParameter param(const std::string& key, double lo, double hi, double x0,
                          ParameterScale scale = ParameterScale::log) {
  return FitParameter{key, "", lo, hi, x0, scale};
}

// EI in [3e9, 8e9] N·m² from ei0 and the damping ratio in [0.005, 0.08] from zeta0 on small_scenario,
// against `records` (default: one of EI 5.5e9, ζ 2 % with 1 % noise).
inline FitProblem ei_damping_problem(double ei0, double zeta0, std::vector<FitRecord> records = {}) {
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, ei0), param("bridge.damping.ratio", 0.005, 0.08, zeta0)};
  p.records = records.empty() ? std::vector<FitRecord>{synthetic_record({5.5e9, 0.02}, 0.01)} : std::move(records);
  p.scenario_at = small_scenario;
  return p;
}

}  // namespace viaduct::test
