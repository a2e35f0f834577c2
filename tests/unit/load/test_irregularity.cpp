// Rail irregularities (issue #21 part 3): the spectra's shapes and closed-form variances, and
// random profiles that carry them, reproducible from a seed.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <complex>

#include "viaduct/core/error.hpp"
#include "viaduct/load/irregularity.hpp"

using namespace viaduct;
using namespace viaduct::load;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr IrregularitySpectrum all[] = {IrregularitySpectrum::fra1, IrregularitySpectrum::fra2, IrregularitySpectrum::fra3,
                                        IrregularitySpectrum::fra4, IrregularitySpectrum::fra5, IrregularitySpectrum::fra6,
                                        IrregularitySpectrum::german_low, IrregularitySpectrum::german_high};

// Simpson's rule on a logarithmic grid (the spectra fall as Ω⁻⁴): an independent check of the
// closed-form variance.
double simpson_variance(IrregularitySpectrum s, double lambda_min, double lambda_max) {
  const double a = std::log(2 * kPi / lambda_max), b = std::log(2 * kPi / lambda_min);
  const int n = 20000;
  const double h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double u = a + i * h, w = std::exp(u);
    sum += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * irregularity_psd(s, w) * w;  // dΩ = Ω du
  }
  return sum * h / 3;
}
}  // namespace

TEST_CASE("irregularity spectra: names, order of the classes, asymptotes and closed-form variance") {
  for (auto s : all) CHECK(irregularity_spectrum(spectrum_name(s)) == s);
  CHECK_THROWS_WITH(irregularity_spectrum("fra7"), Catch::Contains("known: fra1 ... fra6"));
  // FRA class 1 is the worst track, 6 the best; German high disturbance above low.
  for (int c = 0; c < 5; ++c)
    CHECK(irregularity_psd(all[c], 0.5) > irregularity_psd(all[c + 1], 0.5));
  CHECK(irregularity_psd(IrregularitySpectrum::german_high, 0.5) / irregularity_psd(IrregularitySpectrum::german_low, 0.5) ==
        Approx(1.080e-6 / 4.032e-7));
  // Short waves: both fall as Ω⁻⁴; long waves: FRA rises as Ω⁻², the German flattens below Ω_r.
  for (auto s : {IrregularitySpectrum::fra6, IrregularitySpectrum::german_low})
    CHECK(irregularity_psd(s, 200.0) / irregularity_psd(s, 400.0) == Approx(16.0).epsilon(1e-4));
  CHECK(irregularity_psd(IrregularitySpectrum::fra4, 1e-3) / irregularity_psd(IrregularitySpectrum::fra4, 2e-3) == Approx(4.0).epsilon(1e-4));
  CHECK(irregularity_psd(IrregularitySpectrum::german_low, 1e-4) / irregularity_psd(IrregularitySpectrum::german_low, 2e-4) ==
        Approx(1.0).epsilon(1e-3));
  // The variance in a band: closed form against Simpson's rule.
  for (auto s : all)
    for (auto [lo, hi] : {std::pair{1.0, 80.0}, std::pair{2.0, 25.0}, std::pair{0.5, 150.0}})
      CHECK(irregularity_variance(s, lo, hi) == Approx(simpson_variance(s, lo, hi)).epsilon(1e-8));
  CHECK_THROWS_AS(irregularity_psd(IrregularitySpectrum::fra6, 0.0), InputError);
  CHECK_THROWS_AS(irregularity_variance(IrregularitySpectrum::fra6, 5.0, 1.0), InputError);
}

TEST_CASE("a random profile carries its spectrum: every harmonic's amplitude, the band, the variance") {
  ProfileSpec spec;
  spec.spectrum = IrregularitySpectrum::fra5;
  spec.lambda_min = 1.0;
  spec.lambda_max = 50.0;
  spec.dx = 0.125;
  spec.length = 4095 * 0.125;  // 4096 samples: exactly one period of the harmonics
  spec.seed = 7;
  const RailProfile p = random_profile(spec);
  REQUIRE(p.z.size() == 4096);
  const Index n = p.z.size();
  const double dw = 2 * kPi / (static_cast<double>(n) * spec.dx);
  // The DFT at harmonic k is n/2 · a_k · e^{iφ}: a_k = √(2·∫S over its cell), within O(ΔΩ²) of
  // √(2 S ΔΩ) inside the band (0.5 % here), 0 outside.
  const double band_lo = 2 * kPi / spec.lambda_max, band_hi = 2 * kPi / spec.lambda_min;
  const double rms = std::sqrt(p.z.squaredNorm() / static_cast<double>(n));
  int n_in = 0;
  for (Index k = 1; k <= n / 2; ++k) {
    std::complex<double> zk = 0;
    for (Index j = 0; j < n; ++j) zk += p.z[j] * std::polar(1.0, -2 * kPi * static_cast<double>(k * j % n) / static_cast<double>(n));
    const double w = static_cast<double>(k) * dw, amp = std::abs(zk) * 2 / static_cast<double>(n);
    INFO("harmonic " << k << " at " << w << " rad/m");
    if (w + 0.5 * dw <= band_lo || w - 0.5 * dw >= band_hi) {
      CHECK(amp == Approx(0.0).margin(1e-10 * rms));  // rounding of n sums
    } else if (w - 0.5 * dw >= band_lo && w + 0.5 * dw <= band_hi) {
      ++n_in;
      CHECK(amp == Approx(std::sqrt(2 * irregularity_psd(spec.spectrum, w) * dw)).epsilon(0.005));
    }
  }
  CHECK(n_in > 300);
  // Over the period the variance is the band's closed form, exactly (the cells tile the band).
  const double var = p.z.squaredNorm() / static_cast<double>(n);
  CHECK(var == Approx(irregularity_variance(spec.spectrum, spec.lambda_min, spec.lambda_max)).epsilon(1e-10));
}

TEST_CASE("a random profile: the seed reproduces it, the band shares harmonics, between samples it is smooth") {
  ProfileSpec spec;
  spec.length = 300.0;
  spec.seed = 42;
  const RailProfile a = random_profile(spec), b = random_profile(spec);
  CHECK(a.z == b.z);
  ProfileSpec other = spec;
  other.seed = 43;
  CHECK((random_profile(other).z - a.z).norm() > 0.5 * a.z.norm());
  // Two bands from one seed: their difference is the harmonics of 1-2 m only.
  ProfileSpec narrow = spec;
  narrow.lambda_min = 2.0;
  const RailProfile c = random_profile(narrow);
  const double var_diff = (a.z - c.z).squaredNorm() / static_cast<double>(a.z.size());
  CHECK(var_diff == Approx(irregularity_variance(spec.spectrum, 1.0, 2.0)).epsilon(0.05));  // 300 m is not a whole period
  // RMS for the report: FRA class 6, 1-80 m.
  const double rms = std::sqrt(a.z.squaredNorm() / static_cast<double>(a.z.size()));
  CHECK(rms == Approx(std::sqrt(irregularity_variance(spec.spectrum, 1.0, 80.0))).epsilon(0.25));  // 300 m holds few 80 m waves
  // Samples are returned at the samples; between them the cubic follows the harmonic sum. The
  // same period at half the step (same harmonics, same phases) gives the midpoints exactly: 1 m
  // waves sampled every 0.05 m are interpolated to well under 1 % of the RMS.
  CHECK(a.at(a.x0 + 100 * a.dx) == a.z[100]);
  ProfileSpec coarse = spec, fine = spec;
  coarse.length = 8191 * 0.05;  // 8192 samples, period 409.6 m
  fine.dx = 0.025;
  fine.length = 16383 * 0.025;  // 16384 samples, the same period
  const RailProfile pc = random_profile(coarse), pf = random_profile(fine);
  double worst = 0;
  for (Index j = 0; j + 1 < pc.z.size(); ++j) {
    CHECK(pf.z[2 * j] == Approx(pc.z[j]).margin(1e-15));
    worst = std::max(worst, std::abs(pc.at(pc.x0 + (static_cast<double>(j) + 0.5) * pc.dx) - pf.z[2 * j + 1]));
  }
  CHECK(worst < 0.01 * rms);
  CHECK_THROWS_WITH(a.at(a.end() + 1.0), Catch::Contains("outside the profile"));
  ProfileSpec bad = spec;
  bad.lambda_min = 0.1;
  CHECK_THROWS_WITH(random_profile(bad), Catch::Contains("lambda_min >= 4 dx"));
  bad = spec;
  bad.lambda_max = 400.0;
  CHECK_THROWS_WITH(random_profile(bad), Catch::Contains("lambda_max <= length"));
}
