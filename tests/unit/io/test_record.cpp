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
  REQUIRE(a.fs_hz == 100.0);  // the 9-digit rate the stamps give within 1e-9
  REQUIRE(a.t0_s == 0.5);
  // Channels in viaduct's units: mm read as m.
  REQUIRE(a.channels == std::vector<std::string>{"acc1_mps2", "disp_m"});
  REQUIRE(a.units == std::vector<std::string>{"mps2", "m"});
  REQUIRE(a.data(2, 1) == Approx(6e-3).epsilon(1e-15));
  REQUIRE(a.channel("acc1") == 0);
  REQUIRE(a.channel("disp_mm") == 1);  // the file's name still finds it
  REQUIRE(a.channel("disp_m") == 1);
  REQUIRE_THROWS_WITH(a.channel("x"), Catch::Contains("no channel 'x'"));
  const Record b = read_record_csv(d.write("b.csv", "# sampling_rate_hz = 4096\nch_g\n1\n2\n3\n"));
  REQUIRE(b.fs_hz == 4096.0);
  REQUIRE(b.n_samples() == 3);
  REQUIRE(b.data(1, 0) == 2 * 9.80665);
  // Round trip: header and rows only (pandas reads it as is), the rate back from the stamps.
  write_record_csv((d.p / "c.csv").string(), a, 17);
  std::ifstream in(d.p / "c.csv");
  std::string first;
  std::getline(in, first);
  REQUIRE(first == "t_s,acc1_mps2,disp_m");
  const Record c = read_record_csv((d.p / "c.csv").string());
  REQUIRE(c.fs_hz == a.fs_hz);
  REQUIRE(c.t0_s == a.t0_s);
  REQUIRE(c.data == a.data);
  // An awkward rate (1651.2 Hz) and start survive the 12-digit stamps exactly too.
  Record e = a;
  e.fs_hz = 1651.2;
  e.t0_s = 12.345;
  e.data = Matrix::Random(5000, 2);
  write_record_csv((d.p / "e.csv").string(), e, 17);
  const Record e2 = read_record_csv((d.p / "e.csv").string());
  REQUIRE(e2.fs_hz == 1651.2);
  REQUIRE(e2.t0_s == 12.345);
  REQUIRE(e2.data == e.data);
}

TEST_CASE("bad records give file and line, every problem of a file at once") {
  Dir d;
  const std::string h = "t_s,a_mps2,b_m\n";
  // A NaN that cannot be interpolated (two samples): nothing is left of that channel.
  const Record nan2 = read_record_csv(d.write("nan.csv", h + "0,1,2\n0.1,nan,3\n"));
  REQUIRE_THROWS_WITH(valid_span(nan2, {0}, "peaks", nullptr), Catch::Contains("peaks: no 2 successive samples in which every channel used has a value"));
  REQUIRE(valid_span(nan2, {1}, "peaks", nullptr).n_samples() == 2);
  REQUIRE(error_of(d.write("cols.csv", h + "0,1,2\n0.1,3\n0.2,1,2\n")).find("cols.csv:3: expected 3 columns as in the header (line 1), got 2") != std::string::npos);
  REQUIRE(error_of(d.write("more.csv", h + "0,1,2\n0.1,1,2,4\n0.2,1,2\n")).find("more.csv:3: expected 3 columns") != std::string::npos);
  REQUIRE(error_of(d.write("back.csv", h + "0,1,2\n0.1,1,2\n0.05,1,2\n")).find("back.csv:4: time does not increase (t = 0.05 s after 0.1 s on line 3)") != std::string::npos);
  REQUIRE(error_of(d.write("jitter.csv", h + "0,1,2\n0.1,1,2\n0.2,1,2\n0.35,1,2\n0.45,1,2\n")).find("jitter.csv:5: irregular sampling") != std::string::npos);
  REQUIRE(error_of(d.write("dup.csv", "t_s,a_m,a_m\n0,1,2\n1,1,2\n")).find("channel 'a_m' appears twice") != std::string::npos);
  REQUIRE(error_of(d.write("dup2.csv", "t_s,a_mm,a [m]\n0,1,2\n1,1,2\n")).find("channel 'a_m' appears twice") != std::string::npos);
  REQUIRE(error_of(d.write("unit.csv", "t_s,a_furlong\n0,1\n1,1\n")).find("unit.csv:1: channel 'a_furlong' has no unit") != std::string::npos);
  REQUIRE(error_of(d.write("unit2.csv", "t_s,a [furlong]\n0,1\n1,1\n")).find("unit2.csv:1: channel 'a [furlong]': unit 'furlong' is not known") != std::string::npos);
  REQUIRE(error_of(d.write("rate.csv", "a_m\n1\n2\n")).find("the sampling rate is unknown") != std::string::npos);
  REQUIRE(error_of(d.write("both.csv", "# sampling_rate_hz = 50\nt_s,a_m\n0,1\n0.01,2\n")).find("both.csv:3: the rate declared (line 1) is 50 Hz; the time column steps by 0.01 s (100 Hz): they disagree") != std::string::npos);
  REQUIRE(error_of(d.write("short.csv", h + "0,1,2\n")).find("short.csv:2: a record needs at least 2 samples, got 1") != std::string::npos);
  REQUIRE(error_of(d.write("none.csv", "# only a comment\n")).find("no header line") != std::string::npos);
  REQUIRE(error_of(d.write("text.csv", h + "0,1,2\n0.1,1,2x\n")).find("text.csv:3: column 'b_m': '2x' is not a number") != std::string::npos);
  REQUIRE(error_of(d.write("allnan.csv", h + "0,nan,1\n0.1,,2\n0.2,NA,3\n")).find("allnan.csv:2: channel 'a_mps2' holds no number") != std::string::npos);
  REQUIRE(error_of((d.p / "missing.csv").string()).find("cannot open record") != std::string::npos);
  // A file cut inside its last line says so; the same line with its newline does not, and a last
  // line without a newline but whole is read (hand-made files often end so).
  REQUIRE(error_of(d.write("cut.csv", h + "0,1,2\n0.1,1,2\n0.2,1")).find("cut.csv:4: expected 3 columns as in the header (line 1), got 2 (the file ends inside this line, without a newline: cut short?)") !=
          std::string::npos);
  REQUIRE(error_of(d.write("cols2.csv", h + "0,1,2\n0.1,1,2\n0.2,1\n")).find("cut short") == std::string::npos);
  REQUIRE(read_record_csv(d.write("whole.csv", h + "0,1,2\n0.1,1,2\n0.2,1,2")).n_samples() == 3);
  // One pass: every problem of the file, sorted by line, with its count.
  const std::string all = error_of(d.write("many.csv", "t_s,a_mps2,strain_mid\n0,1,2\n0.1,x,2\n0.05,1,2\n0.3,1\n"));
  INFO(all);
  REQUIRE(all.find("many.csv:1: channel 'strain_mid' has no unit") != std::string::npos);
  REQUIRE(all.find("many.csv:3: column 'a_mps2': 'x' is not a number") != std::string::npos);
  REQUIRE(all.find("many.csv:4: time does not increase") != std::string::npos);
  REQUIRE(all.find("many.csv:5: expected 3 columns") != std::string::npos);
  REQUIRE(all.find("(4 problems in this file)") != std::string::npos);
}
