#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "span_run.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/study/speed.hpp"

using namespace viaduct;
using namespace viaduct::study;

TEST_CASE("a simulated train's speed is recovered within 0.5 % (spectral lines and axle peaks)") {
  // A 20 m span under 12 axles 13.14 m apart (a Talgo-like rake) at 43.0 m/s, 2 % damping.
  const double v = 43.0, d = 13.14;
  const RunResult r = test::mid_span_run(20.0, 2e10, 15000.0, load::regular_train("rake", 12, d, 140e3), v, 1.0);
  const SpeedEstimate sp = speed_from_spectrum(r.stations[0].acc, 500.0, d, 20.0, 80.0, 4);
  std::printf("speed from spectrum: %.3f m/s (true %.1f, %+.2f %%, resolution %.2f m/s)\n", sp.speed, v,
              100 * (sp.speed / v - 1), sp.uncertainty);
  REQUIRE(sp.speed == Approx(v).epsilon(0.005));  // issue #3: within 0.5 % (measured +0.37 %)
  // Axle peaks need a channel that sees each axle: on this 4.5 Hz span the vibration period
  // (0.22 s) rivals the axle interval (0.31 s), so use a stiff 10 m span (f1 = 22 Hz) whose
  // deflection follows the axles quasi-statically.
  const RunResult r2 = test::mid_span_run(10.0, 2e10, 10000.0, load::regular_train("rake", 12, d, 140e3), v, 1.0);
  const SpeedEstimate pk = speed_from_peaks(r2.stations[0].disp, 500.0, d, 0.2);
  std::printf("speed from axle peaks: %.3f m/s (%+.2f %%, +- %.3f m/s from %d intervals)\n", pk.speed,
              100 * (pk.speed / v - 1), pk.uncertainty, pk.n_used);
  REQUIRE(pk.speed == Approx(v).epsilon(0.005));
  REQUIRE(pk.n_used >= 10);
  REQUIRE_THROWS_WITH(speed_from_spectrum(r.stations[0].acc, 500.0, d, 20.0, 900.0, 4), Catch::Contains("Nyquist"));
  REQUIRE_THROWS_AS(speed_from_spectrum(r.stations[0].acc, 500.0, 0.0, 20.0, 80.0), InputError);
  REQUIRE_THROWS_WITH(speed_from_peaks(Vector::Zero(100), 500.0, d, 0.2), Catch::Contains("no train found"));
  // Never a speed outside the range searched (issue #36: 36 190 km/h from a 100-200 km/h search).
  REQUIRE_THROWS_WITH(speed_from_peaks(r2.stations[0].disp, 500.0, d, 0.2, 100 / 3.6, 140 / 3.6),
                      Catch::Contains("no train found between 100 and 140 km/h") && Catch::Contains("gives 154."));
  CHECK(speed_from_peaks(r2.stations[0].disp, 500.0, d, 0.2, 100 / 3.6, 200 / 3.6).speed == Approx(pk.speed));
  CHECK(sp.detection > 1.5 * kMinSpectralDetection);  // a train's lines stand out (measured 9.8; noise at most 3.8)
  CHECK(pk.detection > 5 * kMinPeakDetection);        // measured 75 (white noise at most 8.8)
}

TEST_CASE("no train found: a constant channel, a zero one, noise without a train (issue #36)") {
  const double fs = 500.0, d = 13.14;
  std::mt19937 rng(36);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Vector noise(30 * 500);
  for (Index i = 0; i < noise.size(); ++i) noise[i] = 1e-3 * gauss(rng);
  for (const Vector& x : {Vector(Vector::Zero(5000)), Vector(Vector::Constant(5000, 3.0)), noise}) {
    REQUIRE_THROWS_WITH(speed_from_spectrum(x, fs, d, 100 / 3.6, 200 / 3.6, 4), Catch::Contains("no train found"));
    REQUIRE_THROWS_WITH(speed_from_peaks(x, fs, d, 0.2, 100 / 3.6, 200 / 3.6), Catch::Contains("no train found"));
  }
  // Low-passed noise (smooth, so its peaks look like axles to a naive search) stays "no train".
  signal::Cheby1Spec lp;
  lp.band = signal::BandType::lowpass;
  lp.high_hz = 10.0;
  const Vector smooth = signal::sosfiltfilt(signal::cheby1(lp, fs), noise);
  REQUIRE_THROWS_WITH(speed_from_spectrum(smooth, fs, d, 100 / 3.6, 200 / 3.6, 4), Catch::Contains("no train found"));
}

TEST_CASE("delay between two sensors: the lag of a noisy copy within its standard error") {
  // b is a delayed by 0.12345 s (61.725 samples at 500 Hz: a fraction of a sample) with 5 %
  // noise on both: the delay is found within 3 standard errors and the errors are of the noise.
  const double fs = 500.0, delay = 0.12345;
  const Index n = 3000;
  auto pulse = [](double t) { return std::exp(-std::pow((t - 2.0) / 0.15, 2)) - 0.6 * std::exp(-std::pow((t - 3.1) / 0.2, 2)); };
  Vector a(n), b(n);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05 * 0.3);
  for (Index j = 0; j < n; ++j) {
    const double t = static_cast<double>(j) / fs;
    a[j] = pulse(t) + noise(rng);
    b[j] = pulse(t - delay) + noise(rng);
  }
  // Low-passed at 20 Hz (the pulses' content is below 5 Hz): the noise of the first channel,
  // which the fit delays, is then smooth.
  FilterSpec lp;
  lp.cheby.band = signal::BandType::lowpass;
  lp.cheby.high_hz = 20.0;
  const Delay d = delay_between(a, b, fs, lp, 1.0);
  INFO("delay " << d.delay_s << " +- " << d.delay_se);
  REQUIRE(std::abs(d.delay_s - delay) <= 3 * d.delay_se);
  REQUIRE(d.delay_se < 5e-4);  // a quarter of a sample: pulses 75 samples wide, 5 % noise on both within 20 Hz
  REQUIRE(d.correlation > 0.98);
  REQUIRE_THROWS_AS(delay_between(a, b.head(100), fs, lp, 1.0), InputError);
}

TEST_CASE("signature match: a template of known speed and shift, and what is refused") {
  // Template: two bumps 20 m apart passing at v (their times 20/v apart); the record is the
  // template at 30 m/s, 1.5 s late, with 2 % noise.
  const double fs = 400.0;
  auto make = [&](double v) {
    const Index n = static_cast<Index>((60.0 / v + 0.5) * fs);
    Vector m(n);
    for (Index j = 0; j < n; ++j) {
      const double x = v * static_cast<double>(j) / fs;  // travelled [m]
      m[j] = std::exp(-std::pow((x - 10.0) / 2.0, 2)) + 0.7 * std::exp(-std::pow((x - 30.0) / 2.0, 2));
    }
    return m;
  };
  const Vector truth = make(30.0);
  Vector rec = Vector::Zero(truth.size() + 1000);
  rec.segment(600, truth.size()) = truth;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (Index j = 0; j < rec.size(); ++j) rec[j] += noise(rng);
  SignatureOptions o;
  o.v_min = 20.0;
  o.v_max = 45.0;
  o.filter.enabled = false;
  o.max_shift_s = 10.0;
  const std::function<Vector(double)> at = make;
  const SignatureMatch m = match_signature(rec, fs, 0.0, at, fs, o);
  INFO("v " << m.speed << " +- " << m.speed_se << ", shift " << m.shift_s << " +- " << m.shift_se);
  REQUIRE(std::abs(m.speed - 30.0) <= 3 * m.speed_se);
  REQUIRE(std::abs(m.shift_s - 1.5) <= 3 * m.shift_se);
  REQUIRE(m.amplitude == Approx(1.0).epsilon(0.02));
  REQUIRE(m.n_evaluations > 40);
  o.v_max = 10.0;
  REQUIRE_THROWS_WITH(match_signature(rec, fs, 0.0, at, fs, o), Catch::Contains("need v_max > v_min"));
}

TEST_CASE("axles matched to the peaks of a channel that sees them, and not where it merges them") {
  // A two-car unit (bogies 2.7 m, centres 19 m) at 25 m/s over a sensor whose influence line is a
  // Gaussian of 0.4 m (sigma): each axle a pulse at entry + offset/v, 3 % noise, 1 kHz.
  load::Train t;
  t.name = "unit";
  for (double car : {0.0, 26.0})
    for (double x : {0.0, 2.7, 19.0, 21.7}) t.offset.push_back(car + x), t.load.push_back(150e3);
  const double v = 25.0, fs = 1000.0, entry = 0.73, t0 = 0.1;
  auto record = [&](double sigma_m) {
    Vector x = Vector::Zero(3000);
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.03);
    for (Index i = 0; i < x.size(); ++i) {
      const double time = t0 + static_cast<double>(i) / fs;
      for (double off : t.offset) x[i] += std::exp(-0.5 * std::pow((time - entry - off / v) * v / sigma_m, 2));
      x[i] += noise(rng);
    }
    return x;
  };
  study::FilterSpec lp;
  lp.cheby.band = signal::BandType::lowpass;
  lp.cheby.high_hz = 60.0;
  const study::AxleMatch m = study::match_axles(record(0.4), fs, t0, t, v, 0.0, entry, 0.0, lp);
  REQUIRE(m.axles.size() == 8);
  CHECK(m.n_seen == 8);
  CHECK(m.tolerance_s == Approx(0.1 * 2.7 / v));
  for (const auto& a : m.axles) {
    CHECK(a.t_s == Approx(entry + a.offset_m / v));
    CHECK(std::abs(a.peak_t_s - a.t_s) < 2.0 / fs);  // the pulse's centre, to the filter's and noise's resolution
  }
  CHECK(m.rms_residual_s < 1.0 / fs);
  // An influence line of 2 m (sigma) merges each bogie's two axles into one hump between them:
  // no axle is claimed on a peak 1.35 m (54 ms) away from it.
  const study::AxleMatch w = study::match_axles(record(2.0), fs, t0, t, v, 0.0, entry, 0.0, lp);
  CHECK(w.n_seen == 0);
  // A speed 3 % off puts the far axles outside the window: fewer seen, as it should say.
  const study::AxleMatch off = study::match_axles(record(0.4), fs, t0, t, 1.03 * v, 0.0, entry, 0.0, lp);
  CHECK(off.n_seen < 8);
  CHECK_THROWS_AS(study::match_axles(record(0.4), fs, t0, t, 0.0, 0.0, entry, 0.0, lp), InputError);
  CHECK_THROWS_AS(study::match_axles(record(0.4), fs, t0, t, v, -1.0, entry, 0.0, lp), InputError);
}

namespace {

// A strain gauge's record by hand (independent of viaduct's solver): every axle's load times a
// triangular influence line of half-length `half_m` centred on the gauge, plus white noise of
// `noise` times the peak. Returns the samples at fs from t = 0; the first axle passes at entry.
Vector gauge_record(const load::Train& train, double v, double entry, double half_m, double fs, double duration, double noise,
                    unsigned seed) {
  const auto n = static_cast<Index>(duration * fs);
  Vector x = Vector::Zero(n);
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / fs;
    for (std::size_t a = 0; a < train.n_axles(); ++a) {
      const double xi = v * (t - entry) - train.offset[a];  // the axle's distance past the gauge
      if (std::abs(xi) < half_m) x[k] += train.load[a] * 1e-4 * (1.0 - std::abs(xi) / half_m);  // [µε]
    }
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, noise * x.cwiseAbs().maxCoeff());
  for (Index k = 0; k < n; ++k) x[k] += g(rng);
  return x;
}

}  // namespace

TEST_CASE("speed from the train alone: axle or bogie peaks matched to the train's geometry (issue #39 item 5)", "[long]") {
  const load::Train a1 = load::hslm_a("HSLM-A1", load::hslm_a_row(1));
  const double fs = 1000.0;
  TrainTimingOptions o;
  o.v_min = 100 / 3.6;
  o.v_max = 360 / 3.6;
  for (const double v_kmh : {120.0, 250.0}) {
    const double v = v_kmh / 3.6, entry = 1.3, duration = entry + a1.length() / v + 1.0;
    // A gauge that sees axles one by one (0.6 m half-length: a cross-girder), then one that
    // merges each bogie's two axles (2 m apart under a 2 m half-length): bogies are matched.
    for (const double half : {0.6, 2.0}) {
      for (unsigned seed : {1u, 2u, 3u}) {
        const Vector x = gauge_record(a1, v, entry, half, fs, duration, 0.03, seed);
        const TrainTiming r = speed_from_train(x, fs, 0.0, a1, o);
        INFO("v " << v_kmh << " km/h, half-length " << half << " m, seed " << seed << ": " << r.speed * 3.6 << " km/h +- "
                  << 3 * r.speed_se * 3.6 << ", " << r.n_matched << " of " << r.n_groups << " groups (merge " << r.merge_m << " m)");
        REQUIRE(std::abs(r.speed - v) < 0.005 * v);         // the 0.5 %
        REQUIRE(std::abs(r.speed - v) <= 3.0 * r.speed_se);  // and the stated uncertainty (3 standard errors) covers it
        REQUIRE(std::abs(r.entry_s - entry) <= std::max(3.0 * r.entry_se, 2.0 / fs));
        REQUIRE(r.n_matched >= r.n_groups * 9 / 10);
        if (half == 2.0) REQUIRE(r.merge_m > 0.0);  // bogies (and the close pairs of the power cars) merged
        if (half == 0.6) REQUIRE(r.merge_m == 0.0);
      }
    }
  }
  // Noise alone: no train found.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  Vector noise(20000);
  for (Index k = 0; k < noise.size(); ++k) noise[k] = g(rng);
  FilterSpec lp;
  lp.cheby.band = signal::BandType::lowpass;
  lp.cheby.high_hz = 20.0;
  o.filter = lp;
  REQUIRE_THROWS_WITH(speed_from_train(noise, fs, 0.0, a1, o), Catch::Contains("no train found"));
}

TEST_CASE("a doubted signature match is flagged and its uncertainty covers the axles' timing alone") {
  // The matches are made by hand (what a mismatched model gives: a tight speed that is off), the
  // record by gauge_record (axles seen one by one), so only the checks are under test.
  const load::Train a1 = load::hslm_a("HSLM-A1", load::hslm_a_row(1));
  const double fs = 1000.0, v = 200 / 3.6, entry = 1.3;
  const Vector x = gauge_record(a1, v, entry, 0.6, fs, entry + a1.length() / v + 1.0, 0.03, 4u);
  const FilterSpec none;
  auto match = [&](double speed, double amplitude, double correlation) {
    SignatureMatch m;
    m.speed = speed, m.speed_se = 1e-4 * v, m.amplitude = amplitude, m.correlation = correlation;
    return m;
  };
  auto check = [&](const SignatureMatch& m, ResponseKind k) {
    return check_train_signature(m, a1, k, x, fs, 0.0, none, 150 / 3.6, 260 / 3.6);
  };
  // A model that matches: nothing said, nothing widened.
  const SignatureCheck good = check(match(v, 1.0, 0.99), ResponseKind::strain);
  CHECK(good.timing_checked);
  CHECK(good.flags.empty());
  CHECK(good.speed_se == 1e-4 * v);
  // 1 % off beyond both uncertainties: flagged by the timing, widened to cover the truth.
  const SignatureCheck off = check(match(1.01 * v, 1.0, 0.99), ResponseKind::strain);
  REQUIRE(off.flags.size() == 2);
  CHECK_THAT(off.flags[0], Catch::Contains("the axles' timing alone"));
  CHECK(3 * off.speed_se >= 0.01 * v);
  // 0.2 % off, inside the timing's own uncertainty, but the amplitude says the model is wrong
  // (the 18 m model of a 15 m span): the stated 3 standard errors did not cover 0.2 %, now they do.
  const SignatureCheck scaled = check(match(0.998 * v, 0.224, 0.95), ResponseKind::strain);
  CHECK(std::any_of(scaled.flags.begin(), scaled.flags.end(), [](const std::string& f) { return f.find("x the model") != std::string::npos; }));
  CHECK(3 * scaled.speed_se >= 0.002 * v);
  CHECK(3 * scaled.speed_se >= std::abs(scaled.timing_speed - 0.998 * v));
  // A poor correlation alone is flagged too; an acceleration has no model-free timing: flagged,
  // its standard error left as it is (nothing to widen it with).
  CHECK_THAT(check(match(v, 1.0, 0.8), ResponseKind::strain).flags.front(), Catch::Contains("correlation 0.8"));
  const SignatureCheck acc = check(match(0.998 * v, 0.224, 0.95), ResponseKind::acceleration);
  CHECK_FALSE(acc.timing_checked);
  CHECK(acc.flags.size() == 1);
  CHECK(acc.speed_se == 1e-4 * v);
}
