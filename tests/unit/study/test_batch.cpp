#include <catch2/catch.hpp>
#include <cmath>

#include "../../verification/helpers.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/study/sweep.hpp"

using namespace viaduct;
using namespace viaduct::study;

// simulate_batch (Newmark, four speeds per factorisation and per sweep of the matrices) against
// simulate() one speed at a time, on the track model: the same histories up to the order of the
// floating-point sums (1e-9 of each history's peak; the filter is linear, so it keeps that).
namespace {
Scenario short_track() {
  return vt::shipped("old-guadiana-sensitivity",
                     {"track.approach_length=6.0", "track.exit_length=6.0", "analysis.free_vibration_s=0.2",
                      "sweep.mode=\"reference\""});
}
double peak(const Vector& x) { return x.size() ? x.cwiseAbs().maxCoeff() : 0.0; }
}  // namespace

TEST_CASE("batched Newmark runs give the histories of single runs") {
  const Scenario sc = short_track();
  const PreparedModel pm = prepare_model(sc);
  const std::vector<double> speeds = {40.0, 55.5, 71.0, 86.5, 99.0};  // one full batch and one partial
  const std::vector<RunResult> batch = simulate_batch(pm, sc.trains[0], speeds, sc.settings);
  REQUIRE(batch.size() == speeds.size());
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    const RunResult one = simulate(pm, sc.trains[0], speeds[s], sc.settings);
    INFO("speed " << speeds[s]);
    REQUIRE(batch[s].speed == speeds[s]);
    REQUIRE(batch[s].t.size() == one.t.size());
    REQUIRE(batch[s].summary.n_steps == one.summary.n_steps);
    REQUIRE(batch[s].t[batch[s].t.size() - 1] == Approx(one.t[one.t.size() - 1]).epsilon(1e-14));
    REQUIRE(batch[s].stations.size() == one.stations.size());
    for (std::size_t j = 0; j < one.stations.size(); ++j) {
      const StationHistory &b = batch[s].stations[j], &r = one.stations[j];
      REQUIRE(peak(r.acc_filt) > 0.0);
      REQUIRE(b.rail_disp.size() == r.rail_disp.size());
      REQUIRE(peak(b.disp - r.disp) <= 1e-9 * peak(r.disp));
      REQUIRE(peak(b.acc - r.acc) <= 1e-9 * peak(r.acc));
      REQUIRE(peak(b.acc_filt - r.acc_filt) <= 1e-9 * peak(r.acc_filt));
      REQUIRE(peak(b.rail_disp - r.rail_disp) <= 1e-9 * peak(r.rail_disp));
    }
  }
}

TEST_CASE("a Newmark sweep runs in batches and a failing speed costs only itself") {
  Scenario sc = short_track();
  // 1e-4 m/s would record more than kMaxHistoryBytes: refused, inside a batch of four.
  sc.sweep_speeds = {40.0, 1e-4, 60.0, 80.0, 99.0};
  SweepOptions o;
  o.threads = 2;
  const SweepResult r = run_sweep({{"reference", sc}}, o);
  REQUIRE(r.failures.size() == 1);
  REQUIRE(r.failures[0].speed == 1e-4);
  REQUIRE(r.failures[0].message.find("GiB of histories") != std::string::npos);
  REQUIRE(r.rows.size() == 4 * sc.stations.size());
  // The same rows as single runs.
  const PreparedModel pm = prepare_model(sc, false);
  for (const auto& row : r.rows) {
    if (row.station != sc.stations[0].name) continue;
    const auto p = peaks(simulate(pm, sc.trains[0], row.speed, sc.settings));
    REQUIRE(row.max_abs_acc == Approx(p[0].max_abs_acc).epsilon(1e-9));
    REQUIRE(row.max_abs_disp == Approx(p[0].max_abs_disp).epsilon(1e-9));
  }
}
