// FRF estimation: Welch H1/H2/coherence, stepped sine and swept sine on systems with known FRFs.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "synthetic.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/ident/frf.hpp"
#include "viaduct/solve/newmark.hpp"

using namespace viaduct;
using namespace viaduct::ident;

namespace {
double rel(Complex a, Complex b) { return std::abs(a - b) / std::abs(b); }

// Newmark (average acceleration) response of the system's outputs to its force, sampled at fs.
// Its period error is (ω dt)²/12: 3e-5 at 10 Hz with fs = 2 kHz, so FRFs are exact to 1e-3.
Matrix simulate(const vt::PhysicalSystem& s, double fs, double t_end, bool acceleration) {
  const solve::NewmarkOptions o;
  const solve::TimeGrid g{1.0 / fs, t_end};
  const Index n = static_cast<Index>(std::ceil(t_end * fs - 1e-9)) + 1;
  Matrix y(n, s.n_dofs());
  solve::newmark(s, g, o, [&](Index k, double, const Vector& u, const Vector&, const Vector& a) {
    if (k < n) y.row(k) = (acceleration ? a : u).transpose();
  });
  return y;
}
}  // namespace

TEST_CASE("Welch H1 of a delayed copy has the phase -360 f tau: SciPy's conj(X) Y sign") {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  const double fs = 100.0;
  const Index n = 8192, lag = 3;
  Vector x(n), y(n);
  for (Index k = 0; k < n; ++k) x[k] = g(rng);
  for (Index k = 0; k < n; ++k) y[k] = k >= lag ? 2.0 * x[k - lag] : 0.0;
  signal::WelchOptions o;
  o.nperseg = 512;
  const WelchFrf r = welch_frf(x, y, fs, o);
  for (Index k = 5; k < r.frequency_hz.size() - 5; k += 20) {
    const double f = r.frequency_hz[k];
    const Complex expected = 2.0 * std::polar(1.0, -2 * M_PI * f * lag / fs);
    // Segment edges lose 3 of 512 samples to the lag: a 1 % bias, plus averaging noise.
    CHECK(rel(r.h1(k, 0), expected) < 0.03);
    CHECK(r.coherence(k, 0) > 0.97);
  }
}

TEST_CASE("H1 is unbiased under output noise, H2 is biased by 1/coherence") {
  std::mt19937 rng(2);
  std::normal_distribution<double> g;
  const double fs = 200.0;
  const Index n = 200000;
  Vector x(n), y(n);
  for (Index k = 0; k < n; ++k) x[k] = g(rng);
  // FIR y = x[k] + 0.3 x[k-1] - 0.2 x[k-2]: H(f) known exactly, |H| >= 0.5.
  for (Index k = 0; k < n; ++k) y[k] = x[k] + (k > 0 ? 0.3 * x[k - 1] : 0) - (k > 1 ? 0.2 * x[k - 2] : 0);
  const double noise_rms = 0.2;
  for (Index k = 0; k < n; ++k) y[k] += noise_rms * g(rng);
  signal::WelchOptions o;
  o.nperseg = 256;
  const WelchFrf r = welch_frf(x, y, fs, o);
  double worst_h1 = 0, mean_h2_bias = 0;
  int count = 0;
  for (Index k = 3; k < r.frequency_hz.size() - 3; ++k) {
    const double w = 2 * M_PI * r.frequency_hz[k] / fs;
    const Complex H = 1.0 + 0.3 * std::polar(1.0, -w) - 0.2 * std::polar(1.0, -2 * w);
    worst_h1 = std::max(worst_h1, rel(r.h1(k, 0), H));
    // Expected coherence: |H|² Sxx / (|H|² Sxx + Snn), white input and noise.
    const double coh = std::norm(H) / (std::norm(H) + noise_rms * noise_rms);
    CHECK(r.coherence(k, 0) == Approx(coh).margin(0.05));
    mean_h2_bias += std::abs(r.h2(k, 0)) / std::abs(H) - 1.0 / coh;
    ++count;
  }
  // 1500 averages: random error of H1 about (1-γ²)/(2γ² n_avg) ~ 1 %; 5 % bounds the worst line.
  CHECK(worst_h1 < 0.05);
  CHECK(std::abs(mean_h2_bias / count) < 0.02);
  CHECK_THROWS_AS(welch_frf(Vector::Zero(n), y, fs, o), InputError);            // zero force
  CHECK_THROWS_AS(welch_frf(x, Matrix(y.head(n - 1)), fs, o), InputError);      // mismatched lengths
}

TEST_CASE("Stepped sine recovers the FRF of a 2-DOF system point by point", "[long]") {
  vt::ModalSystem m;
  m.f_hz = {5.0, 5.1};
  m.zeta = {0.01, 0.01};
  m.shapes = {{1.0, 0.6}, {0.7, -1.0}};
  const auto sched = regular_schedule(4.6, 5.5, 10, 30.0);
  const double F0 = 1000.0;
  // Phase-continuous drive that jumps in frequency at each dwell.
  auto force = [&](double t) {
    double phase = 0;
    for (const auto& s : sched) {
      const double d = std::min(t, s.t_end_s) - s.t_start_s;
      if (d <= 0) break;
      phase += 2 * M_PI * s.frequency_hz * d;
    }
    return F0 * std::sin(phase);
  };
  const vt::PhysicalSystem sys(m, force);
  const double fs = 2000.0;
  const Matrix y = simulate(sys, fs, sched.back().t_end_s, true);
  Vector f(y.rows());
  for (Index k = 0; k < f.size(); ++k) f[k] = force(static_cast<double>(k) / fs);
  SteppedSineOptions o;
  o.settle_cycles = 100;  // 1 % damping: e^{-2π·0.01·100} = 0.2 % of the transient left
  const auto pts = stepped_sine(f, y, fs, 0.0, sched, o);
  REQUIRE(pts.size() == sched.size());
  for (const auto& p : pts) {
    for (Index c = 0; c < 2; ++c) {
      const Complex H = -std::pow(2 * M_PI * p.frequency_hz, 2) * m.receptance(c, p.frequency_hz);
      INFO("f " << p.frequency_hz << " channel " << c);
      // The transient left after 100 cycles (0.2 %) and the Newmark error (3e-5 in frequency,
      // 1 % damping: 0.3 % near resonance): 1 % bounds each point.
      CHECK(rel(p.h[c], H) < 0.01);
    }
    CHECK(p.force_distortion < 1e-6);
    CHECK(p.frequency_hz == Approx(sched[&p - &pts[0]].frequency_hz).epsilon(1e-6));
  }
  // Without settling the transient shows: settle_change grows.
  o.settle_cycles = 0;
  const auto raw = stepped_sine(f, y, fs, 0.0, sched, o);
  double worst_settled = 0, worst_raw = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    worst_settled = std::max(worst_settled, pts[k].settle_change.maxCoeff());
    worst_raw = std::max(worst_raw, raw[k].settle_change.maxCoeff());
  }
  CHECK(worst_raw > 3 * worst_settled);
}

TEST_CASE("Stepped-sine steps are found from a noisy force alone") {
  const auto sched = regular_schedule(8.0, 9.0, 11, 6.0);  // 0.1 Hz steps: 1.25 % to 1.1 % apart
  const double fs = 200.0;
  const Index n = static_cast<Index>(sched.back().t_end_s * fs);
  Vector f(n);
  double phase = 0.0;
  for (Index k = 0; k < n; ++k) {
    const double t = k / fs;
    std::size_t s = 0;
    while (s + 1 < sched.size() && t >= sched[s].t_end_s) ++s;
    f[k] = 5e3 * std::sin(phase);
    phase += 2 * M_PI * sched[s].frequency_hz / fs;
  }
  std::mt19937 rng(4);
  vt::add_noise(f, 40.0, rng);
  const auto found = detect_steps(f, fs, 0.0);
  REQUIRE(found.size() == sched.size());
  for (std::size_t k = 0; k < sched.size(); ++k) {
    // Frequency: the median of ~50 cycle periods, each jittered by noise/(amplitude·ω).
    CHECK(found[k].frequency_hz == Approx(sched[k].frequency_hz).epsilon(1e-3));
    // Starts within three cycles (crossings, the running median, the persistence test); ends
    // never late (no cycle of the next step), at most 4 + 6 cycles early (the margin).
    const double T = 1.0 / sched[k].frequency_hz;
    CHECK(std::abs(found[k].t_start_s - sched[k].t_start_s) < 3 * T);
    CHECK(found[k].t_end_s <= sched[k].t_end_s + 1e-9);
    CHECK(found[k].t_end_s > sched[k].t_end_s - 10 * T);
  }
  CHECK_THROWS_WITH(detect_steps(Vector::Zero(n), fs, 0.0), Catch::Contains("zero"));
  StepDetectionOptions o;
  o.min_cycles = 1000;  // longer than any step
  CHECK_THROWS_WITH(detect_steps(f, fs, 0.0, o), Catch::Contains("no steady sine"));
}

TEST_CASE("Stepped-sine distortion indicator reads a harmonic's share, bad schedules are refused") {
  const double fs = 500.0, f0 = 7.0;
  const Index n = 5000;
  Vector f(n);
  Matrix y(n, 1);
  for (Index k = 0; k < n; ++k) {
    const double t = k / fs;
    f[k] = std::cos(2 * M_PI * f0 * t) + 0.1 * std::cos(2 * M_PI * 2 * f0 * t);
    y(k, 0) = 3.0 * std::sin(2 * M_PI * f0 * t);
  }
  const auto pts = stepped_sine(f, y, fs, 0.0, {{0.0, 10.0, f0}});
  REQUIRE(pts.size() == 1);
  // 0.1 up to the mean square of a harmonic over a non-integer number of cycles.
  CHECK(pts[0].force_distortion == Approx(0.1).epsilon(1e-3));
  // 3 sin = 3 cos(ωt − 90°): H = 3 e^{−iπ/2}.
  CHECK(rel(pts[0].h[0], Complex(0, -3.0)) < 1e-9);
  CHECK_THROWS_AS(stepped_sine(f, y, fs, 0.0, {{5.0, 20.0, f0}}), InputError);   // beyond the record
  CHECK_THROWS_AS(stepped_sine(f, y, fs, 0.0, {{0.0, 2.0, f0}}), InputError);    // 14 cycles - 30 settling
  CHECK_THROWS_AS(stepped_sine(f, y, fs, 0.0, {{0.0, 10.0, 300.0}}), InputError);  // above Nyquist
  CHECK_THROWS_AS(stepped_sine(f, y, fs, 0.0, {{0.0, 10.0, 9.0}}), InputError);    // not the force's frequency
  CHECK_THROWS_AS(stepped_sine(Vector::Zero(n), y, fs, 0.0, {{0.0, 10.0, f0}}), InputError);
}

TEST_CASE("Swept sine gives the FRF over the swept band") {
  vt::ModalSystem m;
  m.f_hz = {4.0, 9.0};
  m.zeta = {0.02, 0.02};
  m.shapes = {{1.0, 0.5}, {0.8, -1.0}};
  const double f1 = 2.0, f2 = 12.0, T = 60.0, tail = 20.0;
  auto force = [&](double t) {
    if (t > T) return 0.0;
    const double k = (f2 - f1) / T;
    return 500.0 * std::sin(2 * M_PI * (f1 * t + 0.5 * k * t * t));
  };
  const vt::PhysicalSystem sys(m, force);
  const double fs = 1000.0;
  const Matrix y = simulate(sys, fs, T + tail, true);
  Vector f(y.rows());
  for (Index k = 0; k < f.size(); ++k) f[k] = force(static_cast<double>(k) / fs);
  SweptSineOptions o;
  o.f_min_hz = 2.5;
  o.f_max_hz = 11.5;
  const Frf r = swept_sine(f, y, fs, o);
  double worst = 0;
  for (Index k = 0; k < r.frequency_hz.size(); ++k)
    for (Index c = 0; c < 2; ++c) {
      const double fk = r.frequency_hz[k];
      const Complex H = -std::pow(2 * M_PI * fk, 2) * m.receptance(c, fk);
      worst = std::max(worst, std::abs(r.h(k, c) - H) / std::abs(H));
    }
  // The ratio of transforms is exact for a linear system at rest at both record ends; the chirp's
  // abrupt start and end ripple the force spectrum near the band edges: 2 % bounds it.
  CHECK(worst < 0.02);
}
