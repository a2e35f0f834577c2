#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "../scratch.hpp"

using namespace viaduct;
using namespace viaduct::io;
namespace fs = std::filesystem;

namespace {
// One dataset 58 with the standard's field widths (as modal-test software writes them).
std::string dataset(const std::string& id1, int ord_type, int n, double x0, double dx, const std::string& unit,
                    const std::vector<double>& v, int spacing = 1) {
  char buf[256];
  std::string s = "    -1\n    58\n";
  std::snprintf(buf, sizeof buf, "%-80s\n", id1.c_str());
  s += buf;
  for (int i = 0; i < 4; ++i) s += "NONE\n";
  s += "    1         0    0         0 NONE               1   3 NONE               1   3\n";
  std::snprintf(buf, sizeof buf, "%10d%10d%10d%13.5e%13.5e%13.5e\n", ord_type, n, spacing, x0, dx, 0.0);
  s += buf;
  std::snprintf(buf, sizeof buf, "%10d%5d%5d%5d %-20s %-20s\n", 17, 0, 0, 0, "Time", "s");
  s += buf;
  std::snprintf(buf, sizeof buf, "%10d%5d%5d%5d %-20s %-20s\n", 12, 1, 0, 0, "Acceleration", unit.c_str());
  s += buf;
  for (int i = 0; i < 2; ++i) {
    std::snprintf(buf, sizeof buf, "%10d%5d%5d%5d %-20s %-20s\n", 0, 0, 0, 0, "NONE", "NONE");
    s += buf;
  }
  const int per_line = ord_type == 2 ? 6 : 4;
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof buf, ord_type == 2 ? "%13.5e" : "%20.11e", v[i]);
    s += buf;
    if ((i + 1) % static_cast<std::size_t>(per_line) == 0 || i + 1 == v.size()) s += "\n";
  }
  return s + "    -1\n";
}
// The same as a binary dataset 58b: the type line "    58b" with byte order (1 little, 2 big
// endian), floating-point format (2: IEEE 754), 11 ASCII header lines and the data's bytes, then
// the 11 header records as in ASCII, the values as raw bytes, a newline and -1.
std::string dataset_58b(const std::string& id1, int ord_type, int n, double dx, const std::string& unit, const std::vector<double>& v,
                        bool big_endian, int fp_format = 2, long n_bytes = -1) {
  const std::string ascii = dataset(id1, ord_type, n, 0.0, dx, unit, {});
  // ASCII header records: the lines between the type line and the (empty) data.
  const auto h0 = ascii.find('\n', ascii.find("    58\n") + 1) + 1;
  const std::string header = ascii.substr(h0, ascii.rfind("    -1\n") - h0);
  const std::size_t size = ord_type == 2 ? 4 : 8;
  std::string data;
  for (double x : v) {
    unsigned char b[8];
    if (size == 4) {
      const float f = static_cast<float>(x);
      std::memcpy(b, &f, 4);
    } else {
      std::memcpy(b, &x, 8);
    }
    if (big_endian) std::reverse(b, b + size);  // the tests run on little-endian hosts (x86-64, arm64)
    data.append(reinterpret_cast<const char*>(b), size);
  }
  char type[128];
  std::snprintf(type, sizeof type, "%6d%c%6d%6d%12d%12ld%6d%6d%12d%12d\n", 58, 'b', big_endian ? 2 : 1, fp_format, 11,
                n_bytes >= 0 ? n_bytes : static_cast<long>(data.size()), 0, 0, 0, 0);
  return "    -1\n" + std::string(type) + header + data + "\n    -1\n";
}
struct UffDir : vt::ScratchDir {
  UffDir() : vt::ScratchDir("uff") {}
};
std::string uff_error_of(const std::string& path) {
  try {
    read_record(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("UFF dataset 58 (ASCII): single and double precision channels") {
  UffDir d;
  std::vector<double> a(11), b(11);
  for (int i = 0; i < 11; ++i) {
    a[static_cast<std::size_t>(i)] = std::sin(0.3 * i) * 1e-2;
    b[static_cast<std::size_t>(i)] = 1.5 + 0.25 * i;
  }
  // A dataset of another type (151, header) before ours is skipped.
  const std::string text = "    -1\n   151\nmodel\n    -1\n" + dataset("S1 mid", 4, 11, 0.5, 0.00025, "m/s^2", a) +
                           dataset("S2,mid", 2, 11, 0.5, 0.00025, "g", b);
  const Record r = read_record(d.write("test.uff", text));
  REQUIRE(r.fs_hz == Approx(4000.0).epsilon(1e-12));
  REQUIRE(r.t0_s == 0.5);
  // Channels in viaduct's units: g read as m/s² (× 9.80665, the standard gravity).
  REQUIRE(r.channels == std::vector<std::string>{"S1_mid_mps2", "S2_mid_mps2"});
  REQUIRE(r.n_samples() == 11);
  for (int i = 0; i < 11; ++i) {
    REQUIRE(r.data(i, 0) == Approx(a[static_cast<std::size_t>(i)]).epsilon(1e-11));  // 4E20.11
    REQUIRE(r.data(i, 1) == Approx(9.80665 * b[static_cast<std::size_t>(i)]).epsilon(1e-5));   // 6E13.5
  }
}

TEST_CASE("UFF dataset 58: what records cannot hold is refused with file and line") {
  UffDir d;
  const std::vector<double> v = {1, 2, 3, 4};
  REQUIRE(uff_error_of(d.write("c.uff", dataset("x", 6, 2, 0, 0.1, "m/s^2", v))).find("complex ordinates") != std::string::npos);
  REQUIRE(uff_error_of(d.write("u.uff", dataset("x", 4, 2, 0, 0.1, "m/s^2", v, 0))).find("uneven abscissa") != std::string::npos);
  REQUIRE(uff_error_of(d.write("n.uff", dataset("x", 4, 5, 0, 0.1, "m/s^2", v))).find("declares 5 points but holds 4") != std::string::npos);
  REQUIRE(uff_error_of(d.write("k.uff", dataset("x", 4, 4, 0, 0.1, "furlong", v))).find("ordinate unit 'furlong'") != std::string::npos);
  REQUIRE(uff_error_of(d.write("r.uff", dataset("x", 4, 4, 0, 0.1, "m", v) + dataset("y", 4, 4, 0, 0.2, "m", v)))
              .find("differs in rate, start or length") != std::string::npos);
  REQUIRE(uff_error_of(d.write("b.uff", "    -1\n    58b     1     2\n")).find("b.uff:2: dataset 58b: the type line must give") != std::string::npos);
  REQUIRE(uff_error_of(d.write("e.uff", "    -1\n   151\nx\n    -1\n")).find("no dataset 58") != std::string::npos);
  std::string bad = dataset("x", 4, 4, 0, 0.1, "m", v);
  bad.replace(bad.find("2.00000000000e+00"), 17, "   2.0000000000x0");
  REQUIRE(uff_error_of(d.write("t.uff", bad)).find("t.uff:14: not a finite number") != std::string::npos);
}

TEST_CASE("UFF dataset 58: a byte-order mark is read through, a missing -1 is an error, not a lost channel") {
  UffDir d;
  std::vector<double> a(11, 0.5), b(11, 1.5);
  const std::string one = dataset("S1", 2, 11, 0.0, 0.01, "m/s^2", a), two = dataset("S2", 2, 11, 0.0, 0.01, "m/s^2", b);
  // Windows editors put EF BB BF before the first "-1": both channels are still read.
  const Record r = read_record(d.write("bom.uff", "\xEF\xBB\xBF" + one + two));
  REQUIRE(r.channels == std::vector<std::string>{"S1_mps2", "S2_mps2"});
  // The first dataset's closing -1 missing: its data would end at the second's opening -1 and
  // the second dataset be skipped; now the orphan "58" line is reported at its line.
  const std::string cut = one.substr(0, one.size() - std::string("    -1\n").size());
  const int line_58 = static_cast<int>(std::count(cut.begin(), cut.end(), '\n')) + 2;
  CHECK(uff_error_of(d.write("cut.uff", cut + two)) ==
        (d.p / "cut.uff").string() + ":" + std::to_string(line_58) + ": '58' outside any dataset: a -1 delimiter is missing before or after it");
}

TEST_CASE("UFF dataset 58b (binary): either byte order, single and double precision, with ASCII datasets") {
  UffDir d;
  std::vector<double> a(37), b(37), c(37);
  for (int i = 0; i < 37; ++i) {
    const auto k = static_cast<std::size_t>(i);
    a[k] = std::sin(0.3 * i) * 1e-2;
    b[k] = 1.5 + 0.25 * i;
    c[k] = -3.0 + 0.125 * i;  // exact in single precision
  }
  // Bytes that happen to be '\n' or "-1" inside the data must not end it: 10.0 as a float is 0x41200000.
  a[5] = 10.0;
  c[7] = 10.0;
  const std::string text = dataset_58b("S1 mid", 4, 37, 0.001, "m/s^2", a, false) + dataset_58b("S2 mid", 2, 37, 0.001, "mm", c, true) +
                           dataset("S3 mid", 4, 37, 0.0, 0.001, "m", b) + dataset_58b("S4 mid", 4, 37, 0.001, "m", b, true);
  const Record r = read_record(d.write("bin.uff", text));
  REQUIRE(r.channels == std::vector<std::string>{"S1_mid_mps2", "S2_mid_m", "S3_mid_m", "S4_mid_m"});
  REQUIRE(r.fs_hz == Approx(1000.0).epsilon(1e-12));
  for (int i = 0; i < 37; ++i) {
    const auto k = static_cast<std::size_t>(i);
    CHECK(r.data(i, 0) == a[k]);           // doubles bit for bit
    CHECK(r.data(i, 1) == 1e-3 * c[k]);    // mm to m, exact floats
    CHECK(r.data(i, 3) == b[k]);
    CHECK(r.data(i, 2) == Approx(b[k]).epsilon(1e-11));
  }
}

TEST_CASE("UFF dataset 58b: what cannot be read is refused with file and line") {
  UffDir d;
  const std::vector<double> v{1, 2, 3, 4};
  CHECK(uff_error_of(d.write("vms.uff", dataset_58b("x", 4, 4, 0.1, "m", v, false, 1))).find("vms.uff:2: dataset 58b: floating-point format 1 is not IEEE 754") !=
        std::string::npos);
  CHECK(uff_error_of(d.write("nb.uff", dataset_58b("x", 4, 4, 0.1, "m", v, false, 2, 24))).find("declares 24 bytes; 4 points of 8 bytes are 32") !=
        std::string::npos);
  const std::string full = dataset_58b("x", 4, 4, 0.1, "m", v, false);
  CHECK(uff_error_of(d.write("cut.uff", full.substr(0, full.size() - 20))).find("cut.uff:2: dataset 58b 'x': the file ends") != std::string::npos);
  CHECK(uff_error_of(d.write("cplx.uff", dataset_58b("x", 6, 4, 0.1, "m", v, false))).find("complex ordinates") != std::string::npos);
  std::vector<double> nan_v = v;
  nan_v[2] = std::nan("");
  CHECK(uff_error_of(d.write("nan.uff", dataset_58b("x", 4, 4, 0.1, "m", nan_v, false))).find("not a finite number") != std::string::npos);
}
