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
