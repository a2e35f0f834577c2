// Measured rail profiles (issue #21 part 3): read as surveys and recording cars write them, and
// refused with file, line and column where they cannot be a profile.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/io/profile.hpp"
#include "../scratch.hpp"

using namespace viaduct;

namespace {
std::string profile_error_of(const std::string& path) {
  try {
    io::read_rail_profile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("a measured rail profile: units converted, the step and start taken, rounding of positions accepted") {
  vt::ScratchDir d("profile");
  std::string text = "# track recording car, run 3\nx [m],level [mm]\n";
  char buf[64];
  for (int i = 0; i < 200; ++i) {
    // positions written to 4 decimals of a 0.25 m step from 1200.5 m: exact; levels in mm
    std::snprintf(buf, sizeof buf, "%.4f,%.3f\n", 1200.5 + 0.25 * i, 2.0 * std::sin(0.05 * i));
    text += buf;
  }
  const load::RailProfile p = io::read_rail_profile(d.write("p.csv", text));
  CHECK(p.x0 == 1200.5);
  CHECK(p.dx == Approx(0.25).epsilon(1e-12));
  REQUIRE(p.z.size() == 200);
  for (int i = 0; i < 200; ++i) CHECK(p.z[i] == Approx(1e-3 * (std::round(2000.0 * std::sin(0.05 * i)) / 1000.0)).margin(1e-12));
  CHECK(p.at(1200.5 + 0.25 * 7) == p.z[7]);
  // Suffix units, metres both.
  const load::RailProfile q = io::read_rail_profile(d.write("q.csv", "x_m,z_m\n0,0.001\n0.5,0.002\n1,0.003\n1.5,0.004\n"));
  CHECK(q.dx == 0.5);
  CHECK(q.z[3] == 0.004);
}

TEST_CASE("a measured rail profile is refused, naming file, line and column, where it cannot be one") {
  vt::ScratchDir d("profile");
  CHECK(profile_error_of(d.write("a.csv", "x_m,z_mm,y_mm\n0,1,2\n")).find("a.csv:1: a rail profile has two columns") != std::string::npos);
  CHECK(profile_error_of(d.write("b.csv", "x_m,z_V\n0,1\n1,1\n2,1\n3,1\n")).find("b.csv:1: key 'z_V': column 'z_V': 'V' is not a length") !=
        std::string::npos);
  CHECK(profile_error_of(d.write("c.csv", "x_m,level\n0,1\n1,1\n2,1\n3,1\n")).find("column 'level': no unit") != std::string::npos);
  CHECK(profile_error_of(d.write("e.csv", "x_m,z_mm\n0,1\n1,1\n2,1\n")).find("e.csv:4: a rail profile needs at least 4 points, got 3") !=
        std::string::npos);
  CHECK(profile_error_of(d.write("f.csv", "x_m,z_mm\n0,1\n1,one\n2,1\n3,1\n")).find("f.csv:3: key 'z_mm': 'one' is not a number") !=
        std::string::npos);
  CHECK(profile_error_of(d.write("g.csv", "x_m,z_mm\n0,1\n1,1\n2.5,1\n3,1\n4,1\n")).find("g.csv:4: key 'x_m': position 2.5 m is off the uniform step") !=
        std::string::npos);
  CHECK(profile_error_of(d.write("h.csv", "x_m,z_mm\n0,1\n2,1\n1,1\n3,1\n")).find("h.csv:4: key 'x_m': position 1 m does not follow 2 m") !=
        std::string::npos);
  CHECK(profile_error_of(d.write("i.csv", "x_m,z_mm\n3,1\n2,1\n1,1\n0,1\n")).find("i.csv:3: key 'x_m': position 2 m does not follow 3 m") !=
        std::string::npos);
  CHECK(profile_error_of((d.p / "none.csv").string()).find("cannot open") != std::string::npos);
}
