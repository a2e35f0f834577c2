#include <catch2/catch.hpp>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/study/fatigue.hpp"

using namespace viaduct;
using namespace viaduct::study;

TEST_CASE("EN 1993-1-9's S-N curve: its knees and slopes, and nothing below the cut-off") {
  const SnCurve c = SnCurve::en1993_1_9(71);
  const double dc = 71e6, dd = dc * std::cbrt(2.0 / 5.0), dl = dd * std::pow(0.05, 0.2);
  CHECK(c.cycles(dc) == Approx(2e6).epsilon(1e-12));
  CHECK(c.cycles(dd) == Approx(5e6).epsilon(1e-12));
  CHECK(c.cycles(dl) == Approx(1e8).epsilon(1e-12));
  CHECK(c.cycles(2 * dc) == Approx(2e6 / 8).epsilon(1e-12));       // m = 3 above Δσ_D
  CHECK(c.cycles(0.5 * (dd + dl)) == Approx(5e6 * std::pow(dd / (0.5 * (dd + dl)), 5)).epsilon(1e-12));  // m = 5
  CHECK(std::isinf(c.cycles(0.999 * dl)));
  CHECK(std::isinf(c.cycles(0.0)));
  CHECK(equivalent_range_2e6(1.0, c) == Approx(dc).epsilon(1e-12));
  CHECK_THROWS_WITH(SnCurve::en1993_1_9(75), Catch::Contains("not one of EN 1993-1-9's: 36, 40"));
  SnCurve bad = c;
  bad.knee_s = {1e6, 2e6};
  CHECK_THROWS_WITH(bad.validate(), Catch::Contains("ranges descend"));
}

TEST_CASE("Miner's sum of a constant-amplitude history is n / N, with units and partial factors") {
  // A sine of 1000 periods in microstrain, range 400 µε on steel (E = 210 GPa): 84 MPa, against
  // detail category 71: 999.5 cycles of that range (the ends are two half cycles of half of it).
  const int periods = 1000, per = 20;
  Vector x(periods * per + 1);
  for (Index k = 0; k < x.size(); ++k) x[k] = 200.0 * std::sin(2 * M_PI * static_cast<double>(k) / per);
  const SnCurve c = SnCurve::en1993_1_9(71);
  MinerSum d(c, 210e9 * 1e-6);
  for (const auto& cy : signal::rainflow(x)) d.add(cy);
  const double expected = 999.5 / c.cycles(84e6) + 1.0 / c.cycles(42e6);
  CHECK(d.damage == Approx(expected).epsilon(1e-12));
  CHECK(d.damage == Approx(999.5 * std::pow(84.0 / 71.0, 3) / 2e6 + std::pow(42e6 / (71e6 * std::cbrt(0.4)), 5) / 5e6).epsilon(1e-9));
  CHECK(d.cycles == Approx(1000.5));
  CHECK(d.max_range_pa == Approx(84e6));
  // γFf·γMf = 1.35 scales every range: the m = 3 branch's damage by 1.35³.
  MinerSum f(c, 210e9 * 1e-6, 1.0, 1.35);
  for (const auto& cy : signal::rainflow(x)) f.add(cy);
  CHECK(f.damage > 2.4 * d.damage);
  CHECK_THROWS_AS(MinerSum(c, 0.0), InputError);
  CHECK_THROWS_AS(MinerSum(c, 1.0, 0.9), InputError);
}

TEST_CASE("a traffic mix's damage: each train's passage counted, times its trains a day and 365 days") {
  // One axle crawling (0.5 m/s) over a 10 m span: the mid-span moment rises to P L / 4 and falls
  // back, one cycle of that range (two half cycles), the vibration's small ranges below the
  // cut-off. W is chosen so that a 100 kN axle gives 250 kN·m / W = 125 MPa against detail 71:
  // D = (125/71)³ / 2e6 a passage. Tolerance 1.5 %: the FE moment at mid-span is within 0.2 % of
  // P L / 4 (0.6 % in D, the cube), and crawling adds about v / (2 f1 L) = 0.2 % of dynamics
  // (f1 = 11 Hz; at 2 m/s it was 0.75 %).
  Scenario sc;
  model::SpanParams span;
  span.length = 10.0;
  span.EI = 5e9;
  span.mass_per_m = 10000.0;
  sc.bridge.spans = {span};
  sc.bridge.element_size = 0.5;
  sc.bridge.damping.ratio = 0.02;
  sc.stations = {{"mid", true, 0, 5.0, 0.0}};
  sc.settings.dt = 2e-3;
  sc.settings.free_vibration_s = 0.5;
  sc.settings.filter.enabled = false;
  const PreparedModel pm = prepare_model(sc, true, /*with_load_effects=*/true);
  std::size_t moment = pm.effects.size();
  for (std::size_t i = 0; i < pm.effects.size(); ++i)
    if (pm.effects[i].name == "mid_moment_Nm") moment = i;
  REQUIRE(moment < pm.effects.size());
  TrafficMix mix;
  mix.trains = {{"light", load::regular_train("light", 1, 10.0, 100e3), 10.0, 0.5},
                {"heavy", load::regular_train("heavy", 1, 10.0, 140e3), 1.0, 0.5}};
  FatigueCount f;
  f.curve = SnCurve::en1993_1_9(71);
  const double w = 250e3 / 125e6;  // [m³]
  const MixDamage d = traffic_damage(pm, sc.settings, moment, 1.0 / w, mix, f, 2);
  REQUIRE(d.trains.size() == 2);
  REQUIRE(d.n_failed == 0);
  for (int k = 0; k < 2; ++k) {
    const TrainDamage& t = d.trains[static_cast<std::size_t>(k)];
    INFO(t.name);
    REQUIRE(t.passage);
    const double range = (k == 0 ? 100e3 : 140e3) * 10.0 / 4.0 / w;  // [Pa]
    CHECK(t.passage->miner.max_range_pa == Approx(range).epsilon(0.005));
    CHECK(t.passage->miner.damage == Approx(std::pow(range / 71e6, 3) / 2e6).epsilon(0.015));
    CHECK(t.per_year == Approx(t.passage->miner.damage * mix.trains[static_cast<std::size_t>(k)].per_day * 365.0).epsilon(1e-12));
  }
  CHECK(d.per_year == Approx(d.trains[0].per_year + d.trains[1].per_year).epsilon(1e-12));
  CHECK(d.years_to_d1() == Approx(1.0 / d.per_year).epsilon(1e-12));
  // A train that cannot run (its speed refused) is recorded, the rest summed, the count said.
  mix.trains[1].speed = -1.0;
  const MixDamage bad = traffic_damage(pm, sc.settings, moment, 1.0 / w, mix, f, 1);
  CHECK(bad.n_failed == 1);
  CHECK_FALSE(bad.trains[1].passage);
  CHECK_FALSE(bad.trains[1].error.empty());
  CHECK(bad.per_year == Approx(d.trains[0].per_year).epsilon(1e-12));
  CHECK_THROWS_AS(traffic_damage(pm, sc.settings, pm.effects.size(), 1.0, mix, f, 1), InputError);
}
