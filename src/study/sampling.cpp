#include "viaduct/study/sampling.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "viaduct/core/error.hpp"

namespace viaduct::study {

namespace sampling_detail {

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kSqrt2Pi = 2.50662827463100050242;

// Acklam's approximation of Φ⁻¹ (relative error 1.15e-9), refined below.
double acklam(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  constexpr double p_low = 0.02425;
  if (p < p_low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - p_low) return -acklam(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

// Joe and Kuo's new-joe-kuo-6.21201, dimensions 2 to 32: degree s, coefficients a, m_1 .. m_s.
struct DirectionRow {
  int s;
  unsigned a;
  unsigned m[7];
};
const DirectionRow kJoeKuo[] = {
    {1, 0, {1}},          {2, 1, {1, 3}},       {3, 1, {1, 3, 1}},       {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}}, {4, 4, {1, 3, 5, 13}}, {5, 2, {1, 1, 5, 5, 17}}, {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}}, {5, 11, {1, 1, 5, 1, 1}}, {5, 13, {1, 1, 1, 3, 11}}, {5, 14, {1, 3, 5, 5, 31}},
    {6, 1, {1, 3, 3, 9, 7, 49}}, {6, 13, {1, 1, 1, 15, 21, 21}}, {6, 16, {1, 3, 1, 13, 27, 49}},
    {6, 19, {1, 1, 1, 15, 7, 5}}, {6, 22, {1, 3, 1, 15, 13, 25}}, {6, 25, {1, 1, 5, 5, 19, 61}},
    {7, 1, {1, 3, 7, 11, 23, 15, 103}}, {7, 4, {1, 3, 7, 13, 13, 15, 69}}, {7, 7, {1, 1, 3, 13, 7, 35, 63}},
    {7, 8, {1, 3, 5, 9, 1, 25, 53}}, {7, 14, {1, 3, 1, 13, 9, 35, 107}}, {7, 19, {1, 3, 1, 5, 27, 61, 31}},
    {7, 21, {1, 1, 5, 11, 19, 41, 61}}, {7, 28, {1, 3, 5, 3, 3, 13, 69}}, {7, 31, {1, 1, 7, 13, 1, 19, 1}},
    {7, 32, {1, 3, 7, 5, 13, 19, 59}}, {7, 37, {1, 1, 3, 9, 25, 29, 41}}, {7, 41, {1, 3, 5, 13, 23, 1, 55}},
    {7, 42, {1, 3, 7, 3, 13, 59, 17}},
};

// A uniform in (0, 1) from 53 bits of the engine: (k + 1/2) / 2^53.
double unit(std::mt19937_64& g) { return (double(g() >> 11) + 0.5) * 0x1.0p-53; }

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

}  // namespace sampling_detail

double normal_cdf(double x) { return 0.5 * std::erfc(-x / sampling_detail::kSqrt2); }
double normal_sf(double x) { return 0.5 * std::erfc(x / sampling_detail::kSqrt2); }

double normal_quantile(double p) {
  if (std::isnan(p) || p < 0.0 || p > 1.0) return std::numeric_limits<double>::quiet_NaN();
  if (p == 0.0) return -std::numeric_limits<double>::infinity();
  if (p == 1.0) return std::numeric_limits<double>::infinity();
  // Halley's step on the tail the root lies in, so that the residual keeps its digits.
  double x = sampling_detail::acklam(p);
  const double e = p < 0.5 ? normal_cdf(x) - p : (1.0 - p) - normal_sf(x);
  const double u = e * sampling_detail::kSqrt2Pi * std::exp(0.5 * x * x);
  if (std::isfinite(u)) x -= u / (1.0 + 0.5 * x * u);
  return x;
}

bool distribution_kind_of(const std::string& name, DistributionKind* kind) {
  if (name == "uniform") *kind = DistributionKind::uniform;
  else if (name == "normal") *kind = DistributionKind::normal;
  else if (name == "lognormal") *kind = DistributionKind::lognormal;
  else if (name == "truncated") *kind = DistributionKind::truncated;
  else return false;
  return true;
}

bool sampling_method_of(const std::string& name, SamplingMethod* method) {
  if (name == "random") *method = SamplingMethod::random;
  else if (name == "lhs") *method = SamplingMethod::lhs;
  else if (name == "sobol") *method = SamplingMethod::sobol;
  else return false;
  return true;
}

double Distribution::quantile(double u) const {
  switch (kind) {
    case DistributionKind::uniform: return low + u * (high - low);
    case DistributionKind::normal: return mean + sd * normal_quantile(u);
    case DistributionKind::lognormal: {
      const double s2 = std::log1p((sd / mean) * (sd / mean));
      return std::exp(std::log(mean) - 0.5 * s2 + std::sqrt(s2) * normal_quantile(u));
    }
    case DistributionKind::truncated: {
      // In the upper tail through Q = 1 − Φ, so that a truncation far right keeps its digits.
      const double a = (low - mean) / sd, b = (high - mean) / sd;
      double x;
      if (a > 0.0) {
        const double qa = normal_sf(a), qb = normal_sf(b);
        x = -normal_quantile(qa - u * (qa - qb));
      } else {
        const double pa = normal_cdf(a), pb = normal_cdf(b);
        x = normal_quantile(pa + u * (pb - pa));
      }
      return std::min(high, std::max(low, mean + sd * x));
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::pair<double, double> Distribution::support() const {
  if (kind == DistributionKind::uniform || kind == DistributionKind::truncated) return {low, high};
  return {quantile(1e-9), quantile(1.0 - 1e-9)};
}

bool Distribution::is_valid(std::string* why) const {
  using sampling_detail::num;
  auto fail = [&](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  for (double x : {low, high, mean, sd})
    if (!std::isfinite(x)) return fail("parameters must be finite numbers");
  const bool bounded = kind == DistributionKind::uniform || kind == DistributionKind::truncated;
  if (bounded) {
    if (low < 0.0) return fail("low = " + num(low) + ": violated constraint low >= 0 (factors multiply the key's value)");
    if (!(low < high)) return fail("low = " + num(low) + ", high = " + num(high) + ": violated constraint low < high");
  }
  if (kind == DistributionKind::uniform) return true;
  if (!(sd > 0.0)) return fail("sd = " + num(sd) + ": violated constraint sd > 0");
  if (kind == DistributionKind::lognormal && !(mean > 0.0))
    return fail("mean = " + num(mean) + ": violated constraint mean > 0 (a lognormal factor is positive)");
  if (kind == DistributionKind::normal && normal_cdf(-mean / sd) > 1e-9)
    return fail("a normal factor of mean " + num(mean) + " and sd " + num(sd) + " falls below 0 with probability " +
                num(normal_cdf(-mean / sd)) +
                " (violated constraint mean >= 6 sd): use distribution = \"truncated\" with low >= 0, or \"lognormal\"");
  if (kind == DistributionKind::truncated) {
    const double a = (low - mean) / sd, b = (high - mean) / sd;
    const double mass = a > 0.0 ? normal_sf(a) - normal_sf(b) : normal_cdf(b) - normal_cdf(a);
    if (!(mass > 1e-12))
      return fail("[low, high] = [" + num(low) + ", " + num(high) + "] holds " + num(mass) +
                  " of the normal's probability (violated constraint > 1e-12)");
  }
  return true;
}

SobolSequence::SobolSequence(int d) : d_(d), v_(std::size_t(32) * std::size_t(d > 0 ? d : 0)) {
  if (d < 1 || d > max_dimensions())
    throw InputError("Sobol sequence: " + std::to_string(d) + " dimensions, violated constraint 1 <= d <= " +
                     std::to_string(max_dimensions()));
  for (int k = 0; k < 32; ++k) v_[std::size_t(k)] = std::uint32_t(1) << (31 - k);  // van der Corput
  for (int j = 1; j < d; ++j) {
    const auto& row = sampling_detail::kJoeKuo[j - 1];
    std::uint32_t* v = &v_[std::size_t(32) * std::size_t(j)];
    const int s = row.s;
    for (int k = 0; k < s && k < 32; ++k) v[k] = std::uint32_t(row.m[k]) << (31 - k);
    for (int k = s; k < 32; ++k) {
      std::uint32_t x = v[k - s] ^ (v[k - s] >> s);
      for (int i = 1; i < s; ++i)
        if ((row.a >> (s - 1 - i)) & 1u) x ^= v[k - i];
      v[k] = x;
    }
  }
}

std::uint32_t SobolSequence::bits(std::uint64_t i, int j) const {
  const std::uint64_t gray = i ^ (i >> 1);
  const std::uint32_t* v = &v_[std::size_t(32) * std::size_t(j)];
  std::uint32_t x = 0;
  for (int k = 0; k < 32 && (gray >> k) != 0; ++k)
    if ((gray >> k) & 1u) x ^= v[k];
  return x;
}

Matrix unit_design(SamplingMethod method, Index n, int d, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  Matrix u(n, d);
  switch (method) {
    case SamplingMethod::random:
      for (Index i = 0; i < n; ++i)
        for (int j = 0; j < d; ++j) u(i, j) = sampling_detail::unit(g);
      break;
    case SamplingMethod::lhs: {
      std::vector<Index> perm(static_cast<std::size_t>(n));
      for (int j = 0; j < d; ++j) {
        for (Index i = 0; i < n; ++i) perm[std::size_t(i)] = i;
        for (Index i = n - 1; i > 0; --i) std::swap(perm[std::size_t(i)], perm[std::size_t(g() % std::uint64_t(i + 1))]);
        for (Index i = 0; i < n; ++i) u(i, j) = (double(perm[std::size_t(i)]) + sampling_detail::unit(g)) / double(n);
      }
      break;
    }
    case SamplingMethod::sobol: {
      const SobolSequence seq(d);
      std::vector<std::uint32_t> shift(static_cast<std::size_t>(d));
      for (auto& s : shift) s = std::uint32_t(g() >> 32);
      for (Index i = 0; i < n; ++i)
        for (int j = 0; j < d; ++j)
          u(i, j) = (double(seq.bits(std::uint64_t(i), j) ^ shift[std::size_t(j)]) + 0.5) * 0x1.0p-32;
      break;
    }
  }
  return u;
}

Matrix correlate(const Matrix& u, const Matrix& r) {
  const Index d = u.cols();
  auto bad = [](const std::string& s) { throw InputError(SourceLocation{"", 0, "sweep.correlations"}, s); };
  if (r.rows() != d || r.cols() != d) bad("the correlation matrix must be " + std::to_string(d) + " x " + std::to_string(d));
  for (Index i = 0; i < d; ++i)
    for (Index j = 0; j < d; ++j) {
      if (i == j && r(i, j) != 1.0) bad("the correlation of a key with itself must be 1");
      if (!(std::abs(r(i, j)) <= 1.0)) bad("correlations must lie in [-1, 1]");
      if (r(i, j) != r(j, i)) bad("the correlation matrix must be symmetric");
    }
  const Eigen::LLT<Matrix> llt(r);
  if (llt.info() != Eigen::Success) bad("the correlations are not consistent (the matrix is not positive definite)");
  Matrix z = u.unaryExpr([](double p) { return normal_quantile(p); });
  z = z * llt.matrixL().transpose();
  return z.unaryExpr([](double x) { return normal_cdf(x); });
}

SampleDesign sample_design(const SampleSpec& spec) {
  const int d = int(spec.distributions.size());
  if (d < 1) throw InputError("a sampled study needs at least one varied key");
  if (spec.n < 2) throw InputError("a sampled study needs n >= 2 samples, got " + std::to_string(spec.n));
  if (spec.sensitivity && spec.correlation.size() > 0)
    throw InputError(SourceLocation{"", 0, "sweep.correlations"},
                     "Sobol indices assume independent inputs: correlated keys cannot have sweep.sensitivity = true");
  SampleDesign out;
  out.d = d;
  out.n_base = spec.n;
  out.saltelli = spec.sensitivity;
  const int width = spec.sensitivity ? 2 * d : d;
  if (spec.method == SamplingMethod::sobol && width > SobolSequence::max_dimensions())
    throw InputError(SourceLocation{"", 0, "sweep.sampling"}, "a Sobol sequence has at most " +
                     std::to_string(SobolSequence::max_dimensions()) + " dimensions; this study needs " +
                     std::to_string(width) + (spec.sensitivity ? " (two per key for Sobol indices)" : ""));
  // With Sobol indices, A is the first d columns and B the last d: for lhs and random two
  // independent designs, for sobol the two halves of one 2d-dimensional sequence.
  Matrix u = unit_design(spec.method, spec.n, width, spec.seed);
  if (spec.correlation.size() > 0) u = correlate(u, spec.correlation);
  auto map = [&](double p, int j) { return spec.distributions[std::size_t(j)].quantile(p); };
  if (!spec.sensitivity) {
    out.factors.resize(spec.n, d);
    for (Index i = 0; i < spec.n; ++i)
      for (int j = 0; j < d; ++j) out.factors(i, j) = map(u(i, j), j);
    return out;
  }
  out.factors.resize(spec.n * (d + 2), d);
  for (Index i = 0; i < spec.n; ++i) {
    const Index base = i * (d + 2);
    for (int j = 0; j < d; ++j) {
      const double a = map(u(i, j), j), b = map(u(i, d + j), j);
      out.factors(base, j) = a;
      out.factors(base + 1, j) = b;
      for (int k = 0; k < d; ++k) out.factors(base + 2 + k, j) = (k == j) ? b : a;
    }
  }
  return out;
}

}  // namespace viaduct::study
