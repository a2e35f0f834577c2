#include "viaduct/study/vehicle_ladder.hpp"

#include <chrono>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::study {

namespace {

LadderRow run_rung(const Scenario& sc, const RunSettings& settings, const load::Train& train, double speed,
                   const std::string& rung) {
  LadderRow row;
  row.rung = rung;
  row.method = settings.method;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const PreparedModel pm = prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, settings, false);
    const RunResult r = simulate(pm, train, speed, settings);
    row.peaks = peaks(r);
    row.vehicle = vehicle_peaks(r);
    row.n_steps = r.summary.n_steps;
    row.n_modes = r.n_modes;
  } catch (const std::exception& e) {
    row.error = e.what();
  }
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return row;
}

}  // namespace

LadderResult vehicle_ladder(const Scenario& sc, const load::Train& train, double speed, double modal_max_hz) {
  require_positive(speed, "speed [m/s]");
  require_non_negative(modal_max_hz, "modal max frequency [Hz]");
  train.validate();
  struct Rung {
    std::string name;
    VehicleModel model;
    bool profile;
  };
  std::vector<Rung> rungs = {{"forces", VehicleModel::forces, false}};
  if (sc.settings.vehicle.sprung || !train.coaches.empty()) rungs.push_back({"sprung", VehicleModel::sprung, false});
  if (!train.coaches.empty()) rungs.push_back({"multibody", VehicleModel::multibody, false});
  if (sc.settings.irregularity.enabled() && rungs.size() > 1)
    rungs.push_back({rungs.back().name + " + profile", rungs.back().model, true});
  LadderResult out;
  for (const auto& s : sc.stations) out.stations.push_back(s.name);
  for (const Rung& r : rungs) {
    RunSettings st = sc.settings;
    st.vehicle.model = r.model;
    st.superposition = Superposition::direct;
    if (!r.profile) st.irregularity = IrregularitySettings{};
    st.method = Method::newmark;
    out.rows.push_back(run_rung(sc, st, train, speed, r.name));
    if (modal_max_hz > 0.0) {
      st.method = Method::modal;
      st.modal.n_modes = 0;
      st.modal.max_frequency_hz = modal_max_hz;
      out.rows.push_back(run_rung(sc, st, train, speed, r.name));
    }
  }
  // The reference: the richest rung on the full model (the last Newmark row), or the richest that ran.
  std::size_t ref = out.rows.size();
  for (std::size_t i = 0; i < out.rows.size(); ++i)
    if (out.rows[i].method == Method::newmark && out.rows[i].error.empty()) ref = i;
  if (ref == out.rows.size()) throw InputError("vehicle ladder: no rung could run; the first failed with: " + out.rows.front().error);
  out.richest = ref;
  const auto& best = out.rows[ref].peaks;
  for (auto& row : out.rows) {
    if (!row.error.empty()) continue;
    for (std::size_t k = 0; k < best.size(); ++k) {
      row.acc_vs_richest.push_back(row.peaks[k].max_abs_acc / best[k].max_abs_acc - 1.0);
      row.disp_vs_richest.push_back(row.peaks[k].max_abs_disp / best[k].max_abs_disp - 1.0);
    }
  }
  return out;
}

}  // namespace viaduct::study
