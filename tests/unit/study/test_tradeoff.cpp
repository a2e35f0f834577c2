#include <catch2/catch.hpp>

#include "viaduct/study/tradeoff.hpp"

using namespace viaduct;
using namespace viaduct::study;

TEST_CASE("tradeoff: a rung equal to the reference has zero error, a coarser one does not") {
  Scenario sc;
  sc.bridge.spans = {{12.0, 5e9, 10000.0}};
  sc.bridge.element_size = 1.0;
  sc.bridge.damping.ratio = 0.02;
  sc.trains = {load::regular_train("t3", 3, 10.0, 100e3)};
  sc.stations = {{"mid", true, 0, 6.0, 0.0}, {"q", true, 0, 3.0, 0.0}};
  sc.settings.dt = 1e-3;
  sc.settings.free_vibration_s = 0.2;
  sc.sweep_speeds = {20.0, 35.0, 50.0};
  const RunSettings ref = reference_settings(sc);
  REQUIRE(ref.dt == Approx(2.5e-4));
  RunSettings coarse = ref;
  coarse.dt = 2e-3;
  RunSettings modal = ref;
  modal.method = Method::modal;
  modal.modal.n_modes = 2;
  const TradeoffResult r = run_tradeoff(sc, ref, {{"same", ref}, {"coarse", coarse}, {"modal", modal}}, 2);
  REQUIRE(r.rungs.size() == 3);
  REQUIRE(r.rungs[0].max_acc_error == 0.0);  // identical arithmetic
  REQUIRE(r.rungs[0].max_disp_error == 0.0);
  REQUIRE(r.rungs[1].max_acc_error > 1e-3);  // an 8x coarser step is visibly off
  REQUIRE(r.rungs[1].max_acc_error < 0.5);
  REQUIRE(r.rungs[2].n_modes == 2);
  REQUIRE(r.rungs[1].station_acc_error.size() == 2);
  REQUIRE(r.rungs[1].max_acc_error == std::max(r.rungs[1].station_acc_error[0], r.rungs[1].station_acc_error[1]));
  // The default ladder has the dt rungs, both static-correction variants of each basis, two bases
  // without damping vectors and the presets.
  const auto ladder = default_ladder(sc);
  REQUIRE(ladder.size() == 4 + 10 + 2 + 2);
  REQUIRE(default_ladder(sc, true).size() == ladder.size() + 3);
}
