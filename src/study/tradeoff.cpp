#include "viaduct/study/tradeoff.hpp"

#include "viaduct/study/guards.hpp"

#include <chrono>
#include <cmath>
#include <map>

#include "viaduct/core/error.hpp"

namespace viaduct::study {

namespace {
std::string ms(double dt) { return format_number(dt * 1e3, 4) + " ms"; }

// Envelope values keyed by (train, station), ordered by speed.
using Curves = std::map<std::pair<std::string, std::string>, std::map<double, std::pair<double, double>>>;
Curves curves_of(const SweepResult& r) {
  Curves c;
  for (const auto& row : r.rows) c[{row.train, row.station}][row.speed] = {row.max_abs_acc, row.max_abs_disp};
  return c;
}
}  // namespace

double band_edge_hz(const Scenario& sc) {
  if (!sc.settings.filter.enabled || sc.settings.filter.cheby.band == signal::BandType::highpass) return 30.0;
  return sc.settings.filter.cheby.high_hz;
}

RunSettings reference_settings(const Scenario& sc, double reference_dt) {
  RunSettings s = sc.settings;
  s.method = Method::newmark;
  s.superposition = Superposition::direct;
  s.dt = reference_dt > 0.0 ? reference_dt : sc.settings.dt / 4.0;
  return s;
}

RunSettings preset_settings(const std::string& name, const Scenario& sc) {
  const double fc = band_edge_hz(sc);
  RunSettings s = sc.settings;
  s.superposition = Superposition::direct;
  s.modal = ModalSettings{};
  if ((name == "fast" || name == "default") && sc.track && rail_on_pad_hz(*sc.track) < (name == "fast" ? 1.5 : 2.0) * fc) {
    // Soft pads: the rail's resonance inside the band defeats a truncated modal basis
    // (study/guards.hpp); Newmark at the same step.
    s.method = Method::newmark;
    s.dt = 1.0 / (16.0 * fc);
  } else if (name == "fast" || name == "default") {
    s.method = Method::modal;
    s.modal.max_frequency_hz = (name == "fast" ? 1.5 : 2.0) * fc;
    s.modal.static_correction = true;
    s.dt = 1.0 / (16.0 * fc);
  } else if (name == "reference") {
    s.method = Method::newmark;
    s.dt = 1.0 / (80.0 * fc);
  } else {
    throw InputError("unknown preset '" + name + "': fast, default or reference");
  }
  return s;
}

std::vector<TradeoffRung> default_ladder(const Scenario& sc, bool with_ida) {
  std::vector<TradeoffRung> out;
  const double dt = sc.settings.dt, fc = band_edge_hz(sc);
  for (double k : {4.0, 2.0, 1.0, 0.5}) {
    RunSettings s = sc.settings;
    s.method = Method::newmark;
    s.superposition = Superposition::direct;
    s.dt = dt * k;
    // A coarse step must still sample the filter's band.
    if (sc.settings.filter.enabled && sc.settings.filter.cheby.high_hz >= 0.45 / s.dt) continue;
    out.push_back({"newmark dt=" + ms(s.dt), s});
  }
  for (double k : {1.0, 1.5, 2.0, 3.0, 5.0})
    for (bool sc_on : {true, false}) {
      RunSettings s = sc.settings;
      s.method = Method::modal;
      s.superposition = Superposition::direct;
      s.modal = ModalSettings{};
      s.modal.max_frequency_hz = k * fc;
      s.modal.static_correction = sc_on;
      out.push_back({"modal " + format_number(k * fc, 4) + " Hz" + (sc_on ? " +sc" : "") + " dt=" + ms(dt), s});
    }
  // The same as the presets' bases without the damping vectors: what they buy.
  for (double k : {1.5, 3.0}) {
    RunSettings s = sc.settings;
    s.method = Method::modal;
    s.superposition = Superposition::direct;
    s.modal = ModalSettings{};
    s.modal.max_frequency_hz = k * fc;
    s.modal.damping_vectors = 0;
    out.push_back({"modal " + format_number(k * fc, 4) + " Hz +sc dv=0 dt=" + ms(dt), s});
  }
  for (const char* name : {"fast", "default"}) {
    const RunSettings s = preset_settings(name, sc);
    out.push_back({std::string("preset ") + name + " (modal " + format_number(s.modal.max_frequency_hz, 4) +
                       " Hz +sc dt=" + ms(s.dt) + ")",
                   s});
  }
  if (with_ida)
    for (double rtol : {1e-2, 1e-3, 1e-4}) {
      RunSettings s = sc.settings;
      s.method = Method::ida;
      s.superposition = Superposition::direct;
      s.ida.rtol = rtol;
      s.ida.atol_disp = 1e-3 * rtol;
      s.ida.atol_vel = 1e-1 * rtol;
      // With vehicles IDA integrates the modes: those of the scenario, or up to 3 f_c.
      const bool band = s.vehicle.model != VehicleModel::forces && s.modal.n_modes == 0 && !(s.modal.max_frequency_hz > 0.0);
      if (band) s.modal.max_frequency_hz = 3.0 * fc;
      out.push_back({"ida rtol=" + format_number(rtol, 3) + (band ? " modal " + format_number(3.0 * fc, 4) + " Hz" : "") +
                         " out=" + ms(dt),
                     s});
    }
  if (sc.trains.size() > 1) {
    RunSettings s = sc.settings;
    s.method = Method::newmark;
    s.superposition = Superposition::unit_response;
    out.push_back({"unit-response newmark dt=" + ms(dt), s});
    s.method = Method::modal;
    s.modal = ModalSettings{};
    s.modal.max_frequency_hz = 3.0 * fc;
    out.push_back({"unit-response modal " + format_number(3.0 * fc, 4) + " Hz +sc dt=" + ms(dt), s});
  }
  return out;
}

TradeoffResult run_tradeoff(const Scenario& sc, const RunSettings& reference, const std::vector<TradeoffRung>& ladder,
                            int threads, const ProgressSink& progress) {
  if (sc.sweep_speeds.empty()) throw InputError("tradeoff needs the scenario's sweep speeds");
  TradeoffResult out;
  for (const auto& st : sc.stations) out.stations.push_back(st.name);
  auto run = [&](const std::string& label, const RunSettings& s) {
    Scenario v = sc;
    v.settings = s;
    SweepOptions o;
    o.threads = threads;
    const auto t0 = std::chrono::steady_clock::now();
    SweepResult r = run_sweep({{label, v}}, o);
    TradeoffRow row;
    row.label = label;
    row.settings = s;
    row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.n_failed = r.summary.n_failed;
    row.n_modes = r.summary.n_modes.front();  // the sweep's own basis: no second eigenproblem
    return std::make_pair(row, r);
  };
  auto [ref_row, ref_sweep] = run("reference newmark dt=" + ms(reference.dt), reference);
  if (ref_sweep.summary.n_failed > 0)
    throw SolverError("the reference failed in " + std::to_string(ref_sweep.summary.n_failed) +
                      " case(s), e.g.: " + ref_sweep.failures.front().message);
  out.reference = ref_row;
  out.reference.station_acc_error.assign(sc.stations.size(), 0.0);
  out.reference.station_disp_error.assign(sc.stations.size(), 0.0);
  const Curves ref = curves_of(ref_sweep);
  std::size_t done = 0;
  if (progress) progress(++done, ladder.size() + 1);
  for (const auto& rung : ladder) {
    auto [row, sweep] = run(rung.label, rung.settings);
    row.station_acc_error.assign(sc.stations.size(), 0.0);
    row.station_disp_error.assign(sc.stations.size(), 0.0);
    const Curves got = curves_of(sweep);
    for (const auto& [key, ref_curve] : ref) {
      double peak_a = 0.0, peak_d = 0.0, err_a = 0.0, err_d = 0.0;
      for (const auto& [speed, v] : ref_curve) peak_a = std::max(peak_a, v.first), peak_d = std::max(peak_d, v.second);
      const auto it = got.find(key);
      if (it == got.end()) continue;
      for (const auto& [speed, v] : it->second) {
        const auto r = ref_curve.find(speed);
        if (r == ref_curve.end()) continue;
        err_a = std::max(err_a, std::abs(v.first - r->second.first));
        err_d = std::max(err_d, std::abs(v.second - r->second.second));
      }
      const double ea = peak_a > 0 ? err_a / peak_a : 0.0, ed = peak_d > 0 ? err_d / peak_d : 0.0;
      for (std::size_t s = 0; s < sc.stations.size(); ++s)
        if (sc.stations[s].name == key.second) {
          row.station_acc_error[s] = std::max(row.station_acc_error[s], ea);
          row.station_disp_error[s] = std::max(row.station_disp_error[s], ed);
        }
      row.max_acc_error = std::max(row.max_acc_error, ea);
      row.max_disp_error = std::max(row.max_disp_error, ed);
    }
    out.rungs.push_back(row);
    if (progress) progress(++done, ladder.size() + 1);
  }
  return out;
}

}  // namespace viaduct::study
