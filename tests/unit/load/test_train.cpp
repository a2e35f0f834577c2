#include <catch2/catch.hpp>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/load/moving_loads.hpp"
#include "viaduct/load/train.hpp"

using namespace viaduct;
using namespace viaduct::load;

TEST_CASE("HSLM-A trains: axle count, length and total load (REFERENCE.md §3)") {
  const Train a1 = hslm_a("HSLM-A1", hslm_a_row(1));
  REQUIRE(a1.n_axles() == 50);
  REQUIRE(a1.length() == Approx(397.525).epsilon(1e-12));
  REQUIRE(a1.total_load() == Approx(8500e3).epsilon(1e-12));
  // Power car axles and the 3.525 m gap to the end coach.
  REQUIRE(a1.offset[3] == 17.0);
  REQUIRE(a1.offset[4] == Approx(20.525));
  // Symmetric train: the offsets read the same from the tail.
  for (std::size_t i = 0; i < a1.n_axles(); ++i)
    REQUIRE(a1.offset[i] + a1.offset[a1.n_axles() - 1 - i] == Approx(a1.length()).epsilon(1e-12));
  for (int n = 1; n <= 10; ++n) {
    const HslmRow r = hslm_a_row(n);
    const Train t = hslm_a("A", r);
    INFO("A" << n);
    REQUIRE(t.n_axles() == static_cast<std::size_t>(2 * r.n_coaches + 14));
    // First to last axle: two power cars (17 m), two 3.525 m gaps, (N + 2) coach lengths
    // between the couplings minus the two half gaps.
    REQUIRE(t.length() == Approx(2 * 17.0 + 3.525 + (r.n_coaches + 2) * r.coach_length).epsilon(1e-12));
    // Articulated bogies are D apart (characteristic distance of the train).
    REQUIRE(t.offset[8] - t.offset[6] == Approx(r.coach_length).epsilon(1e-12));
  }
  REQUIRE_THROWS_AS(hslm_a_row(11), InputError);
  REQUIRE(hslm_a_row(2).bogie_spacing == 3.5);
  REQUIRE(hslm_a_row(10).axle_load == 210e3);
}

TEST_CASE("regular trains and validation") {
  const Train t = regular_train("x", 20, 18.0, 210e3);
  REQUIRE(t.n_axles() == 20);
  REQUIRE(t.length() == Approx(342.0));
  REQUIRE(t.total_load() == Approx(4200e3));
  REQUIRE_THROWS_AS(regular_train("x", 0, 18.0, 1.0), InputError);
  REQUIRE_THROWS_AS(regular_train("x", 2, 18.0, -1.0), InputError);
  Train bad = t;
  bad.offset[3] = 1.0;  // goes backwards
  REQUIRE_THROWS_WITH(bad.validate(), Catch::Contains("must not decrease"));
}

TEST_CASE("moving loads: consistent nodal forces, entry and exit") {
  model::BridgeParams b;
  b.spans = {{10.0, 1e9, 5000.0}};
  b.element_size = 1.0;
  b.damping.kind = model::DampingKind::none;
  const model::Structure s = model::build_structure(b, std::nullopt);
  const Train t = regular_train("two", 2, 3.0, 100e3);
  const MovingLoads ml(s, t, 10.0, 0.5);
  REQUIRE(ml.t_exit() == Approx((10.0 + 3.0) / 10.0));
  Vector f = Vector::Zero(s.n_dofs);
  // Sum of the vertical nodal forces (w DOFs) equals the load on the span, and the moment about
  // x = 0 equals Σ P x (a consistent load is statically equivalent). Tolerance: round-off.
  auto check = [&](double time, double expect_force, double expect_moment) {
    f.setZero();
    ml.add_to(time, f);
    double F = 0.0, Mo = 0.0;
    for (std::size_t i = 0; i < s.deck_elements.size(); ++i) {
      const auto& e = s.deck_elements[i];
      if (e.dofs[0] >= 0) {
        F += f[e.dofs[0]];
        Mo += f[e.dofs[0]] * e.x0;
      }
      Mo += f[e.dofs[1]];  // a nodal moment (rotation DOF, θ = dw/dx) adds directly
      if (i + 1 == s.deck_elements.size()) {
        if (e.dofs[2] >= 0) {
          F += f[e.dofs[2]];
          Mo += f[e.dofs[2]] * (e.x0 + e.h);
        }
        Mo += f[e.dofs[3]];
      }
    }
    // Rigid supports drop the w DOFs at the span ends: the loads checked are more than one
    // element away from them, where those DOFs receive nothing.
    REQUIRE(F == Approx(expect_force).epsilon(1e-12));
    REQUIRE(Mo == Approx(expect_moment).epsilon(1e-12));
  };
  check(0.25, 50e3, 50e3 * 2.5);                     // first axle at 2.5 m, second not yet on
  check(0.75, 100e3, 50e3 * 7.5 + 50e3 * 4.5);       // both on
  f.setZero();
  ml.add_to(1.35, f);                                // both gone
  REQUIRE(f.cwiseAbs().maxCoeff() == 0.0);
  REQUIRE_THROWS_AS(MovingLoads(s, t, 0.0), InputError);
  REQUIRE_THROWS_AS(MovingLoads(s, t, -5.0), InputError);
}

TEST_CASE("characteristic distance: the spacing of a regular train, the coach length of HSLM-A") {
  // Regular trains add up equally at d, d/2, d/3...: the longest, d, is the one reported. 2 mm:
  // the 1 mm grid in λ.
  CHECK(characteristic_distance(regular_train("r", 20, 18.0, 210e3)) == Approx(18.0).margin(2e-3));
  CHECK(characteristic_distance(regular_train("r", 12, 13.14, 100e3)) == Approx(13.14).margin(2e-3));
  // HSLM-A: N coaches of length D between power cars; D governs (EN 1991-2 E.1).
  for (int i = 1; i <= 10; ++i) {
    INFO("HSLM-A" << i);
    const HslmRow row = hslm_a_row(i);
    CHECK(characteristic_distance(hslm_a("a", row)) == Approx(row.coach_length).margin(2e-3));
  }
  CHECK(characteristic_distance(regular_train("one", 1, 0.0, 1e5)) == 0.0);
}
