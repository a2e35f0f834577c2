#pragma once
// Private to src/study: small operations on sampled series shared by the comparison and the
// speed identification.
#include <cmath>

#include "viaduct/core/types.hpp"

namespace viaduct::study::detail {

/// x (sampled at fs from t = 0) linearly interpolated at t; 0 outside, its last sample at its end.
inline double sample_at(const Vector& x, double fs, double t) {
  const double s = t * fs;
  if (!(s >= 0.0) || s > static_cast<double>(x.size() - 1)) return 0.0;
  const auto i = static_cast<Index>(std::floor(s));
  if (i + 1 >= x.size()) return x[x.size() - 1];
  const double w = s - static_cast<double>(i);
  return (1.0 - w) * x[i] + w * x[i + 1];
}

/// Pearson correlation coefficient of two series of one length; 0 when either is constant.
inline double pearson(const Vector& a, const Vector& b) {
  const Vector da = a.array() - a.mean(), db = b.array() - b.mean();
  const double den = std::sqrt(da.squaredNorm() * db.squaredNorm());
  return den > 0 ? da.dot(db) / den : 0.0;
}

}  // namespace viaduct::study::detail
