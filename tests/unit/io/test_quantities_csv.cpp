// load_effects.csv (write_quantities_csv): its rows formatted on threads in blocks, the same file
// for any thread count, each cell as printf's %.10g writes it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
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
