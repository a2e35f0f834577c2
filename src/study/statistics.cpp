#include "viaduct/study/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "viaduct/core/error.hpp"

namespace viaduct::study {

double percentile_of_sorted(const std::vector<double>& sorted, double p) {
  VIADUCT_ASSERT(!sorted.empty() && p >= 0.0 && p <= 100.0);
  const double rank = p / 100.0 * double(sorted.size() - 1);
  const std::size_t lo = std::size_t(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (rank - double(lo)) * (sorted[hi] - sorted[lo]);
}

Exceedance exceedance(const std::vector<double>& values, double limit) {
  Exceedance e;
  e.n = Index(values.size());
  if (e.n == 0) return e;
  e.n_over = Index(std::count_if(values.begin(), values.end(), [&](double x) { return x > limit; }));
  const double n = double(e.n);
  e.p = double(e.n_over) / n;
  e.se = std::sqrt(e.p * (1.0 - e.p) / n);
  constexpr double z = 1.959963984540054;  // Φ⁻¹(0.975)
  const double z2n = z * z / n;
  e.upper95 = std::min(1.0, (e.p + 0.5 * z2n + z * std::sqrt(e.p * (1.0 - e.p) / n + 0.25 * z2n / n)) / (1.0 + z2n));
  return e;
}

namespace statistics_detail {

// The indices of one resample (rows idx of the base points).
void estimate(const Vector& fa, const Vector& fb, const Matrix& fab, const std::vector<Index>& idx, std::vector<double>& s,
              std::vector<double>& st) {
  const Index n = Index(idx.size()), d = fab.cols();
  double mean = 0.0;
  for (Index r : idx) mean += fa(r) + fb(r);
  mean /= double(2 * n);
  double var = 0.0;
  for (Index r : idx) var += (fa(r) - mean) * (fa(r) - mean) + (fb(r) - mean) * (fb(r) - mean);
  var /= double(2 * n);
  for (Index i = 0; i < d; ++i) {
    double first = 0.0, total = 0.0;
    for (Index r : idx) {
      first += (fb(r) - mean) * (fab(r, i) - fa(r));
      total += (fa(r) - fab(r, i)) * (fa(r) - fab(r, i));
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s[std::size_t(i)] = var > 0.0 ? first / double(n) / var : nan;
    st[std::size_t(i)] = var > 0.0 ? total / double(2 * n) / var : nan;
  }
}

double quantile_of(std::vector<double> xs, double q) {
  std::sort(xs.begin(), xs.end());
  return percentile_of_sorted(xs, 100.0 * q);
}

}  // namespace statistics_detail

std::vector<SobolIndex> sobol_indices(const Vector& fa, const Vector& fb, const Matrix& fab, const SobolOptions& options) {
  const Index n = fa.size(), d = fab.cols();
  if (fb.size() != n || fab.rows() != n || n < 2)
    throw InputError("sobol_indices: f(A), f(B) and f(AB) need the same number (>= 2) of base points");
  if (options.n_bootstrap < 0 || !(options.level > 0.0 && options.level < 1.0))
    throw InputError("SobolOptions: violated constraint n_bootstrap >= 0 and 0 < level < 1");
  std::vector<Index> idx(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) idx[std::size_t(i)] = i;
  std::vector<double> s(static_cast<std::size_t>(d)), st(static_cast<std::size_t>(d));
  statistics_detail::estimate(fa, fb, fab, idx, s, st);
  std::vector<SobolIndex> out(static_cast<std::size_t>(d));
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {s[i], s[i], s[i], st[i], st[i], st[i]};
  if (options.n_bootstrap == 0 || std::isnan(s.front())) return out;
  std::vector<std::vector<double>> bs(static_cast<std::size_t>(d)), bst(static_cast<std::size_t>(d));
  std::mt19937_64 g(options.seed);
  for (int b = 0; b < options.n_bootstrap; ++b) {
    for (auto& r : idx) r = Index(g() % std::uint64_t(n));
    statistics_detail::estimate(fa, fb, fab, idx, s, st);
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (std::isfinite(s[i])) bs[i].push_back(s[i]);  // a resample of equal responses has none
      if (std::isfinite(st[i])) bst[i].push_back(st[i]);
    }
  }
  const double tail = 0.5 * (1.0 - options.level);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (bs[i].empty() || bst[i].empty()) continue;
    out[i].s_lo = statistics_detail::quantile_of(bs[i], tail);
    out[i].s_hi = statistics_detail::quantile_of(bs[i], 1.0 - tail);
    out[i].st_lo = statistics_detail::quantile_of(bst[i], tail);
    out[i].st_hi = statistics_detail::quantile_of(bst[i], 1.0 - tail);
  }
  return out;
}

}  // namespace viaduct::study
