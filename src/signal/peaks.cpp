#include "viaduct/signal/peaks.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::signal {

bool PeakOptions::is_valid(std::string* why) const {
  OptionsCheck c("PeakOptions", why);
  // min_height may be -inf (no height limit), never NaN.
  return (!std::isnan(min_height) || c.fail("min_height", "nan", "min_height not NaN")) &&
         c.require(min_prominence >= 0.0, "min_prominence", min_prominence, "min_prominence >= 0") &&
         c.require(min_distance >= 1, "min_distance", static_cast<double>(min_distance), "min_distance >= 1 sample");
}

namespace {

// SciPy's prominence: the lowest point on each side before a higher sample (or the border);
// the base is the higher of the two minima.
double prominence(const Vector& y, Index i) {
  const double h = y[i];
  double left = h, right = h;
  for (Index j = i - 1; j >= 0 && y[j] <= h; --j) left = std::min(left, y[j]);
  for (Index j = i + 1; j < y.size() && y[j] <= h; ++j) right = std::min(right, y[j]);
  return h - std::max(left, right);
}

void refine(const Vector& y, Peak& p, Interpolation interp) {
  p.position = static_cast<double>(p.index);
  p.value = y[p.index];
  if (interp == Interpolation::none || p.index == 0 || p.index + 1 >= y.size()) return;
  double a = y[p.index - 1], b = y[p.index], c = y[p.index + 1];
  const bool logs = interp == Interpolation::gaussian && a > 0 && b > 0 && c > 0;
  if (logs) {
    a = std::log(a);
    b = std::log(b);
    c = std::log(c);
  }
  const double den = a - 2 * b + c;
  if (!(den < 0)) return;  // flat or not a maximum of the parabola
  const double d = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
  const double v = b - 0.25 * (a - c) * d;
  p.position += d;
  p.value = logs ? std::exp(v) : v;
}

}  // namespace

double max_abs_between_samples(const Vector& y) {
  const Index n = y.size();
  if (n == 0) return 0.0;
  Index i = 0;
  double best = std::abs(y[0]);
  for (Index k = 1; k < n; ++k) {
    const double a = std::abs(y[k]);
    if (a > best || std::isnan(a)) {
      best = a;
      i = k;
      if (std::isnan(a)) return a;
    }
  }
  if (i == 0 || i == n - 1) return best;
  // signed, as a maximum: s·y with s the sign of the extremum
  const double s = y[i] < 0.0 ? -1.0 : 1.0, a = s * y[i - 1], b = s * y[i], c = s * y[i + 1];
  const double curv = a - 2.0 * b + c;
  if (!(a <= b && c <= b && curv < 0.0)) return best;  // not an extremum of a smooth curve
  if (c == b && i + 2 < n && s * y[i + 2] >= b) return best;  // a plateau, not a crest between two samples
  return b - (c - a) * (c - a) / (8.0 * curv);
}

std::vector<Peak> find_peaks(const Vector& y, const PeakOptions& o, Interpolation interp) {
  std::string why;
  if (!o.is_valid(&why)) throw InputError("peak picking: " + why);
  if (!y.allFinite()) throw InputError("peak picking: the curve holds NaN or infinite values");
  // Local maxima; a flat top counts once, at its middle (rounded down).
  std::vector<Index> cand;
  for (Index i = 1; i + 1 < y.size(); ++i) {
    if (!(y[i - 1] < y[i])) continue;
    Index j = i;
    while (j + 1 < y.size() && y[j + 1] == y[i]) ++j;
    if (j + 1 < y.size() && y[j + 1] < y[i]) cand.push_back((i + j) / 2);
    i = j;
  }
  std::vector<Index> keep;
  for (Index i : cand)
    if (y[i] >= o.min_height) keep.push_back(i);
  if (o.min_distance > 1) {  // highest first; drop neighbours within the distance
    std::vector<Index> by_height = keep;
    std::stable_sort(by_height.begin(), by_height.end(), [&](Index a, Index b) { return y[a] > y[b]; });
    std::vector<Index> kept;
    for (Index i : by_height) {
      bool near = false;
      for (Index k : kept) near = near || std::abs(k - i) < o.min_distance;
      if (!near) kept.push_back(i);
    }
    std::sort(kept.begin(), kept.end());
    keep = kept;
  }
  std::vector<Peak> out;
  for (Index i : keep) {
    Peak p;
    p.index = i;
    p.prominence = prominence(y, i);
    if (p.prominence < o.min_prominence) continue;
    refine(y, p, interp);
    out.push_back(p);
  }
  if (o.max_peaks > 0 && out.size() > o.max_peaks) {
    std::stable_sort(out.begin(), out.end(), [](const Peak& a, const Peak& b) { return a.value > b.value; });
    out.resize(o.max_peaks);
    std::sort(out.begin(), out.end(), [](const Peak& a, const Peak& b) { return a.index < b.index; });
  }
  return out;
}

}  // namespace viaduct::signal
