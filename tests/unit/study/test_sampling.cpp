// Sampling designs and statistics of sampled studies: the normal quantile, Sobol points against
// SciPy's, Latin hypercube strata, the factor distributions against their closed forms, the
// Gaussian copula, Saltelli's layout; percentiles and exceedance of a linear model against its
// closed form; Sobol indices of the Ishigami function against its known values.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/study/sampling.hpp"
#include "viaduct/study/statistics.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using study::Distribution;
using study::DistributionKind;
using study::SamplingMethod;

namespace sampling_test {
const std::string src = VIADUCT_SOURCE_DIR;
constexpr double kPi = 3.14159265358979323846;

Distribution uniform(double lo, double hi) { return Distribution{DistributionKind::uniform, lo, hi}; }
Distribution normal_like(DistributionKind k, double mean, double sd, double lo = 0.0, double hi = 0.0) {
  return Distribution{k, lo, hi, mean, sd};
}
// The mean and variance of a distribution by the midpoint rule in u (n points).
std::pair<double, double> moments(const Distribution& d, int n) {
  double m = 0.0, m2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = d.quantile((i + 0.5) / n);
    m += x;
    m2 += x * x;
  }
  m /= n;
  return {m, m2 / n - m * m};
}
double ishigami(double x1, double x2, double x3) {
  return std::sin(x1) + 7.0 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
}

TEST_CASE("normal quantile: Φ(Φ⁻¹(p)) = p to rounding from 1e-300 to 1 − 1e-16, and known values") {
  // The double nearest the exact quantile x moves Φ by a relative ~x²·1.1e-16 (dΦ/Φ ≈ |x| dx in
  // the tail): 1e-14·max(1, x²) allows 100 times that.
  for (double e = -300.0; e <= -0.302; e += 0.25) {
    const double p = std::pow(10.0, e), x = study::normal_quantile(p);
    INFO("p = " << p);
    CHECK(std::abs(study::normal_cdf(x) - p) <= 1e-14 * std::max(1.0, x * x) * p);
    const double q = 1.0 - (1.0 - p);  // the upper tail's probability as 1 − p rounds it
    if (q == 0.0) continue;
    const double xu = study::normal_quantile(1.0 - p);
    CHECK(std::abs(study::normal_sf(xu) - q) <= 1e-14 * std::max(1.0, xu * xu) * q);
  }
  // Values from the closed form's tables (Abramowitz & Stegun 26.2, to 16 digits with mpmath).
  CHECK(study::normal_quantile(0.975) == Approx(1.959963984540054).epsilon(1e-15));
  CHECK(study::normal_quantile(1e-10) == Approx(-6.361340902404056).epsilon(1e-14));
  CHECK(study::normal_quantile(0.5) == 0.0);
  CHECK(std::isinf(study::normal_quantile(0.0)));
  CHECK(std::isnan(study::normal_quantile(1.5)));
}

TEST_CASE("Sobol sequence: the first 256 points in 32 dimensions are SciPy's bit for bit") {
  std::ifstream in(src + "/tests/data/sobol_reference.csv");
  REQUIRE(in);
  const study::SobolSequence seq(32);
  std::string line;
  std::uint64_t i = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    for (int j = 0; std::getline(ss, cell, ','); ++j) {
      INFO("point " << i << ", dimension " << j);
      REQUIRE(seq.bits(i, j) == std::uint32_t(std::stoull(cell)));
    }
    ++i;
  }
  CHECK(i == 256);
  CHECK_THROWS_AS(study::SobolSequence(33), InputError);
}

TEST_CASE("designs: Sobol's shifted points and a Latin hypercube hold one point per stratum") {
  const int n = 1024, d = 32;
  for (auto method : {SamplingMethod::sobol, SamplingMethod::lhs}) {
    const Matrix u = study::unit_design(method, n, d, 7);
    for (int j = 0; j < d; ++j) {
      std::set<long> cells;
      for (int i = 0; i < n; ++i) {
        REQUIRE(u(i, j) > 0.0);
        REQUIRE(u(i, j) < 1.0);
        cells.insert(long(std::floor(u(i, j) * n)));
      }
      CHECK(cells.size() == std::size_t(n));
    }
    // Deterministic in the seed, different across seeds.
    CHECK(study::unit_design(method, n, d, 7) == u);
    CHECK(study::unit_design(method, n, d, 8) != u);
  }
  // Sobol's 2-D projections are nets: 1024 points, one in each of 32 × 32 cells for dims 0 and 1.
  const Matrix s = study::unit_design(SamplingMethod::sobol, n, 2, 3);
  std::set<long> cells;
  for (int i = 0; i < n; ++i) cells.insert(long(std::floor(s(i, 0) * 32)) * 32 + long(std::floor(s(i, 1) * 32)));
  CHECK(cells.size() == 1024);
}

TEST_CASE("factor distributions: moments and bounds against their closed forms") {
  // Midpoint rule over 2e5 points: moments to ~1e-6 of their values (tails included at u = 2.5e-6).
  const auto [mu, var] = moments(uniform(0.5, 2.0), 1000);
  CHECK(mu == Approx(1.25).epsilon(1e-12));
  CHECK(var == Approx(1.5 * 1.5 / 12).epsilon(1e-5));
  const auto [ln_m, ln_v] = moments(normal_like(DistributionKind::lognormal, 1.2, 0.3), 200000);
  CHECK(ln_m == Approx(1.2).epsilon(1e-5));
  CHECK(std::sqrt(ln_v) == Approx(0.3).epsilon(2e-3));  // the midpoint rule misses the far tail's share
  const auto [n_m, n_v] = moments(normal_like(DistributionKind::normal, 1.0, 0.1), 200000);
  CHECK(n_m == Approx(1.0).epsilon(1e-9));
  CHECK(std::sqrt(n_v) == Approx(0.1).epsilon(2e-3));
  // Truncated normal: mean = μ + σ (φ(a) − φ(b)) / (Φ(b) − Φ(a)).
  const Distribution t = normal_like(DistributionKind::truncated, 1.0, 0.5, 0.5, 2.5);
  const double a = -1.0, b = 3.0, phi_a = std::exp(-0.5) / std::sqrt(2 * kPi), phi_b = std::exp(-4.5) / std::sqrt(2 * kPi);
  CHECK(moments(t, 200000).first ==
        Approx(1.0 + 0.5 * (phi_a - phi_b) / (study::normal_cdf(b) - study::normal_cdf(a))).epsilon(1e-6));
  // Far in the upper tail (8 to 9 sd) the quantile stays inside and finite.
  const Distribution far = normal_like(DistributionKind::truncated, 1.0, 0.1, 1.8, 1.9);
  for (double u : {1e-12, 0.5, 1.0 - 1e-12}) {
    CHECK(far.quantile(u) >= 1.8);
    CHECK(far.quantile(u) <= 1.9);
  }
  CHECK(far.quantile(0.5) < 1.82);  // most of the mass sits at the lower bound
}

TEST_CASE("factor distributions: bad parameters are refused with the violated constraint") {
  std::string why;
  CHECK_FALSE(uniform(2.0, 1.0).is_valid(&why));
  CHECK(why.find("low < high") != std::string::npos);
  CHECK_FALSE(uniform(-0.1, 1.0).is_valid(&why));
  CHECK(why.find("low >= 0") != std::string::npos);
  CHECK_FALSE(normal_like(DistributionKind::normal, 1.0, -0.1).is_valid(&why));
  CHECK(why.find("sd > 0") != std::string::npos);
  CHECK_FALSE(normal_like(DistributionKind::normal, 1.0, 0.3).is_valid(&why));
  CHECK(why.find("truncated") != std::string::npos);
  CHECK_FALSE(normal_like(DistributionKind::lognormal, 0.0, 0.3).is_valid(&why));
  CHECK(why.find("mean > 0") != std::string::npos);
  CHECK_FALSE(normal_like(DistributionKind::truncated, 1.0, 0.01, 2.0, 3.0).is_valid(&why));  // 100 sd away
  CHECK(why.find("probability") != std::string::npos);
  CHECK(normal_like(DistributionKind::normal, 1.0, 0.15).is_valid(&why));
  CHECK(normal_like(DistributionKind::truncated, 1.0, 0.5, 0.0, 3.0).is_valid(&why));
}

TEST_CASE("Gaussian copula: the normals behind the uniforms get the correlation asked for") {
  Matrix r(2, 2);
  r << 1.0, 0.6, 0.6, 1.0;
  const Matrix u = study::correlate(study::unit_design(SamplingMethod::sobol, 4096, 2, 1), r);
  const Vector z0 = u.col(0).unaryExpr([](double p) { return study::normal_quantile(p); });
  const Vector z1 = u.col(1).unaryExpr([](double p) { return study::normal_quantile(p); });
  const double c = (z0.array() - z0.mean()).matrix().dot((z1.array() - z1.mean()).matrix()) /
                   std::sqrt((z0.array() - z0.mean()).square().sum() * (z1.array() - z1.mean()).square().sum());
  CHECK(c == Approx(0.6).margin(0.01));  // 4096 quasi-random points: sampling error ~1e-3
  r(0, 1) = r(1, 0) = 1.2;
  CHECK_THROWS_AS(study::correlate(u, r), InputError);
  Matrix r3 = Matrix::Identity(3, 3);
  r3(0, 1) = r3(1, 0) = 0.9;
  r3(0, 2) = r3(2, 0) = 0.9;
  r3(1, 2) = r3(2, 1) = -0.9;  // each pair possible, the three together not
  CHECK_THROWS_WITH(study::correlate(study::unit_design(SamplingMethod::lhs, 8, 3, 1), r3),
                    Catch::Contains("positive definite"));
}

TEST_CASE("Saltelli's design: A, B and A with one column from B, interleaved per base point") {
  study::SampleSpec spec;
  spec.distributions = {uniform(0.5, 1.5), normal_like(DistributionKind::lognormal, 1.0, 0.2), uniform(0.0, 2.0)};
  spec.method = SamplingMethod::sobol;
  spec.n = 16;
  spec.sensitivity = true;
  const study::SampleDesign design = study::sample_design(spec);
  REQUIRE(design.factors.rows() == 16 * 5);
  for (Index j = 0; j < 16; ++j) {
    const Index base = j * 5;
    CHECK(design.block(base) == 0);
    CHECK(design.independent(base + 1));
    CHECK_FALSE(design.independent(base + 2));
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        CHECK(design.factors(base + 2 + i, k) == design.factors(base + (k == i ? 1 : 0), k));
  }
  spec.correlation = Matrix::Identity(3, 3);
  CHECK_THROWS_WITH(study::sample_design(spec), Catch::Contains("independent inputs"));
}

TEST_CASE("percentiles and exceedance of a sampled linear model against the closed form") {
  // Y = 2 X1 + 3 X2, X normal factors (1, 0.1): Y ~ N(5, 0.1 √13). 4096 LHS samples.
  study::SampleSpec spec;
  spec.distributions = {normal_like(DistributionKind::normal, 1.0, 0.1), normal_like(DistributionKind::normal, 1.0, 0.1)};
  spec.n = 4096;
  spec.seed = 5;
  const Matrix x = study::sample_design(spec).factors;
  std::vector<double> y(static_cast<std::size_t>(x.rows()));
  for (Index i = 0; i < x.rows(); ++i) y[std::size_t(i)] = 2 * x(i, 0) + 3 * x(i, 1);
  const double sd = 0.1 * std::sqrt(13.0);
  std::vector<double> sorted = y;
  std::sort(sorted.begin(), sorted.end());
  // The standard error of a percentile of n = 4096 samples, sd·√(p(1−p)/n)/φ(z), is 0.033 sd at
  // 5 % and 95 %: three of them allowed.
  for (double p : {5.0, 50.0, 95.0})
    CHECK(study::percentile_of_sorted(sorted, p) == Approx(5.0 + sd * study::normal_quantile(p / 100)).margin(0.1 * sd));
  const study::Exceedance e = study::exceedance(y, 5.5);
  const double exact = study::normal_sf(0.5 / sd);
  CHECK(std::abs(e.p - exact) <= 3 * e.se);
  CHECK(e.upper95 > e.p);
  CHECK(e.n == 4096);
  // numpy's "linear" percentiles; the Wilson bound of 0 in 1000 is 3.8e-3.
  CHECK(study::percentile_of_sorted({1, 2, 3, 4}, 50) == 2.5);
  CHECK(study::percentile_of_sorted({1, 2, 3, 4}, 90) == Approx(3.7));
  CHECK(study::exceedance(std::vector<double>(1000, 1.0), 2.0).upper95 == Approx(3.83e-3).epsilon(2e-3));
}

TEST_CASE("Sobol indices: Ishigami's known indices within their bootstrap intervals") {
  // x_i uniform on (−π, π): factors uniform on (0, 2π) less π. Known (a = 7, b = 0.1):
  // V = a²/8 + bπ⁴/5 + b²π⁸/18 + 1/2, V1 = (1 + bπ⁴/5)²/2, V2 = a²/8, V13 = b²π⁸·8/225.
  const double b = 0.1, pi4 = std::pow(kPi, 4), pi8 = pi4 * pi4;
  const double V = 49.0 / 8 + b * pi4 / 5 + b * b * pi8 / 18 + 0.5, V1 = 0.5 * std::pow(1 + b * pi4 / 5, 2), V2 = 49.0 / 8,
               V13 = b * b * pi8 * 8.0 / 225.0;
  const double s_exact[] = {V1 / V, V2 / V, 0.0}, st_exact[] = {(V1 + V13) / V, V2 / V, V13 / V};
  study::SampleSpec spec;
  spec.distributions = {uniform(0, 2 * kPi), uniform(0, 2 * kPi), uniform(0, 2 * kPi)};
  spec.method = SamplingMethod::sobol;
  spec.n = 8192;
  spec.sensitivity = true;
  const study::SampleDesign design = study::sample_design(spec);
  Vector fa(spec.n), fb(spec.n);
  Matrix fab(spec.n, 3);
  for (Index r = 0; r < design.factors.rows(); ++r) {
    const double f = ishigami(design.factors(r, 0) - kPi, design.factors(r, 1) - kPi, design.factors(r, 2) - kPi);
    const Index j = r / 5;
    const int blk = design.block(r);
    if (blk == 0) fa(j) = f;
    else if (blk == 1) fb(j) = f;
    else fab(j, blk - 2) = f;
  }
  study::SobolOptions o;
  o.n_bootstrap = 300;
  const auto idx = study::sobol_indices(fa, fb, fab, o);
  REQUIRE(idx.size() == 3);
  for (int i = 0; i < 3; ++i) {
    INFO("x" << i + 1 << ": S = " << idx[i].s << " [" << idx[i].s_lo << ", " << idx[i].s_hi << "], ST = " << idx[i].st << " ["
              << idx[i].st_lo << ", " << idx[i].st_hi << "]");
    CHECK(s_exact[i] >= idx[i].s_lo);
    CHECK(s_exact[i] <= idx[i].s_hi);
    CHECK(st_exact[i] >= idx[i].st_lo);
    CHECK(st_exact[i] <= idx[i].st_hi);
    // Intervals narrow enough to mean something at n = 8192 (their width ~4 standard errors).
    CHECK(idx[i].s_hi - idx[i].s_lo < 0.08);
    CHECK(idx[i].st_hi - idx[i].st_lo < 0.08);
  }
  // A response whose mean is far above its spread (a resonance peak over uncertain pads): the
  // centred estimator keeps Y = 1000 + X1 + 2 X2 (S = ST = 0.2, 0.8) within 0.05 from 256 points;
  // without the centring its first-order indices came out at tens.
  study::SampleSpec lin;
  lin.distributions = {uniform(0, 1), uniform(0, 1)};
  lin.method = SamplingMethod::sobol;
  lin.n = 256;
  lin.sensitivity = true;
  const study::SampleDesign ld = study::sample_design(lin);
  Vector la(256), lb(256);
  Matrix lab(256, 2);
  for (Index r = 0; r < ld.factors.rows(); ++r) {
    const double f = 1000.0 + ld.factors(r, 0) + 2.0 * ld.factors(r, 1);
    const int blk = ld.block(r);
    (blk == 0 ? la(r / 4) : blk == 1 ? lb(r / 4) : lab(r / 4, blk - 2)) = f;
  }
  const auto li = study::sobol_indices(la, lb, lab, o);
  CHECK(li[0].s == Approx(0.2).margin(0.05));
  CHECK(li[1].s == Approx(0.8).margin(0.05));
  CHECK(li[0].st == Approx(0.2).margin(0.05));
  CHECK(li[1].st == Approx(0.8).margin(0.05));
  // A response that does not vary has no indices.
  const auto flat = study::sobol_indices(Vector::Ones(8), Vector::Ones(8), Matrix::Ones(8, 2), o);
  CHECK(std::isnan(flat[0].s));
}

}  // namespace sampling_test
