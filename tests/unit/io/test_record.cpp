#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "../scratch.hpp"

using namespace viaduct;
using namespace viaduct::io;
namespace fs = std::filesystem;

namespace {
struct Dir : vt::ScratchDir {
  Dir() : vt::ScratchDir("rec") {}
};
std::string error_of(const std::string& path) {
  try {
    read_record_csv(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("records with a time column or a declared rate") {
  Dir d;
  const Record a = read_record_csv(d.write("a.csv", "# logger X\nt_s,acc1_mps2,disp_mm\n0.5,1,2\n0.51,3,4\n0.52,5,6\n"));
  REQUIRE(a.fs_hz == Approx(100.0).epsilon(1e-12));
  REQUIRE(a.t0_s == 0.5);
  REQUIRE(a.channels == std::vector<std::string>{"acc1_mps2", "disp_mm"});
  REQUIRE(a.units == std::vector<std::string>{"mps2", "mm"});
  REQUIRE(a.data(2, 1) == 6.0);
  REQUIRE(a.channel("acc1") == 0);
  REQUIRE(a.channel("disp_mm") == 1);
  REQUIRE_THROWS_WITH(a.channel("x"), Catch::Contains("no channel 'x'"));
  const Record b = read_record_csv(d.write("b.csv", "# sampling_rate_hz = 4096\nch_g\n1\n2\n3\n"));
  REQUIRE(b.fs_hz == 4096.0);
  REQUIRE(b.n_samples() == 3);
  // Round trip.
  write_record_csv((d.p / "c.csv").string(), a, 17);
  const Record c = read_record_csv((d.p / "c.csv").string());
  REQUIRE(c.fs_hz == Approx(a.fs_hz).epsilon(1e-12));
  REQUIRE(c.data == a.data);
}

TEST_CASE("bad records give file, line and column, and nothing is repaired") {
  Dir d;
  const std::string h = "t_s,a_mps2,b_m\n";
  REQUIRE(error_of(d.write("nan.csv", h + "0,1,2\n0.1,nan,3\n")).find("nan.csv:3: column 'a_mps2': not a finite number") != std::string::npos);
  REQUIRE(error_of(d.write("empty.csv", h + "0,1,2\n0.1,,3\n")).find("empty.csv:3: column 'a_mps2'") != std::string::npos);
  REQUIRE(error_of(d.write("cols.csv", h + "0,1,2\n0.1,3\n")).find("cols.csv:3: expected 3 columns") != std::string::npos);
  REQUIRE(error_of(d.write("more.csv", h + "0,1,2,4\n")).find("more than the header's 3 columns") != std::string::npos);
  REQUIRE(error_of(d.write("back.csv", h + "0,1,2\n0.1,1,2\n0.05,1,2\n")).find("time does not increase at sample 3") != std::string::npos);
  REQUIRE(error_of(d.write("jitter.csv", h + "0,1,2\n0.1,1,2\n0.2,1,2\n0.35,1,2\n0.45,1,2\n")).find("irregular sampling at sample 4") != std::string::npos);
  REQUIRE(error_of(d.write("dup.csv", "t_s,a_m,a_m\n0,1,2\n1,1,2\n")).find("channel 'a_m' appears twice") != std::string::npos);
  REQUIRE(error_of(d.write("unit.csv", "t_s,a_furlong\n0,1\n1,1\n")).find("channel 'a_furlong' has no known unit suffix") != std::string::npos);
  REQUIRE(error_of(d.write("rate.csv", "a_m\n1\n2\n")).find("the sampling rate is unknown") != std::string::npos);
  REQUIRE(error_of(d.write("both.csv", "# sampling_rate_hz = 50\nt_s,a_m\n0,1\n0.01,2\n")).find("disagrees with the time column") != std::string::npos);
  REQUIRE(error_of(d.write("short.csv", h + "0,1,2\n")).find("at least 2 samples") != std::string::npos);
  REQUIRE(error_of(d.write("none.csv", "# only a comment\n")).find("no header line") != std::string::npos);
  REQUIRE(error_of(d.write("text.csv", h + "0,1,2x\n")).find("unexpected text") != std::string::npos);
  REQUIRE(error_of((d.p / "missing.csv").string()).find("cannot open record") != std::string::npos);
  // A file cut inside its last line says so; the same line with its newline does not, and a last
  // line without a newline but whole is read (hand-made files often end so).
  REQUIRE(error_of(d.write("cut.csv", h + "0,1,2\n0.1,1,2\n0.2,1")).find("cut.csv:4: expected 3 columns as in the header, got 2 (the file ends inside this line, without a newline: cut short?)") !=
          std::string::npos);
  REQUIRE(error_of(d.write("cols2.csv", h + "0,1,2\n0.1,1,2\n0.2,1\n")).find("cut short") == std::string::npos);
  REQUIRE(read_record_csv(d.write("whole.csv", h + "0,1,2\n0.1,1,2\n0.2,1,2")).n_samples() == 3);
}
