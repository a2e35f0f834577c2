// Logger files as loggers write them (issue #19 part 1): layouts, units, rounded time stamps,
// NaN and gaps. The signals are closed-form, so every repaired or converted value is checked
// against what it must be.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "../scratch.hpp"

using namespace viaduct;
using namespace viaduct::io;

namespace {

struct ImportDir : vt::ScratchDir {
  ImportDir() : vt::ScratchDir("import") {}
};

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = 1651.2;  // [Hz] an awkward logger rate: 1/fs = 0.60562... ms

double acc_g(double t) { return 0.01 * std::sin(2 * kPi * 5.0 * t); }          // [g]
double strain_ue(double t) { return 30.0 * std::sin(2 * kPi * 1.3 * t + 0.2); }  // [µε]

// Rows of samples k (skipping `skip`), time rounded to 0.1 ms as the logger writes it,
// cells joined by `sep`, with a decimal comma when asked; `cell` may blank a cell.
std::string logger_rows(int n, char sep, bool decimal_comma, const std::function<bool(int)>& skip,
                        const std::function<std::string(int, int, std::string)>& cell) {
  std::ostringstream os;
  char buf[64];
  for (int k = 0; k < n; ++k) {
    if (skip(k)) continue;
    const double t = 20.0 + k / kFs;
    std::string cells[3];
    std::snprintf(buf, sizeof buf, "%.4f", std::round(t * 1e4) / 1e4);
    cells[0] = buf;
    std::snprintf(buf, sizeof buf, "%.17g", acc_g(t));
    cells[1] = buf;
    std::snprintf(buf, sizeof buf, "%.17g", strain_ue(t));
    cells[2] = buf;
    for (int c = 0; c < 3; ++c) {
      std::string v = cell(k, c, cells[c]);
      if (decimal_comma) std::replace(v.begin(), v.end(), '.', ',');
      os << v << (c < 2 ? std::string(1, sep) : "\r\n");
    }
  }
  return os.str();
}

std::string keep(int, int, std::string v) { return v; }
bool none(int) { return false; }

}  // namespace

TEST_CASE("logger layouts: separators, decimal comma, preamble, units in brackets or on their own line") {
  ImportDir d;
  const int n = 2000;
  struct Layout {
    std::string name, head;
    char sep;
    bool comma;
  };
  const std::vector<Layout> layouts = {
      {"semicolon.csv", "Logger DX-100 export\r\nSerial number: 44120\r\nSample rate: 1651,2 Hz\r\nTime [s];Acc1 [g];Strain1 [µε]\r\n", ';', true},
      {"tab.txt", "Time\tAcc1\tStrain1\r\ns\tg\tmicrostrain\r\n", '\t', false},
      {"comma.csv", "# exported 2026-11-30\r\nTime (s),Acc1 (g),Strain1 (ue)\r\n", ',', false},
  };
  for (const auto& l : layouts) {
    INFO(l.name);
    ImportReport rep;
    const Record r = read_record(d.write(l.name, l.head + logger_rows(n, l.sep, l.comma, none, keep)), {}, &rep);
    REQUIRE(r.channels == std::vector<std::string>{"Acc1_mps2", "Strain1_ue"});
    REQUIRE(r.n_samples() == n);
    // The rate: declared (1651.2 exactly) or from stamps rounded to 0.1 ms, fitted over 1.2 s:
    // rounding error 5e-5 s over 1.2 s bounds it by 4e-5 relative; the fit does far better.
    REQUIRE(r.fs_hz == Approx(kFs).epsilon(1e-6));
    REQUIRE(r.t0_s == 20.0);
    REQUIRE(rep.max_time_offset > 0.05);  // the stamps are rounded by up to 0.083 samples
    REQUIRE(rep.max_time_offset < 0.09);
    REQUIRE(rep.repairs.empty());
    REQUIRE(!rep.plain);
    for (int k : {0, 777, n - 1}) {
      const double t = 20.0 + k / kFs;
      REQUIRE(r.data(k, 0) == Approx(9.80665 * acc_g(t)).margin(1e-15));
      REQUIRE(r.data(k, 1) == Approx(strain_ue(t)).margin(1e-12));
    }
    REQUIRE(rep.channels[0].factor == 9.80665);
    REQUIRE(r.channel("Acc1") == 0);
    REQUIRE(r.sources[1] == (l.sep == '\t' ? "Strain1 [microstrain]" : l.sep == ';' ? "Strain1 [µε]" : "Strain1 (ue)"));
  }
}

TEST_CASE("NaN cells and time gaps: short runs interpolated, long ones cut or refused, all reported") {
  ImportDir d;
  const int n = 3000;
  const std::string head = "Time [s],Acc1 [g],Strain1 [µε]\n";
  // A gap of 4 samples in the time column, a run of 2 NaN in one channel, an empty cell in the other.
  const auto skip = [](int k) { return k >= 1000 && k < 1004; };
  const auto blank = [](int k, int c, std::string v) { return (c == 1 && (k == 200 || k == 201)) || (c == 2 && k == 500) ? std::string(k == 500 ? "" : "NaN") : v; };
  const std::string path = d.write("gaps.csv", head + logger_rows(n, ',', false, skip, blank));
  ImportReport rep;
  const Record r = read_record(path, {}, &rep);
  REQUIRE(r.n_samples() == n);  // the gap's samples are back on the grid
  REQUIRE(rep.gap_samples == 4);
  REQUIRE(rep.channels[0].missing == 6);
  REQUIRE(rep.channels[0].interpolated == 6);
  REQUIRE(rep.channels[1].missing == 5);
  // Linear interpolation between the neighbours, exactly.
  const auto t = [](int k) { return 20.0 + k / kFs; };
  REQUIRE(r.data(200, 0) == Approx(9.80665 * (acc_g(t(199)) + (acc_g(t(202)) - acc_g(t(199))) / 3)).margin(1e-15));
  REQUIRE(r.data(1002, 1) == Approx(strain_ue(t(999)) + (strain_ue(t(1004)) - strain_ue(t(999))) * 3 / 5).margin(1e-12));
  REQUIRE(r.data(500, 1) == Approx((strain_ue(t(499)) + strain_ue(t(501))) / 2).margin(1e-12));
  REQUIRE(rep.repairs.size() == 2);
  REQUIRE(rep.repairs[0].find("skips 4 samples") != std::string::npos);
  REQUIRE(rep.repairs[1].find("interpolated linearly (runs up to 8 samples, --fill-max-s): Acc1_mps2 6, Strain1_ue 5") != std::string::npos);

  // The same file with interpolation limited to 3 samples (4.9 ms at 1651.2 Hz → 8 by default):
  // the time gap stays missing in every channel (each is reported); the record keeps its
  // length, and a command takes the longest piece where its channels have values.
  ReadOptions o;
  o.fill_max_s = 3.0 / kFs;
  const Record kept = read_record(path, o, &rep);
  REQUIRE(kept.n_samples() == n);
  REQUIRE(std::isnan(kept.data(1001, 0)));
  REQUIRE(missing_runs(kept, 0) == std::vector<std::pair<Index, Index>>{{1000, 1004}});
  REQUIRE(rep.repairs.back().find("that channel has no value there; the other channels keep theirs") != std::string::npos);
  std::vector<std::string> notes;
  const Record cut = valid_span(kept, {0, 1}, "test", &notes);
  REQUIRE(cut.n_samples() == n - 1004);
  REQUIRE(cut.t0_s == Approx(t(1004)).margin(1e-6));  // the rate fitted to stamps rounded to 0.1 ms: 1e-7 of 0.6 s
  REQUIRE(cut.data(0, 1) == Approx(strain_ue(t(1004))).margin(1e-12));
  REQUIRE(notes.size() == 1);
  REQUIRE(notes[0].find("takes the longest piece where they all have values") != std::string::npos);
  // ... or refused, naming the line after the gap.
  o.split_long_gaps = false;
  try {
    read_record(path, o);
    FAIL("refused expected");
  } catch (const InputError& e) {
    const std::string m = e.what();
    INFO(m);
    REQUIRE(m.find("gaps.csv:1002: missing samples too long to interpolate") != std::string::npos);  // line 1002 holds sample 1004
    REQUIRE(m.find("Acc1_mps2, 4 samples from") != std::string::npos);
  }
  // A NaN at either end cannot be interpolated: missing in its channel; valid_span trims it.
  const Record ends_read = read_record(d.write("ends.csv", "t_s,a_m\n0,nan\n0.1,1\n0.2,2\n0.3,3\n0.4,nan\n"), {}, &rep);
  REQUIRE(ends_read.n_samples() == 5);
  const Record ends = valid_span(ends_read, {0}, "test", nullptr);
  REQUIRE(ends.n_samples() == 3);
  REQUIRE(ends.t0_s == Approx(0.1).epsilon(1e-12));
  REQUIRE(ends.data(0, 0) == 1.0);
}

TEST_CASE("a long missing run marks its own channel only (issue #39 item 2)") {
  ImportDir d;
  // 0.3 s of NaN in channel b only, early in the record: channel a keeps every sample.
  std::string text = "t_s,a_m,b_mps2\n";
  const int n = 1000;
  for (int k = 0; k < n; ++k) {
    const double t = k / 500.0;
    text += std::to_string(t) + "," + std::to_string(std::sin(t)) + "," + (t > 0.5 && t < 0.8 ? std::string("NaN") : std::to_string(std::cos(t))) + "\n";
  }
  ImportReport rep;
  const Record r = read_record(d.write("one.csv", text), {}, &rep);
  REQUIRE(r.n_samples() == n);
  REQUIRE(rep.channels[0].missing == 0);
  REQUIRE(rep.channels[1].missing == 149);
  // A command using a only takes the whole record; one using b (or both) its longest valid piece.
  REQUIRE(valid_span(r, {0}, "test", nullptr).n_samples() == n);
  std::vector<std::string> notes;
  const Record b = valid_span(r, {0, 1}, "test", &notes);
  REQUIRE(b.n_samples() == n - 400);
  REQUIRE(b.t0_s == Approx(0.8));
  REQUIRE(notes.at(0).find("b_mps2 from 0.502 to 0.798 s") != std::string::npos);
  // Nothing usable: a clear error naming the channel.
  Record none = r;
  none.data.col(1).setConstant(std::nan(""));
  none.data(3, 1) = 1.0;
  REQUIRE_THROWS_WITH(valid_span(none, {1}, "test", nullptr), Catch::Contains("no 2 successive samples") && Catch::Contains("b_mps2 from"));
}

TEST_CASE("a clipped stretch counts as missing in its channel only") {
  ImportDir d;
  std::string text = "t_s,a_m,b_m\n";
  for (int k = 0; k < 400; ++k) {
    const double t = k / 200.0;
    const double b = std::min(0.8, std::sin(2 * kPi * t));  // over the range: held at 0.8
    text += std::to_string(t) + "," + std::to_string(std::sin(2 * kPi * 0.7 * t)) + "," + std::to_string(b) + "\n";
  }
  ImportReport rep;
  const Record r = read_record(d.write("clip.csv", text), {}, &rep);
  REQUIRE(rep.channels[1].clipped > 0);
  REQUIRE(rep.channels[0].clipped == 0);
  REQUIRE(!missing_runs(r, 1).empty());
  REQUIRE(missing_runs(r, 0).empty());
  bool said = false;
  for (const auto& x : rep.repairs) said = said || x.find("b_m is clipped") != std::string::npos;
  REQUIRE(said);
}

TEST_CASE("time columns by name, by index or none, clock times, units of time") {
  ImportDir d;
  ReadOptions o;
  // No time-like name: the first column is a channel unless --time-column says otherwise.
  const std::string p = d.write("idx.csv", "stamp_s,acc_g\n0.000,1\n0.002,2\n0.004,3\n");
  REQUIRE_THROWS_WITH(read_record(p, o), Catch::Contains("the sampling rate is unknown"));
  o.time_column = "1";
  Record r = read_record(p, o);
  REQUIRE(r.fs_hz == 500.0);
  REQUIRE(r.channels == std::vector<std::string>{"acc_mps2"});
  o.time_column = "stamp_s";
  REQUIRE(read_record(p, o).fs_hz == 500.0);
  o.time_column = "7";
  REQUIRE_THROWS_WITH(read_record(p, o), Catch::Contains("idx.csv:1: --time-column 7: the header has columns 1 to 2"));
  // Milliseconds.
  o = {};
  r = read_record(d.write("ms.csv", "Time [ms];a [mm]\n0;1\n0,5;2\n1;3\n"), o);
  REQUIRE(r.fs_hz == 2000.0);
  REQUIRE(r.data(1, 0) == 2e-3);
  // Clock times after a date: seconds of the day.
  r = read_record(d.write("clock.csv", "Timestamp,acc_mps2\n2026-03-01 12:00:01.000,1\n2026-03-01 12:00:01.010,2\n2026-03-01 12:00:01.020,3\n"), o);
  REQUIRE(r.fs_hz == 100.0);
  REQUIRE(r.t0_s == 43201.0);
  // No time column and no rate: --rate-hz gives it; a time column is checked against it.
  o.time_column = "none";
  o.fs_hz = 200.0;
  r = read_record(d.write("norate.csv", "strain_mid\n1\n2\n"), [&] {
    ReadOptions q = o;
    q.units = {{"strain_mid", "µε"}};
    return q;
  }());
  REQUIRE(r.channels == std::vector<std::string>{"strain_mid_ue"});
  REQUIRE(r.fs_hz == 200.0);
  o.time_column.clear();
  REQUIRE_THROWS_WITH(read_record(d.write("disagree.csv", "t_s,a_m\n0,1\n0.01,2\n"), o), Catch::Contains("disagree.csv:2: the rate declared (--rate-hz) is 200 Hz; the time column steps by 0.01 s (100 Hz): they disagree"));
}

TEST_CASE("preamble rates with units or none, and a separator at the end of every line") {
  ImportDir d;
  ImportReport rep;
  Record r = read_record(d.write("sps.csv", "Sample rate: 200 samples/s\nacc_g\n1\n2\n3\n"), {}, &rep);
  REQUIRE(r.fs_hz == 200.0);
  // A rate line that says no number is not a declaration (the stamps give the rate) ...
  r = read_record(d.write("na.csv", "Sampling rate: see the channel list\nt_s,a_m\n0,1\n0.01,2\n0.02,3\n"));
  REQUIRE(r.fs_hz == 100.0);
  // ... nor is a header cell named like one; a number that is no rate is an error.
  REQUIRE_THROWS_WITH(read_record(d.write("fs.csv", "fs,a_m\n1,2\n3,4\n")), Catch::Contains("channel 'fs' has no unit"));
  REQUIRE_THROWS_WITH(read_record(d.write("zero.csv", "Sample rate: 0 Hz\na_m\n1\n2\n")), Catch::Contains("zero.csv:1: the sampling rate declared here is not a number > 0"));
  // Spreadsheet exports end every line with the separator: the empty last column is no channel.
  r = read_record(d.write("trail.csv", "t_s,a_m,\n0,1,\n0.01,2,\n0.02,3,\n"), {}, &rep);
  REQUIRE(r.channels == std::vector<std::string>{"a_m"});
  REQUIRE(r.data(2, 0) == 3.0);
  REQUIRE(rep.notes.front().find("ends with a separator") != std::string::npos);
  // A value under that empty name is a column without a name.
  REQUIRE_THROWS_WITH(read_record(d.write("trail2.csv", "t_s,a_m,\n0,1,\n0.01,2,5\n")), Catch::Contains("column 3 has no name"));
}

TEST_CASE("units: logger spellings to viaduct's units with their factors") {
  struct Case {
    const char* text;
    const char* unit;
    double factor;
  };
  const Case cases[] = {{"g", "mps2", 9.80665}, {"m/s^2", "mps2", 1}, {"m/s²", "mps2", 1}, {"mg", "mps2", 9.80665e-3},
                        {"mm", "m", 1e-3},       {"µm", "m", 1e-6},      {"kN", "N", 1e3},     {"kN·m", "Nm", 1e3},
                        {"µε", "ue", 1},         {"με", "ue", 1},        {"microstrain", "ue", 1}, {"strain", "ue", 1e6},
                        {"MPa", "Pa", 1e6},      {"mV", "V", 1e-3},      {"°C", "degC", 1},    {"mps2", "mps2", 1}};
  for (const auto& c : cases) {
    INFO(c.text);
    const auto u = parse_unit(c.text);
    REQUIRE(u);
    REQUIRE(u->unit == c.unit);
    REQUIRE(u->factor == Approx(c.factor).epsilon(1e-15));
  }
  REQUIRE(!parse_unit("furlong"));
  REQUIRE(!parse_unit(""));
}

TEST_CASE("channel summary: offsets, drift, clipping and stuck values") {
  const Index n = 4000;
  Vector x(n), clipped(n), stuck(n);
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / 1000.0;
    // An oversampled sine quantised to 1e-3: flat tops of a few samples, not clipping.
    x[k] = std::round(1e3 * (0.5 + 30.0 * std::sin(2 * kPi * 1.25 * t))) / 1e3;
    clipped[k] = std::min(2.0, std::max(-2.0, 3.0 * std::sin(2 * kPi * 5.0 * t)));
    stuck[k] = k >= 1000 && k < 1100 ? 0.123 : std::sin(2 * kPi * 5.0 * t);
  }
  const ChannelSummary s = summarise_channel(x);
  REQUIRE(s.mean == Approx(0.5).margin(1e-3));  // 5 whole periods: the offset, within the quantisation
  REQUIRE(s.rms_ac == Approx(30.0 / std::sqrt(2.0)).epsilon(0.02));
  REQUIRE(!s.clipped);
  const ChannelSummary c = summarise_channel(clipped);
  REQUIRE(c.clipped);
  REQUIRE(c.at_limits > 500);  // 20 plateaus of about 27 % of a half-period
  const ChannelSummary f = summarise_channel(stuck);
  REQUIRE(f.longest_flat == 100);
  REQUIRE(!f.clipped);
}
