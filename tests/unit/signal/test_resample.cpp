#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/resample.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::signal;

namespace {
std::vector<double> numbers(const std::string& line) {
  std::vector<double> v;
  std::stringstream ss(line);
  std::string c;
  while (std::getline(ss, c, ',')) v.push_back(c == "nan" ? NAN : std::stod(c));
  return v;
}
Vector resample_vec(const std::vector<double>& v) { return Eigen::Map<const Vector>(v.data(), static_cast<Index>(v.size())); }
double rel(const Vector& a, const Vector& b) { return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff(); }
}  // namespace

TEST_CASE("decimate and the Hilbert envelope match SciPy") {
  std::ifstream in(std::string(VIADUCT_SOURCE_DIR) + "/tests/data/resample_reference.csv");
  REQUIRE(in.good());
  std::string line, block;
  std::vector<double> x, env, env_even, d4, d10;
  while (std::getline(in, line)) {
    if (line.rfind("# d4", 0) == 0) { block = "d4"; continue; }
    if (line.rfind("# d10", 0) == 0) { block = "d10"; continue; }
    if (line.empty() || line[0] == '#') continue;
    const auto v = numbers(line);
    if (block.empty()) {
      x.push_back(v[0]);
      env.push_back(v[1]);
      if (!std::isnan(v[2])) env_even.push_back(v[2]);
    } else if (block == "d4") {
      d4 = v;
    } else {
      d10 = v;
    }
  }
  const Vector X = resample_vec(x);
  // Same filter pipeline as SciPy: agreement to round-off, bounded by the 1e-9 used for filters.
  REQUIRE(decimate(X, 4).size() == static_cast<Index>(d4.size()));
  REQUIRE(rel(decimate(X, 4), resample_vec(d4)) < 1e-9);
  REQUIRE(rel(decimate(X, 10), resample_vec(d10)) < 1e-9);
  REQUIRE(rel(hilbert_envelope(X), resample_vec(env)) < 1e-12);  // one FFT pair: round-off only
  REQUIRE(rel(hilbert_envelope(X.head(X.size() - 1)), resample_vec(env_even)) < 1e-12);
  REQUIRE_THROWS_AS(decimate(X, 1), InputError);
}

TEST_CASE("resampling, running RMS and max-abs envelope") {
  const double fs = 1000.0;
  Vector x(3001);
  for (Index j = 0; j < x.size(); ++j) x[j] = std::sin(2 * M_PI * 5.0 * static_cast<double>(j) / fs);
  // Down to 200 Hz: a 5 Hz sine passes the anti-alias filter (edge 80 Hz) unchanged.
  const Vector y = resample(x, fs, 200.0);
  REQUIRE(y.size() == 601);
  double err = 0;
  for (Index j = 50; j < 550; ++j) err = std::max(err, std::abs(y[j] - std::sin(2 * M_PI * 5.0 * static_cast<double>(j) / 200.0)));
  // Chebyshev I ripples across the whole passband: forward and backward, up to 2 x 0.05 dB
  // = 1.2 % of the amplitude (0.9 % measured at 5 Hz).
  REQUIRE(err < 0.012);
  // Up to 4096 Hz: linear interpolation of a 5 Hz sine sampled at 1 kHz, error ~ (ω h)²/8.
  const Vector z = resample(x, fs, 4096.0);
  REQUIRE(std::abs(z[z.size() / 2] - std::sin(2 * M_PI * 5.0 * static_cast<double>(z.size() / 2) / 4096.0)) < 2e-4);
  // RMS of a sine over whole periods is amplitude / √2.
  const Vector r = running_rms(x, 1001);  // 5 periods and one sample: 0.1 % from the ideal
  REQUIRE(r[1500] == Approx(1.0 / std::sqrt(2.0)).epsilon(1e-3));
  const Vector m = maxabs_envelope(x, 101);
  REQUIRE(m[1500] == Approx(1.0).epsilon(1e-3));
  Vector pulse = Vector::Zero(50);
  pulse[20] = -3.0;
  const Vector mp = maxabs_envelope(pulse, 5);
  REQUIRE(mp[18] == 3.0);
  REQUIRE(mp[22] == 3.0);
  REQUIRE(mp[17] == 0.0);
  REQUIRE(mp[23] == 0.0);
  REQUIRE_THROWS_WITH(running_rms(x, 4), Catch::Contains("odd"));
  Vector bad = x;
  bad[7] = NAN;
  REQUIRE_THROWS_WITH(resample(bad, fs, 100.0), Catch::Contains("NaN"));
}

TEST_CASE("records of huge or tiny samples: the same results scaled, no overflow, and rates that leave no samples refused") {
  const Index n = 4096;
  Vector x(n);
  for (Index k = 0; k < n; ++k) x[k] = std::sin(0.05 * k) + 0.3 * std::cos(0.31 * k);
  // Scaled by powers of two far beyond the range where squares overflow (1e154) or underflow:
  // the envelopes are the unscaled ones times the scale (power-of-two scaling is exact; only the
  // squares would leave the range). 1e-12: FFT rounding, relative to an envelope of order 1.
  for (const int e : {600, -700}) {
    INFO("scale 2^" << e);
    const double s = std::ldexp(1.0, e);
    const Vector env = hilbert_envelope(s * x), rms = running_rms(s * x, 101);
    REQUIRE(env.allFinite());
    REQUIRE(rms.allFinite());
    CHECK((env / s - hilbert_envelope(x)).cwiseAbs().maxCoeff() <= 1e-12);
    CHECK((rms / s - running_rms(x, 101)).cwiseAbs().maxCoeff() <= 1e-12);
  }
  WelchOptions o;
  o.nperseg = 512;
  // Samples of 1e155 at 1 MHz: |X|² overflows, the density (about 1e307) does not.
  const Psd p = welch(1e155 * x, 1e6, o), p0 = welch(x, 1e6, o);
  REQUIRE(p.density.allFinite());
  CHECK((p.density / 1e155 / 1e155 - p0.density).cwiseAbs().maxCoeff() <= 1e-12 * p0.density.maxCoeff());
  // Subnormal samples (about 2^-1060, below the smallest normal double): scaled up by 2^1022 at
  // most, since 2^1060 is not a double. Subnormals are spaced 2^-1074 apart, so the samples keep
  // 14 bits; the envelope is that of the samples as stored (xq), times 2^-1060, and is itself
  // stored as subnormals: 2^-13, twice the spacing 2^-1074 relative to 2^-1060.
  const Vector stored = std::ldexp(1.0, -530) * (std::ldexp(1.0, -530) * x);
  const Vector xq = std::ldexp(1.0, 530) * (std::ldexp(1.0, 530) * stored);
  const Vector env_sub = hilbert_envelope(stored);
  REQUIRE(env_sub.allFinite());
  CHECK((xq - x).cwiseAbs().maxCoeff() > 0.0);  // the samples did lose bits
  CHECK((std::ldexp(1.0, 530) * (std::ldexp(1.0, 530) * env_sub) - hilbert_envelope(xq)).cwiseAbs().maxCoeff() <= std::ldexp(1.0, -13));
  // One that overflows is refused, not written as inf.
  CHECK_THROWS_WITH(welch(std::ldexp(1.0, 600) * x, 100.0, o), Catch::Contains("overflows a double"));
  // Rate changes that would leave fewer than two samples, or billions of them.
  CHECK_THROWS_WITH(resample(x, 100.0, 1e-308), Catch::Contains("fewer than two samples"));
  CHECK_THROWS_WITH(resample(x, 100.0, 1e12), Catch::Contains("more than the limit"));
  CHECK_THROWS_WITH(decimate(x, static_cast<int>(n)), Catch::Contains("fewer than two"));
}
