#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::signal;

namespace {
std::vector<double> split(const std::string& line, std::vector<std::string>* text = nullptr) {
  std::vector<double> v;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    if (text) text->push_back(cell);
    try {
      v.push_back(std::stod(cell));
    } catch (const std::exception&) {
      v.push_back(NAN);
    }
  }
  return v;
}
Vector vec(const std::vector<double>& v) { return Eigen::Map<const Vector>(v.data(), static_cast<Index>(v.size())); }
}  // namespace

TEST_CASE("Welch PSD and CSD match SciPy's reference vectors") {
  const std::string dir = std::string(VIADUCT_SOURCE_DIR) + "/tests/data/spectrum_reference";
  int n_cases = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    INFO(entry.path().filename().string());
    std::ifstream in(entry.path());
    std::string line;
    int block = 0;
    double fs = 0;
    WelchOptions o;
    std::vector<double> x, y, f, pxx, rxy, ixy;
    while (std::getline(in, line)) {
      if (line.rfind("# fs,", 0) == 0) { block = 1; continue; }
      if (line.rfind("# x,y", 0) == 0) { block = 2; continue; }
      if (line.rfind("# f,", 0) == 0) { block = 3; continue; }
      if (line.empty() || line[0] == '#') continue;
      std::vector<std::string> text;
      const auto v = split(line, &text);
      if (block == 1) {
        fs = v[0];
        o.nperseg = static_cast<Index>(v[1]);
        o.noverlap = static_cast<Index>(v[2]);
        o.window = text[3] == "hann" ? Window::hann : Window::rectangular;
        o.detrend = text[4] == "constant" ? Detrend::constant : text[4] == "linear" ? Detrend::linear : Detrend::none;
      } else if (block == 2) {
        x.push_back(v[0]);
        y.push_back(v[1]);
      } else if (block == 3) {
        f.push_back(v[0]);
        pxx.push_back(v[1]);
        rxy.push_back(v[2]);
        ixy.push_back(v[3]);
      }
    }
    const Psd p = welch(vec(x), fs, o);
    const Csd c = csd(vec(x), vec(y), fs, o);
    REQUIRE(p.density.size() == static_cast<Index>(pxx.size()));
    REQUIRE((p.frequency_hz - vec(f)).cwiseAbs().maxCoeff() < 1e-9 * fs);
    // Requirement of issue #3: within 1e-9 of SciPy, relative to the spectrum's peak.
    REQUIRE((p.density - vec(pxx)).cwiseAbs().maxCoeff() < 1e-9 * vec(pxx).maxCoeff());
    ComplexVector ref(c.density.size());
    for (Index k = 0; k < ref.size(); ++k) ref[k] = {rxy[static_cast<std::size_t>(k)], ixy[static_cast<std::size_t>(k)]};
    REQUIRE((c.density - ref).cwiseAbs().maxCoeff() < 1e-9 * ref.cwiseAbs().maxCoeff());
    ++n_cases;
  }
  REQUIRE(n_cases >= 3);
}

TEST_CASE("a sine on a bin reads its exact amplitude and frequency") {
  const double fs = 1000.0;
  const Index n = 2000;  // 0.5 Hz bins
  Vector x(n);
  for (Index j = 0; j < n; ++j) x[j] = 0.2 + 1.5 * std::sin(2 * M_PI * 12.5 * j / fs + 0.3);
  const AmplitudeSpectrum a = amplitude_spectrum(x, fs);
  Index k = 0;
  a.amplitude.tail(a.amplitude.size() - 1).maxCoeff(&k);
  ++k;
  REQUIRE(a.frequency_hz[k] == Approx(12.5).epsilon(1e-14));
  REQUIRE(a.amplitude[k] == Approx(1.5).epsilon(1e-12));  // round-off of a 2000-point FFT
  REQUIRE(a.amplitude[0] == Approx(0.2).epsilon(1e-12));  // DC not doubled
  Vector nyq(8);
  for (Index j = 0; j < 8; ++j) nyq[j] = (j % 2 == 0) ? 1.0 : -1.0;
  REQUIRE(amplitude_spectrum(nyq, 8.0).amplitude[4] == Approx(1.0).epsilon(1e-14));  // Nyquist not doubled
}

TEST_CASE("Welch PSD integrates to the variance (Parseval)") {
  Vector x(1024);
  for (Index j = 0; j < x.size(); ++j) x[j] = std::sin(0.37 * j) + 0.5 * std::cos(1.9 * static_cast<double>(j * j % 7)) + 3.0;
  WelchOptions o;
  o.nperseg = x.size();
  o.noverlap = 0;
  o.window = Window::rectangular;
  const double fs = 50.0;
  const Psd p = welch(x, fs, o);
  const double df = fs / static_cast<double>(x.size());
  const double variance = (x.array() - x.mean()).square().mean();
  REQUIRE(p.density.sum() * df == Approx(variance).epsilon(1e-12));  // exact up to round-off
  o.detrend = Detrend::none;
  REQUIRE(welch(x, fs, o).density.sum() * df == Approx(x.squaredNorm() / static_cast<double>(x.size())).epsilon(1e-12));
}

TEST_CASE("cross spectrum phase: conj(X)·Y of a delayed copy lags by 2π f τ") {
  const double fs = 1000.0;
  const Index n = 8192, delay = 5;
  Vector x(n), y(n);
  for (Index j = 0; j < n; ++j) x[j] = std::sin(2 * M_PI * 31.25 * j / fs);
  for (Index j = 0; j < n; ++j) y[j] = j >= delay ? x[j - delay] : 0.0;
  WelchOptions o;
  o.nperseg = 512;  // 31.25 Hz sits on bin 16
  const Csd c = csd(x, y, fs, o);
  const double phase = std::arg(c.density[16]);
  REQUIRE(phase == Approx(-2 * M_PI * 31.25 * delay / fs).margin(1e-3));  // y lags x
}

TEST_CASE("FFT plans are shared safely between threads") {
  auto make = [](Index n, double seed) {
    Vector v(n);
    for (Index j = 0; j < n; ++j) v[j] = std::sin(seed * static_cast<double>(j + 1));
    return v;
  };
  const std::vector<Index> sizes = {64, 100, 1000, 4096, 100, 64};
  std::vector<ComplexVector> serial;
  for (std::size_t i = 0; i < sizes.size(); ++i) serial.push_back(rfft(make(sizes[i], 0.1 * static_cast<double>(i + 1))));
  std::vector<ComplexVector> threaded(sizes.size());
  std::vector<std::thread> pool;
  for (std::size_t i = 0; i < sizes.size(); ++i)
    pool.emplace_back([&, i] {
      for (int rep = 0; rep < 50; ++rep) threaded[i] = rfft(make(sizes[i], 0.1 * static_cast<double>(i + 1)));
    });
  for (auto& t : pool) t.join();
  for (std::size_t i = 0; i < sizes.size(); ++i) REQUIRE(threaded[i] == serial[i]);
}

TEST_CASE("spectra reject bad records with a clear error") {
  Vector x = Vector::Ones(100);
  WelchOptions o;
  o.nperseg = 256;
  REQUIRE_THROWS_WITH(welch(x, 100.0, o), Catch::Contains("WelchOptions::nperseg = 256: violated constraint nperseg <= the record's 100 samples"));
  o.nperseg = 50;
  o.noverlap = 50;
  REQUIRE_THROWS_WITH(welch(x, 100.0, o), Catch::Contains("noverlap in [0, nperseg)"));
  x[10] = NAN;
  REQUIRE_THROWS_WITH(welch(x, 100.0, WelchOptions{}), Catch::Contains("NaN"));
  REQUIRE_THROWS_WITH(amplitude_spectrum(x, 100.0), Catch::Contains("NaN"));
  REQUIRE_THROWS_WITH(csd(Vector::Ones(300), Vector::Ones(299), 100.0), Catch::Contains("differ in length"));
  REQUIRE_THROWS_WITH(amplitude_spectrum(Vector::Ones(10), 0.0), Catch::Contains("sampling rate"));
  REQUIRE_THROWS_AS(rfft(Vector()), InputError);
}

TEST_CASE("irfft inverts rfft and best_lag finds a known delay to a fraction of a sample") {
  Vector x(1000);
  for (Index j = 0; j < x.size(); ++j) x[j] = std::exp(-0.5 * std::pow((j - 300.0) / 20.0, 2)) + 0.1 * std::sin(0.05 * j);
  REQUIRE((irfft(rfft(x), x.size()) - x).cwiseAbs().maxCoeff() < 1e-13);
  Vector odd = x.head(999);
  REQUIRE((irfft(rfft(odd), odd.size()) - odd).cwiseAbs().maxCoeff() < 1e-13);
  // y = 1.7 x delayed by 123.4 samples (a smooth pulse, delayed by interpolation)
  Vector y(1000);
  for (Index j = 0; j < y.size(); ++j) y[j] = 1.7 * std::exp(-0.5 * std::pow((j - 423.4) / 20.0, 2));
  Vector xp(1000);
  for (Index j = 0; j < xp.size(); ++j) xp[j] = std::exp(-0.5 * std::pow((j - 300.0) / 20.0, 2));
  REQUIRE(best_lag(xp, y, 500) == Approx(123.4).margin(0.05));   // parabola on a Gaussian correlation
  REQUIRE(best_lag(y, xp, 500) == Approx(-123.4).margin(0.05));
  REQUIRE(best_lag(xp, y, 100) == Approx(100).margin(1e-9));     // clipped to the search range
}

// One reading of the window and detrend names for the CLI and the Python package (issue #37
// item 3: Python took SciPy's "boxcar", the CLI refused it).
TEST_CASE("window and detrend names: read once, the key named in the error") {
  CHECK(window_of("hann") == Window::hann);
  CHECK(window_of("rectangular") == Window::rectangular);
  CHECK(window_of("boxcar") == Window::rectangular);
  CHECK_THROWS_WITH(window_of("hamming", "--window"), "--window must be hann or rectangular, got 'hamming'");
  CHECK(detrend_of("constant") == Detrend::constant);
  CHECK(detrend_of("linear") == Detrend::linear);
  CHECK(detrend_of("none") == Detrend::none);
  CHECK_THROWS_WITH(detrend_of("quadratic"), "detrend must be constant, linear or none, got 'quadratic'");
}
