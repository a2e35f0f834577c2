#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "span_run.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/simulation.hpp"

using namespace viaduct;
using namespace viaduct::study;

TEST_CASE("comparison recovers a known time shift and gain on a simulated record") {
  // The model: a 12 m span under three 100 kN axles at 30 m/s, recorded every 2 ms.
  const RunResult r = test::mid_span_run(12.0, 5e9, 10000.0, load::regular_train("t", 3, 8.0, 100e3), 30.0, 1.5);
  const Vector& acc = r.stations[0].acc;
  // The "measurement": gain 1.25, the train arriving 0.8 s after the logger started at
  // t0 = 10 s, sampled at 800 Hz, with 2 % noise.
  const double fs = 800.0, shift = 10.8, gain = 1.25;
  const Index n = static_cast<Index>(8.0 * fs);
  Vector rec(n);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.02 * acc.cwiseAbs().maxCoeff());
  for (Index j = 0; j < n; ++j) {
    const double tm = (10.0 + static_cast<double>(j) / fs) - shift;
    const double s_idx = tm / 2e-3;
    double v = 0.0;
    if (s_idx >= 0 && s_idx < static_cast<double>(acc.size() - 1)) {
      const auto i = static_cast<Index>(s_idx);
      v = acc[i] + (s_idx - static_cast<double>(i)) * (acc[i + 1] - acc[i]);
    }
    rec[j] = gain * v + noise(rng);
  }
  ComparisonOptions o;
  o.filter.cheby.low_hz = 1.0;
  o.filter.cheby.high_hz = 30.0;
  o.max_shift_s = 5.0;
  const ChannelComparison c = compare_channel(rec, fs, 10.0, acc, 500.0, o);
  REQUIRE(c.shift_s == Approx(shift).margin(1.0 / fs));     // within one record sample
  REQUIRE(c.peak_ratio == Approx(1.0 / gain).epsilon(0.02));  // noise and filtering: 2 %
  REQUIRE(c.rms_ratio == Approx(1.0 / gain).epsilon(0.03));
  // 2 % noise (of the peak) leaves about 1 % in the 1-30 Hz band; over the overlap, which
  // includes the quiet decay, that gives r = 0.988 (measured).
  REQUIRE(c.correlation > 0.98);
  REQUIRE(c.spectral_correlation > 0.95);  // the noise floor fills quiet bins: 0.972 measured
  REQUIRE(c.f_peak_record_hz == Approx(c.f_peak_model_hz).margin(0.2));
  REQUIRE(c.t.size() == n);
  REQUIRE_THROWS_AS(compare_channel(rec.head(8), fs, 0.0, acc, 500.0, o), InputError);
  Vector bad = rec;
  bad[3] = NAN;
  REQUIRE_THROWS_WITH(compare_channel(bad, fs, 0.0, acc, 500.0, o), Catch::Contains("non-finite"));
}

TEST_CASE("a unit's factor between record and model with the same shape is named, a model's error is not") {
  // g read as m/s²: the model 9.81 times the record.
  const std::string g = unit_slip_warning(9.76, 9.71, 0.9999, "deck_acc_mps2");
  REQUIRE_THAT(g, Catch::Contains("channel deck_acc_mps2: the record reads 9.76 times smaller"));
  REQUIRE_THAT(g, Catch::Contains("the factor between g and m/s²"));
  // mm read as m: the record 1000 times the model; µε read as ε.
  REQUIRE_THAT(unit_slip_warning(1e-3, 1.02e-3, 0.99, "d_m"), Catch::Contains("reads 1000 times larger"));
  REQUIRE_THAT(unit_slip_warning(1e-3, 1.02e-3, 0.99, "d_m"), Catch::Contains("between mm and m"));
  REQUIRE_THAT(unit_slip_warning(0.9e6, 1.1e6, 0.95, "s_ue"), Catch::Contains("between µε and ε"));
  // The band is 20 % on both ratios (log distance): 1.19 x the factor in, 1.21 x out.
  REQUIRE_FALSE(unit_slip_warning(1.19 * 9.80665, 9.80665, 0.9, "a").empty());
  REQUIRE(unit_slip_warning(1.21 * 9.80665, 9.80665, 0.9, "a").empty());
  REQUIRE(unit_slip_warning(9.80665, 9.80665 / 1.21, 0.9, "a").empty());
  // Another shape is a model's error, not a unit's: no word below a correlation of 0.8.
  REQUIRE(unit_slip_warning(9.80665, 9.80665, 0.79, "a").empty());
  // A model within a factor of two, and undefined ratios, say nothing.
  REQUIRE(unit_slip_warning(1.6, 1.5, 0.99, "a").empty());
  REQUIRE(unit_slip_warning(std::nan(""), 9.8, 0.99, "a").empty());
  REQUIRE(unit_slip_warning(0.0, 9.8, 0.99, "a").empty());
  // A wider band (fit: the initial values are tens of percent off) takes 1.45 x the factor.
  REQUIRE(unit_slip_warning(1.45 * 9.80665, 1.3 * 9.80665, 0.9, "a").empty());
  REQUIRE_FALSE(unit_slip_warning(1.45 * 9.80665, 1.3 * 9.80665, 0.9, "a", 1.5).empty());
  REQUIRE(unit_slip_warning(1.55 * 9.80665, 9.80665, 0.9, "a", 1.5).empty());
}
