#include <catch2/catch.hpp>

#include "viaduct/study/vehicle_ladder.hpp"

using namespace viaduct;

namespace ladder_unit {

// Two AVE coaches over a 25 m span (REFERENCE.md section 8's beam), 1 % modal damping.
study::Scenario ladder_scenario() {
  study::Scenario sc;
  sc.bridge.spans = {model::SpanParams{25.0, 3.5e10 * 1.3901, 18358.0}};
  sc.bridge.element_size = 0.5;
  sc.bridge.damping.ratio = 0.01;
  load::CoachSpec c;
  c.name = "AVE S103";
  c.body_mass = 47800, c.body_pitch_inertia = 1957888, c.bogie_spacing = 17.375, c.bogie_mass = 3500;
  c.bogie_pitch_inertia = 1715, c.wheelbase = 2.5, c.wheelset_mass = 1800, c.primary_k = 2.4e6, c.primary_c = 2e4;
  c.secondary_k = 7e5, c.secondary_c = 4e4, c.length = 25.0;
  sc.trains = {load::coach_train("2 AVE", c, 2)};
  sc.stations = {{"mid", true, 0, 12.5, 0.0}};
  sc.settings.free_vibration_s = 0.5;
  sc.settings.filter.cheby.high_hz = 30.0;
  return sc;
}

}  // namespace ladder_unit

using namespace ladder_unit;

TEST_CASE("the vehicle ladder runs every rung a train allows, on both paths, against the richest") {
  study::Scenario sc = ladder_scenario();
  sc.settings.irregularity.spectrum = "fra5";
  const study::LadderResult r = study::vehicle_ladder(sc, sc.trains[0], 250 / 3.6, 60.0);
  REQUIRE(r.rows.size() == 8);  // forces, sprung, multibody, multibody + profile; Newmark and modal each
  CHECK(r.rows[0].rung == "forces");
  CHECK(r.rows[6].rung == "multibody + profile");
  CHECK(r.richest == 6);
  for (const auto& row : r.rows) {
    INFO(row.rung << " " << solve::method_name(row.method));
    REQUIRE(row.error.empty());
    CHECK(row.vehicle.present == (row.rung != "forces"));
    CHECK(row.n_modes == (row.method == study::Method::modal ? row.n_modes : 0));
  }
  CHECK(r.rows[6].acc_vs_richest[0] == 0.0);
  // The profile shakes the deck: the smooth rungs differ from the richest by more than the fast
  // path does from the full one (measured: -45 % and 0.3 %).
  CHECK(std::abs(r.rows[4].acc_vs_richest[0]) > 0.1);
  CHECK(std::abs(r.rows[7].acc_vs_richest[0]) < 0.02);
  CHECK(r.rows[7].n_modes > 0);
}

TEST_CASE("a rung that fails is recorded and the others complete") {
  study::Scenario sc = ladder_scenario();
  sc.settings.vehicle.wheel_radius = -0.4;  // the Hertz stiffness of the vehicle rungs cannot be formed
  const study::LadderResult r = study::vehicle_ladder(sc, sc.trains[0], 200 / 3.6, 0.0);
  REQUIRE(r.rows.size() == 3);
  CHECK(r.rows[0].error.empty());
  CHECK_THAT(r.rows[1].error, Catch::Contains("wheel_radius"));
  CHECK_THAT(r.rows[2].error, Catch::Contains("wheel_radius"));
  CHECK(r.richest == 0);  // only the forces ran
}
