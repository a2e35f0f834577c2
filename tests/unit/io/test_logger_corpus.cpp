// Issue #39 item 1: files as six logger families write them (tests/data/loggers, written by
// scripts/generate/make_logger_corpus.py from the vendors' published layouts; sources in the
// folder's README.md). Every file holds the same two closed-form signals, so each value read is
// checked, not only that reading succeeds.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "../scratch.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::io;

namespace {

constexpr double kCorpusPi = 3.14159265358979323846;
double corpus_acc(double t) { return 0.5 * std::sin(2 * kCorpusPi * 10.0 * t); }             // [m/s²]
double corpus_strain(double t) { return 30.0 * std::sin(2 * kCorpusPi * 2.0 * t) + 12.0; }  // [µε]

struct LoggerFamily {
  const char* file;
  double fs_hz;
  double t0_s;     // 14:22:05 as seconds of the day where the file's time has a clock
  const char* acc_channel;
  const char* strain_channel;
};

const std::string corpus = std::string(VIADUCT_SOURCE_DIR) + "/tests/data/loggers/";

}  // namespace

TEST_CASE("logger corpus: six families and issue #39's preamble read to the same signals") {
  const LoggerFamily families[] = {
      {"hbm-catman.txt", 600.0, 0.0, "Acc_S1_mid_mps2", "SG_S1_mid_ue"},
      {"dewesoft.txt", 1000.0, 51725.0, "AI_1_Acc_S1_mid_mps2", "AI_2_SG_S1_mid_ue"},
      {"ni-labview.lvm", 500.0, 0.0, "Acc_S1_mid_mps2", "SG_S1_mid_ue"},
      {"campbell-toa5.dat", 100.0, 51725.0, "Acc_S1_mid_mps2", "SG_S1_mid_ue"},
      {"gantner.csv", 200.0, 51725.0, "Acc_S1_mid_mps2", "SG_S1_mid_ue"},
      {"spreadsheet-de.csv", 250.0, 51725.0, "Beschleunigung_S1_mps2", "Dehnung_S1_ue"},
      {"preamble-datetime.csv", 1250.0, 51725.0, "Acc_S1_mid_mps2", "SG_S1_mid_ue"},
  };
  for (const auto& f : families) {
    INFO(f.file);
    ImportReport rep;
    const Record r = read_record(corpus + f.file, {}, &rep);
    REQUIRE(r.n_samples() == 300);
    REQUIRE(r.channels.size() == 2);  // record numbers, dates and empty comment columns are no channels
    // Spreadsheet serial days carry 15 digits: 1e-10 days is 9 µs, 2e-3 of a sample at 250 Hz.
    REQUIRE(r.fs_hz == Approx(f.fs_hz).epsilon(1e-7));
    REQUIRE(r.t0_s == Approx(f.t0_s).margin(1e-5));
    const std::size_t a = r.channel(f.acc_channel), e = r.channel(f.strain_channel);
    REQUIRE(r.units[a] == "mps2");
    REQUIRE(r.units[e] == "ue");
    double err_a = 0, err_e = 0;
    for (Index k = 0; k < r.n_samples(); ++k) {
      const double t = static_cast<double>(k) / f.fs_hz;
      err_a = std::max(err_a, std::abs(r.data(k, static_cast<Index>(a)) - corpus_acc(t)));
      err_e = std::max(err_e, std::abs(r.data(k, static_cast<Index>(e)) - corpus_strain(t)));
    }
    // The files hold 6 to 7 significant digits (and g or mg converted): 2e-6 of the amplitudes.
    REQUIRE(err_a < 1e-6);
    REQUIRE(err_e < 6e-5);
  }
}

TEST_CASE("a date or clock column misread names the fix") {
  // The Date/Time column taken as a channel (the time said to be column 2): the error says it
  // reads as a clock time and names --time-column.
  ReadOptions o;
  o.time_column = "2";
  o.units = {{"Acc S1 mid [m/s^2]", "m/s^2"}};
  try {
    read_record(corpus + "preamble-datetime.csv", o);
    FAIL("an error was expected");
  } catch (const InputError& e) {
    const std::string m = e.what();
    INFO(m);
    REQUIRE(m.find("reads as a date or clock time; if this is the time, give --time-column 'Date/Time'") != std::string::npos);
  }
  // --header-line names the header; --skip-lines passes over a preamble.
  ReadOptions h;
  h.header_line = 6;
  REQUIRE(read_record(corpus + "preamble-datetime.csv", h).n_samples() == 300);
  ReadOptions s;
  s.skip_lines = 5;
  REQUIRE(read_record(corpus + "preamble-datetime.csv", s).n_samples() == 300);
  ReadOptions bad;
  bad.header_line = 2;  // "Start: 03.12.2026 14:22:05": no rows of one cell under it
  REQUIRE_THROWS_AS(read_record(corpus + "preamble-datetime.csv", bad), InputError);
}

TEST_CASE("time stamps: ISO 8601 with zone, dates across midnight") {
  // 23:59:59.9 +01:00 to 00:00:00.01 the next day, 100 Hz: time keeps increasing over midnight.
  std::string text = "time,x_m\n";
  for (int k = 0; k < 12; ++k) {
    const int cs = 90 + k;  // hundredths of a second after 23:59:59
    char row[64];
    std::snprintf(row, sizeof row, cs < 100 ? "2026-12-03T23:59:59.%02d+01:00,%d\n" : "2026-12-04T00:00:00.%02d+01:00,%d\n", cs % 100, k);
    text += row;
  }
  vt::ScratchDir d("loggers");
  const std::string path = d.write("iso.csv", text);
  const Record r = read_record(path);
  REQUIRE(r.n_samples() == 12);
  REQUIRE(r.fs_hz == Approx(100.0).epsilon(1e-9));
  REQUIRE(r.t0_s == Approx(22 * 3600.0 + 59 * 60 + 59.9).margin(1e-6));  // UTC: 22:59:59.9 of the first stamp's day
}

TEST_CASE("dates in another order are not guessed, and a trigger channel is not clipped") {
  // 05/14/2026: month first or day first? The clock counts from its own midnight.
  std::string text = "Timestamp,a_m,trigger_V\n";
  for (int k = 0; k < 40; ++k) {
    char row[96];
    std::snprintf(row, sizeof row, "05/14/2026 10:31:%06.3f,%.6f,%d\n", 7.0 + 0.01 * k, std::sin(0.3 * k), k >= 10 && k < 30 ? 5 : 0);
    text += row;
  }
  vt::ScratchDir d("loggers");
  const std::string path = d.write("us.csv", text);
  ImportReport rep;
  const Record r = read_record(path, {}, &rep);
  REQUIRE(r.t0_s == Approx(10 * 3600.0 + 31 * 60 + 7.0).margin(1e-6));
  REQUIRE(r.fs_hz == Approx(100.0).epsilon(1e-9));
  // The 0/5 V trigger sits at its limits by design: not clipped, no sample missing.
  REQUIRE(rep.channels.at(1).clipped == 0);
  REQUIRE(missing_runs(r, 1).empty());
}
