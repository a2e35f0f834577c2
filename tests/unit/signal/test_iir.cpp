#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/iir.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::signal;

namespace {
struct Reference {
  Cheby1Spec spec;
  double fs = 0;
  std::vector<Section> sos;
  Vector x, y;
};

std::vector<double> split(const std::string& line) {
  std::vector<double> v;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
  return v;
}

Reference read_reference(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in.good());
  Reference r;
  std::string line;
  int block = 0;  // 0 header, 1 params, 2 sos, 3 data
  std::vector<double> xs, ys;
  while (std::getline(in, line)) {
    if (line.rfind("# band", 0) == 0) { block = 1; continue; }
    if (line.rfind("# sos", 0) == 0) { block = 2; continue; }
    if (line.rfind("# x,y", 0) == 0) { block = 3; continue; }
    if (line.empty() || line[0] == '#') continue;
    if (block == 1) {
      const auto comma = line.find(',');
      const std::string band = line.substr(0, comma);
      const auto v = split(line.substr(comma + 1));
      r.spec.band = band == "bandpass" ? BandType::bandpass : band == "lowpass" ? BandType::lowpass : BandType::highpass;
      r.spec.order = static_cast<int>(v[0]);
      r.spec.ripple_db = v[1];
      r.spec.low_hz = v[2];
      r.spec.high_hz = v[3];
      r.fs = v[4];
    } else if (block == 2) {
      const auto v = split(line);
      r.sos.push_back({v[0], v[1], v[2], v[3], v[4], v[5]});
    } else if (block == 3) {
      const auto v = split(line);
      xs.push_back(v[0]);
      ys.push_back(v[1]);
    }
  }
  r.x = Eigen::Map<Vector>(xs.data(), static_cast<Index>(xs.size()));
  r.y = Eigen::Map<Vector>(ys.data(), static_cast<Index>(ys.size()));
  return r;
}
}  // namespace

TEST_CASE("Chebyshev I design and sosfiltfilt match SciPy's reference vectors") {
  const std::string dir = std::string(VIADUCT_SOURCE_DIR) + "/tests/data/filter_reference";
  int n_cases = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const Reference r = read_reference(entry.path().string());
    INFO(entry.path().filename().string());
    const Sos sos = cheby1(r.spec, r.fs);
    REQUIRE(sos.n_sections() == r.sos.size());
    // Same sections in the same order (SciPy's pairing): coefficients agree to round-off of the
    // pole computation (complex sqrt and products), far below the 1e-9 output requirement.
    for (std::size_t s = 0; s < r.sos.size(); ++s)
      for (std::size_t c = 0; c < 6; ++c) REQUIRE(sos.sections[s][c] == Approx(r.sos[s][c]).margin(1e-12).epsilon(1e-10));
    const Vector y = sosfiltfilt(sos, r.x);
    // The requirement: filtered output within 1e-9 of SciPy's, relative to the output's peak.
    const double rel = (y - r.y).cwiseAbs().maxCoeff() / r.y.cwiseAbs().maxCoeff();
    REQUIRE(rel < 1e-9);
    ++n_cases;
  }
  REQUIRE(n_cases >= 7);
}

TEST_CASE("Chebyshev I band edges sit at -ripple dB in one pass (SciPy's convention)") {
  Cheby1Spec s;
  s.order = 3;
  s.ripple_db = 0.5;
  s.low_hz = 1.0;
  s.high_hz = 60.0;
  const Sos sos = cheby1(s, 1000.0);
  auto db = [&](double f) { return 20 * std::log10(std::abs(sos.response(f, 1000.0))); };
  REQUIRE(db(1.0) == Approx(-0.5).margin(1e-9));   // edge definition, exact up to round-off
  REQUIRE(db(60.0) == Approx(-0.5).margin(1e-9));
  REQUIRE(db(10.0) <= 1e-9);                         // ripple never amplifies
  REQUIRE(db(10.0) >= -0.5 - 1e-9);
  REQUIRE(db(200.0) < -30.0);                        // stop band of an order-3 band-pass
}

TEST_CASE("zero-phase filtering keeps a steady in-band sine in phase") {
  Cheby1Spec s;
  s.low_hz = 1.0;
  s.high_hz = 30.0;
  const double fs = 500.0;
  const Sos sos = cheby1(s, fs);
  Vector x(20000);  // 40 s: the 1 Hz edge poles ring for several seconds
  for (Index i = 0; i < x.size(); ++i) x[i] = std::sin(2 * M_PI * 8.0 * i / fs);
  const Vector y = sosfiltfilt(sos, x);
  // Away from the ends, y = |H(8 Hz)|² x with no phase shift.
  const double g = std::norm(sos.response(8.0, fs));
  const Vector mid_err = (y - g * x).segment(7500, 5000);
  REQUIRE(mid_err.cwiseAbs().maxCoeff() < 1e-6);  // 15 s from either end: edge transients decayed
}

TEST_CASE("filter inputs are validated") {
  Cheby1Spec s;
  s.high_hz = 600.0;
  REQUIRE_THROWS_WITH(cheby1(s, 1000.0), Catch::Contains("Cheby1Spec::high_hz = ") && Catch::Contains("high_hz in (0, fs/2"));
  s = Cheby1Spec{};
  s.low_hz = 40.0;
  s.high_hz = 30.0;
  REQUIRE_THROWS_WITH(cheby1(s, 1000.0), Catch::Contains("low_hz < high_hz"));
  s = Cheby1Spec{};
  s.order = 0;
  REQUIRE_THROWS_AS(cheby1(s, 1000.0), InputError);
  s = Cheby1Spec{};
  s.ripple_db = 0.0;
  REQUIRE_THROWS_AS(cheby1(s, 1000.0), InputError);
  const Sos sos = cheby1(Cheby1Spec{}, 1000.0);
  REQUIRE(default_padlen(sos) == 21);  // 3·(2·3 + 1) for three full sections
  REQUIRE_THROWS_WITH(sosfiltfilt(sos, Vector::Ones(21)), Catch::Contains("too short"));
  REQUIRE_NOTHROW(sosfiltfilt(sos, Vector::Ones(22)));
}

namespace {
// A decaying two-tone response cut while it still rings (as a simulated record is after its
// free vibration), at rest at t = 0.
Vector ringing(double fs, double duration) {
  Vector x(static_cast<Index>(std::llround(duration * fs)));
  for (Index i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / fs;
    x[i] = std::exp(-0.8 * t) * (std::sin(2 * M_PI * 10.0 * t) + 0.4 * std::sin(2 * M_PI * 35.0 * t)) * std::min(1.0, t);
  }
  return x;
}
}  // namespace

TEST_CASE("zero-phase filtering from rest equals filtering the record followed by zeros") {
  Cheby1Spec s;
  s.low_hz = 1.0;
  s.high_hz = 60.0;
  for (double fs : {200.0, 1000.0, 8000.0}) {
    const Sos sos = cheby1(s, fs);
    const Vector x = ringing(fs, 3.0);
    // Brute force: 60 s of zeros after the record (the 1 Hz edge poles decay with tau ~ 0.6 s,
    // so their ringing is below 1e-40 there), zero states at both ends.
    Vector padded = Vector::Zero(x.size() + static_cast<Index>(60.0 * fs));
    padded.head(x.size()) = x;
    Vector y;
    sosfilt(sos, padded, y);
    Vector rev = y.reverse();
    sosfilt(sos, rev, y);
    const Vector expected = y.reverse().head(x.size());
    const Vector got = filtfilt_from_rest(sos, x);
    INFO("fs = " << fs);
    // rounding only: the doubling sums the same geometric series as the brute-force tail; both
    // recursions amplify rounding by ~1/(1 - pole radius) (~5e3 at 8 kHz): 4e-10 measured there
    REQUIRE((got - expected).cwiseAbs().maxCoeff() < 1e-8 * expected.cwiseAbs().maxCoeff());
    // Appending zeros changes nothing (the odd extension of sosfiltfilt does change).
    Vector longer = Vector::Zero(x.size() + static_cast<Index>(0.3 * fs));
    longer.head(x.size()) = x;
    REQUIRE((filtfilt_from_rest(sos, longer).head(x.size()) - got).cwiseAbs().maxCoeff() < 1e-8 * got.cwiseAbs().maxCoeff());
    const double odd_change = (sosfiltfilt(sos, longer).head(x.size()) - sosfiltfilt(sos, x)).cwiseAbs().maxCoeff();
    REQUIRE(odd_change > 1e-3 * got.cwiseAbs().maxCoeff());
  }
  // Degenerate lengths.
  const Sos sos = cheby1(s, 1000.0);
  REQUIRE(filtfilt_from_rest(sos, Vector()).size() == 0);
  REQUIRE(filtfilt_from_rest(sos, Vector::Ones(1)).allFinite());
}

TEST_CASE("the maximum of a response filtered from rest hardly depends on the sampling rate") {
  // The same ringing record at 1 kHz and 10 kHz: the designs differ only by the bilinear
  // transform's warping of in-band ripple (~0.2 % at 40 Hz for this band), and the maxima of
  // the 10 Hz response 1.5 s before the cut agree to that; with sosfiltfilt's 21-sample odd
  // extension (21 ms against 2.1 ms) they need not.
  Cheby1Spec s;
  s.low_hz = 1.0;
  s.high_hz = 60.0;
  const double m1 = filtfilt_from_rest(cheby1(s, 1000.0), ringing(1000.0, 2.9993)).cwiseAbs().maxCoeff();
  const double m10 = filtfilt_from_rest(cheby1(s, 10000.0), ringing(10000.0, 2.9999)).cwiseAbs().maxCoeff();
  REQUIRE(std::abs(m1 / m10 - 1.0) < 2e-3);
}

TEST_CASE("sosfilt gives the numbers of one section at a time for 1 to 12 sections, with initial and final states") {
  // sosfilt runs the sections sample by sample, in groups of up to four; every operation is the
  // one of the plain section-after-section loop below on the same numbers, so the results are
  // equal exactly (a wrong group boundary, state or section order fails by far more).
  const Vector x = ringing(1000.0, 2.0);
  for (int order = 1; order <= 12; ++order) {
    Cheby1Spec s;
    s.order = order;
    s.band = order % 2 ? BandType::bandpass : BandType::lowpass;  // bandpass: order sections; lowpass: ⌈order/2⌉
    s.low_hz = 2.0;
    s.high_hz = 40.0;
    const Sos sos = cheby1(s, 1000.0);
    const std::size_t ns = sos.n_sections();
    std::vector<std::array<double, 2>> zi(ns);
    for (std::size_t k = 0; k < ns; ++k) zi[k] = {0.01 * static_cast<double>(k + 1), -0.02 * static_cast<double>(k)};
    Vector expected = x;
    std::vector<std::array<double, 2>> zf_expected(ns);
    for (std::size_t k = 0; k < ns; ++k) {
      const Section& c = sos.sections[k];
      double z0 = zi[k][0], z1 = zi[k][1];
      for (Index i = 0; i < expected.size(); ++i) {
        const double xi = expected[i], yi = c[0] * xi + z0;
        z0 = c[1] * xi - c[4] * yi + z1;
        z1 = c[2] * xi - c[5] * yi;
        expected[i] = yi;
      }
      zf_expected[k] = {z0, z1};
    }
    Vector y;
    std::vector<std::array<double, 2>> zf;
    sosfilt(sos, x, y, &zi, &zf);
    INFO("order " << order << ", " << ns << " sections");
    REQUIRE(y.size() == x.size());
    REQUIRE((y - expected).cwiseAbs().maxCoeff() == 0.0);
    REQUIRE(zf == zf_expected);
    // In place, as filtfilt_from_rest's second pass does not, but a caller may.
    Vector inplace = x;
    sosfilt(sos, inplace, inplace, &zi);
    REQUIRE((inplace - expected).cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("one FiltfiltFromRest serves many records with filtfilt_from_rest's numbers") {
  Cheby1Spec s;
  s.low_hz = 1.0;
  s.high_hz = 30.0;
  const Sos sos = cheby1(s, 1000.0);
  const FiltfiltFromRest filt(sos);
  for (double d : {0.0, 0.001, 0.5, 3.0}) {
    const Vector x = ringing(1000.0, d);
    const Vector a = filt(x), b = filtfilt_from_rest(sos, x);
    REQUIRE(a.size() == x.size());
    REQUIRE((a.size() == 0 || (a - b).cwiseAbs().maxCoeff() == 0.0));
  }
  // Many records at once, of different lengths (one empty, one of a single sample) and a count
  // that is not a multiple of four: each the very numbers of the one-record call, with a filter
  // of one chunk of sections (order 3 band-pass: three) and one of two (order 5: four and one).
  for (int order : {3, 5}) {
    s.order = order;
    const Sos so = cheby1(s, 1000.0);
    const FiltfiltFromRest f(so);
    std::vector<Vector> xs;
    for (double d : {0.3, 0.0, 0.5, 0.001, 0.7, 0.45, 0.31, 0.2, 0.6}) xs.push_back(ringing(1000.0, d));
    xs[3] = Vector::Constant(1, 2.5);
    const std::vector<Vector> many = f(xs);
    REQUIRE(many.size() == xs.size());
    for (std::size_t k = 0; k < xs.size(); ++k) {
      INFO("order " << order << ", record " << k << " of " << xs[k].size() << " samples");
      const Vector one = f(xs[k]);
      REQUIRE(many[k].size() == one.size());
      CHECK((one.size() == 0 || (many[k] - one).cwiseAbs().maxCoeff() == 0.0));
    }
  }
  // An unstable filter is refused when the operator is built.
  Sos bad = sos;
  bad.sections[0][5] = 1.5;  // a pole pair outside the unit circle
  REQUIRE_THROWS_AS(FiltfiltFromRest(bad), InputError);
}
