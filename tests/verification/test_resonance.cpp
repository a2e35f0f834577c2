#include <catch2/catch.hpp>
#include <cstdio>

#include "helpers.hpp"
#include "viaduct/study/sweep.hpp"

using namespace viaduct;

TEST_CASE("the artificial train's resonance peaks sit at v_j = f1 d / j") {
  // Old Guadiana bridge (both spans, elastic bearings) without track to keep the sweep short,
  // under the paper's 20 x 210 kN train, d = 18 m.
  study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
  sc.track.reset();
  sc.settings.free_vibration_s = 0.5;
  // Keep only the fundamental (1-15 Hz): v_j = f1 d / j predicts its resonances; with 1-60 Hz the
  // third span mode's own resonances (f3 d / j', f3 ≈ 40 Hz) sit within ±12 % of v_2.
  sc.settings.filter.cheby.high_hz = 15.0;
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const double f1 = model::compute_modes(s, 1).frequency_hz[0];
  const double d = 18.0;
  for (int j : {2, 3}) {
    const double vj = f1 * d / j;
    study::Scenario one = sc;
    one.sweep_speeds.clear();
    for (int i = -12; i <= 12; ++i) one.sweep_speeds.push_back(vj * (1 + 0.01 * i));  // ±12 % in 1 % steps
    study::SweepOptions opt;
    opt.threads = 2;
    const auto r = study::run_sweep({{"reference", one}}, opt);
    REQUIRE(r.failures.empty());
    double best_v = 0, best_a = 0, edge_a = 0;
    for (const auto& row : r.rows) {
      if (row.station != "S1_mid") continue;
      if (row.max_abs_acc > best_a) {
        best_a = row.max_abs_acc;
        best_v = row.speed;
      }
      if (row.speed == one.sweep_speeds.front() || row.speed == one.sweep_speeds.back()) edge_a = std::max(edge_a, row.max_abs_acc);
    }
    std::printf("resonance j = %d: predicted %.2f km/h, peak at %.2f km/h (%+.1f %%), %.3f m/s2 vs %.3f at +-12 %%\n", j,
                vj * 3.6, best_v * 3.6, 100 * (best_v / vj - 1), best_a, edge_a);
    REQUIRE(std::abs(best_v / vj - 1) <= 0.021);  // the 1 % speed grid plus damping's small shift
    // A real peak, not a monotonic trend: an interior maximum clearly above both ends (with
    // 1.565 % damping and 20 loads the peak is broad, about 1.2x the values at ±12 %).
    REQUIRE(best_v > one.sweep_speeds.front());
    REQUIRE(best_v < one.sweep_speeds.back());
    REQUIRE(best_a > 1.1 * edge_a);
  }
}
