// load_effects.csv (write_quantities_csv): its rows formatted on threads in blocks, the same file
// for any thread count, each cell as printf's %.10g writes it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "../scratch.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/study/scenario.hpp"
#include "viaduct/study/sweep.hpp"

namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string g10(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", x);
  return b;
}

// Two variants with a factor each (the second's label holds a comma and a quote) and n rows over
// them: values of every sign and magnitude, a quasi-static of 0 (phi_dyn empty) every 7th row, a
// train name with a comma.
struct Table {
  std::vector<viaduct::study::Variant> variants;
  std::vector<viaduct::study::QuantityRow> rows;
  explicit Table(std::size_t n) {
    variants.resize(2);
    variants[0].label = "reference";
    variants[0].factors = {{"bearings.k", 1.0}};
    variants[1].label = "k x0.5, \"soft\"";
    variants[1].factors = {{"bearings.k", 0.5}};
    rows.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      viaduct::study::QuantityRow& r = rows[k];
      r.variant = variants[k % 2].label;
      r.train = k % 3 ? "HSLM-A" + std::to_string(k % 10 + 1) : "ICE 3, 8 cars";
      r.quantity = "L_" + std::to_string(k % 31) + "_moment_Nm";
      r.speed = 38.0 + 0.01 * static_cast<double>(k);
      const double x = std::sin(0.37 * static_cast<double>(k)) * std::pow(10.0, static_cast<double>(k % 17) - 8.0);
      r.dynamic = {std::abs(x) * 1.25, -std::abs(x) / 3.0};
      r.quasi_static = k % 7 ? viaduct::study::EffectPeak{std::abs(x), 0.0} : viaduct::study::EffectPeak{};
    }
  }
};

}  // namespace

TEST_CASE("load_effects.csv: the same file on 1, 2 and 3 threads, across several waves of blocks") {
  // 2048 rows a block, 8 blocks a thread a wave: 40 000 rows are three waves on two threads and a
  // partial block at the end.
  const Table t(40000);
  vt::ScratchDir dir("quantities");
  std::vector<std::string> text;
  for (int n : {1, 2, 3}) {
    const std::string path = (dir.p / ("q" + std::to_string(n) + ".csv")).string();
    viaduct::io::write_quantities_csv(path, t.rows, t.variants, n);
    text.push_back(read_all(path));
  }
  REQUIRE(!text[0].empty());
  CHECK(text[1] == text[0]);
  CHECK(text[2] == text[0]);
  // Every line is the header or a row, in the rows' order, each number as %.10g writes it.
  std::istringstream in(text[0]);
  std::string line;
  std::getline(in, line);
  CHECK(line == "variant,bearings.k_factor,train,speed_kmh,quantity,max,min,max_abs,quasi_static_max,quasi_static_min,phi_dyn");
  std::size_t k = 0;
  for (; std::getline(in, line); ++k) {
    REQUIRE(k < t.rows.size());
    const viaduct::study::QuantityRow& r = t.rows[k];
    const std::string label = k % 2 ? "\"k x0.5, \"\"soft\"\"\"" : "reference";
    const std::string train = k % 3 ? r.train : "\"" + r.train + "\"";
    const double phi = r.phi_dyn();
    const std::string expected = label + "," + g10(k % 2 ? 0.5 : 1.0) + "," + train + "," + g10(r.speed * 3.6) + "," +
                                 r.quantity + "," + g10(r.dynamic.max) + "," + g10(r.dynamic.min) + "," +
                                 g10(r.dynamic.max_abs()) + "," + g10(r.quasi_static.max) + "," +
                                 g10(r.quasi_static.min) + "," + (std::isnan(phi) ? std::string() : g10(phi));
    if (line != expected) FAIL("row " << k << ": '" << line << "' against '" << expected << "'");
  }
  CHECK(k == t.rows.size());
}

TEST_CASE("load_effects.csv: a row of an unknown variant is refused, naming the table, and no file is left") {
  Table t(5000);
  t.rows[4321].variant = "Kp x9";
  vt::ScratchDir dir("quantities-bad");
  const std::string path = (dir.p / "load_effects.csv").string();
  for (int n : {1, 2}) {
    CHECK_THROWS_WITH(viaduct::io::write_quantities_csv(path, t.rows, t.variants, n),
                      Catch::Contains("load_effects.csv") && Catch::Contains("Kp x9"));
    CHECK_FALSE(std::filesystem::exists(path));
  }
}

TEST_CASE("load_effects.csv: values repeated across rows (speeds, quasi-static extremes) and max_abs of every sign, as printf writes them") {
  // The layout of a sweep: per train, per speed, per quantity, so that a speed repeats on the
  // rows of its case and a quantity's quasi-static extremes on every speed; 300 quantities give
  // 600 such values a train, more than the writer's table of values met before holds (entries
  // replaced and found again). max_abs = max(max, −min) is max, or −min of either sign; NaN,
  // infinities and signed zeros among them.
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<double, double>> special = {{1.5, -2.25},  {-3.0, 0.5},  {0.0, -0.0},  {-0.0, 0.0},
                                                          {-0.0, -0.0}, {nan, -1.0},  {2.0, nan},   {inf, -inf},
                                                          {-inf, inf},  {1e-300, -1e300}, {-7.0, -8.0}, {4e21, 3.0}};
  std::vector<viaduct::study::Variant> variants(1);
  variants[0].label = "reference";
  std::vector<viaduct::study::QuantityRow> rows;
  for (int t = 0; t < 2; ++t)
    for (int s = 0; s < 12; ++s)
      for (int q = 0; q < 300; ++q) {
        viaduct::study::QuantityRow r;
        r.variant = "reference";
        r.train = "HSLM-A" + std::to_string(t + 1);
        r.quantity = "L_" + std::to_string(q) + "_shear_N";
        r.speed = (140.0 + 5.0 * s) / 3.6;
        const double x = std::sin(0.1 * q + t) * std::pow(10.0, q % 9 - 4.0);
        const std::size_t k = rows.size();
        r.dynamic = k % 5 ? viaduct::study::EffectPeak{x * (1.0 + 0.01 * s), -x * (0.9 + 0.02 * s)}
                          : viaduct::study::EffectPeak{special[k / 5 % special.size()].first, special[k / 5 % special.size()].second};
        r.quasi_static = {std::abs(x), q % 4 ? -std::abs(x) / 7.0 : 0.0};
        rows.push_back(r);
      }
  vt::ScratchDir dir("quantities-repeat");
  const std::string path = (dir.p / "load_effects.csv").string();
  viaduct::io::write_quantities_csv(path, rows, variants, 2);
  std::istringstream in(read_all(path));
  std::string line;
  std::getline(in, line);
  std::size_t k = 0, from_min = 0, negated = 0;
  for (; std::getline(in, line); ++k) {
    REQUIRE(k < rows.size());
    const viaduct::study::QuantityRow& r = rows[k];
    const double phi = r.phi_dyn(), y = r.dynamic.max_abs();
    if (!(y == r.dynamic.max) && !std::isnan(y)) ++from_min, negated += !std::signbit(r.dynamic.min);
    const std::string expected = "reference," + r.train + "," + g10(r.speed * 3.6) + "," + r.quantity + "," +
                                 g10(r.dynamic.max) + "," + g10(r.dynamic.min) + "," + g10(y) + "," +
                                 g10(r.quasi_static.max) + "," + g10(r.quasi_static.min) + "," +
                                 (std::isnan(phi) ? std::string() : g10(phi));
    if (line != expected) FAIL("row " << k << ": '" << line << "' against '" << expected << "'");
  }
  CHECK(k == rows.size());
  // Both ways of writing −min were taken.
  CHECK(from_min > 100);
  CHECK(negated > 10);
}
