#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/rainflow.hpp"

using namespace viaduct;
using namespace viaduct::signal;

namespace {

// Counts per range (ranges of the examples are integers).
std::map<long, double> by_range(const std::vector<Cycle>& cs) {
  std::map<long, double> m;
  for (const auto& c : cs) m[std::lround(c.range)] += c.count;
  return m;
}

Vector of(std::initializer_list<double> v) {
  Vector x(static_cast<Index>(v.size()));
  Index i = 0;
  for (double d : v) x[i++] = d;
  return x;
}

}  // namespace

TEST_CASE("rainflow: ASTM E1049's example, by the three-point and the four-point method") {
  // ASTM E1049-85 §5.4.4, Fig. 6 / Table 4: ranges 3 (0.5), 4 (1.5), 6 (0.5), 8 (1.0), 9 (0.5).
  const Vector x = of({-2, 1, -3, 5, -1, 3, -4, 4, -2});
  const std::map<long, double> astm = {{3, 0.5}, {4, 1.5}, {6, 0.5}, {8, 1.0}, {9, 0.5}};
  for (const RainflowMethod m : {RainflowMethod::three_point, RainflowMethod::four_point}) {
    const std::vector<Cycle> cs = rainflow(x, m);
    INFO((m == RainflowMethod::three_point ? "three-point" : "four-point"));
    CHECK(by_range(cs) == astm);
  }
  // The three-point method's cycles in the standard's order and with their means: the half
  // cycles -2..1 and 1..-3 through the starting point, the whole cycle -1..3, then -3..5.
  const std::vector<Cycle> cs = rainflow(x);
  REQUIRE(cs.size() == 7);
  CHECK(cs[0].range == 3);
  CHECK(cs[0].mean == -0.5);
  CHECK(cs[0].count == 0.5);
  CHECK(cs[2].range == 4);
  CHECK(cs[2].mean == 1);
  CHECK(cs[2].count == 1.0);
  CHECK(cs[3].range == 8);
  CHECK(cs[3].mean == 1);
  CHECK(cs[3].count == 0.5);
}

TEST_CASE("rainflow: a sine of N periods is N cycles of twice its amplitude, and samples between turning points change nothing") {
  const int periods = 50, per = 40;
  Vector x(periods * per + 1);
  for (Index k = 0; k < x.size(); ++k) x[k] = 2.5 * std::sin(2 * M_PI * static_cast<double>(k) / per);
  double n = 0.0, other = 0.0;
  for (const auto& c : rainflow(x)) (std::abs(c.range - 5.0) < 1e-12 ? n : other) += c.count;
  // From 0 up to +A, down to -A, …, back to 0: the 2N − 1 ranges of 2A make N − 1 whole cycles
  // and one half; the first and last ranges (0 to A, −A to 0) are half cycles of range A.
  CHECK(n == Approx(periods - 0.5).epsilon(1e-12));
  CHECK(other == 1.0);  // two half cycles of range A at the ends
  // The same history with every sample doubled and extra points along each rise and fall.
  std::vector<double> dense;
  for (Index k = 0; k + 1 < x.size(); ++k) {
    dense.push_back(x[k]);
    dense.push_back(x[k]);
    dense.push_back(0.5 * (x[k] + x[k + 1]));
  }
  dense.push_back(x[x.size() - 1]);
  CHECK(by_range(rainflow(Eigen::Map<const Vector>(dense.data(), static_cast<Index>(dense.size())))) == by_range(rainflow(x)));
}

TEST_CASE("rainflow: streaming in blocks counts what the whole history counts, holding only the residue") {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  Vector x(200000);
  double ar = 0.0;
  for (Index k = 0; k < x.size(); ++k) x[k] = ar = 0.9 * ar + g(rng);  // a band-limited random history
  for (const RainflowMethod m : {RainflowMethod::three_point, RainflowMethod::four_point}) {
    const std::vector<Cycle> whole = rainflow(x, m);
    std::vector<Cycle> streamed;
    std::size_t most_open = 0;
    Rainflow r([&](const Cycle& c) { streamed.push_back(c); }, m);
    for (Index k = 0; k < x.size(); k += 997) {
      r.push(Vector(x.segment(k, std::min<Index>(997, x.size() - k))));
      most_open = std::max(most_open, r.n_open());
    }
    r.finish();
    REQUIRE(streamed.size() == whole.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < whole.size(); ++i) differ += streamed[i].range != whole[i].range || streamed[i].count != whole[i].count;
    CHECK(differ == 0);
    // Every range between two turning points is counted once: as a half cycle, or as one of the
    // two ranges of a whole cycle. So 2 Σ counts = turning points − 1.
    Index turning = 1;
    for (Index k = 1; k + 1 < x.size(); ++k) turning += (x[k] - x[k - 1]) * (x[k + 1] - x[k]) < 0.0;
    ++turning;  // the last sample
    double twice = 0.0;
    for (const auto& c : whole) twice += 2.0 * c.count;
    CHECK(twice == Approx(static_cast<double>(turning - 1)));
    CHECK(most_open < 64);  // memory: the residue of a stationary history stays small
  }
}

TEST_CASE("rainflow: hysteresis drops the reversals of noise, bad samples and bins are refused or counted, never dropped") {
  // A triangle wave of range 10 with ±0.2 of noise on every sample: with a hysteresis of 1 its
  // cycles are the triangle's.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  Vector x(2001);
  for (Index k = 0; k < x.size(); ++k) {
    const double ph = std::fmod(static_cast<double>(k), 100.0) / 100.0;
    x[k] = (ph < 0.5 ? 20 * ph : 20 * (1 - ph)) - 5 + u(rng);
  }
  double big = 0.0, small = 0.0;
  for (const auto& c : rainflow(x, RainflowMethod::three_point, 1.0)) (c.range > 9 ? big : small) += c.count;
  // 20 periods: 19½ whole-range cycles plus the ends' halves, which the noise at the first and
  // last sample may put just under or over 9 (so ±½ cycle), and at most the two end halves small.
  CHECK(big == Approx(20.0).margin(0.51));
  CHECK(small <= 1.0);
  double noisy = 0.0;
  for (const auto& c : rainflow(x)) noisy += c.count;
  CHECK(noisy > 100.0);  // without it, every wiggle is a cycle
  Vector bad = of({0, 1, NAN, 2});
  CHECK_THROWS_WITH(rainflow(bad), Catch::Contains("sample 2 is not finite"));
  CHECK_THROWS_AS(rainflow(x, RainflowMethod::three_point, -1.0), InputError);
  CHECK_THROWS_WITH(CycleHistogram({0, 2, 1}), Catch::Contains("must ascend"));
  CHECK_THROWS_WITH(CycleHistogram({-1, 2}), Catch::Contains("range edges >= 0"));
  CycleHistogram h({0, 4, 8}, {-2, 0, 2});
  for (const auto& c : rainflow(of({-2, 1, -3, 5, -1, 3, -4, 4, -2}))) h.add(c);
  CHECK(h.counts.sum() + h.outside == Approx(4.0));  // every count is somewhere
  CHECK(h.outside == 0.5);                           // range 9, beyond the last edge
  CHECK(h.counts(0, 0) == 0.5);                       // range 3, mean −0.5
  CHECK(h.counts(1, 0) == 0.5);                       // range 4, mean −1
  CHECK(h.counts(1, 1) == 2.5);                       // ranges 4 (1), 8 (0.5 + 0.5: the last edge is closed), 6 (0.5)
}
