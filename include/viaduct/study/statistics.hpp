#pragma once
/// \file Statistics of sampled studies: percentiles, the probability of exceeding a limit with
/// its sampling error, and Sobol sensitivity indices (Saltelli's first-order and Jansen's total
/// estimators) with bootstrap intervals.

#include <cstdint>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::study {

/// The p-th percentile (p in [0, 100]) of `sorted` (ascending, not empty), interpolating
/// linearly between order statistics at rank p/100 · (n − 1) (numpy's default, "linear").
double percentile_of_sorted(const std::vector<double>& sorted, double p);

/// The probability that a response exceeds `limit`, estimated from n samples.
struct Exceedance {
  Index n = 0, n_over = 0;  ///< samples, and those with value > limit
  double p = 0.0;           ///< n_over / n
  /// Binomial standard error sqrt(p (1 − p) / n): exact for independent samples, an upper
  /// bound for a Latin hypercube or Sobol sequence (whose estimates vary less).
  double se = 0.0;
  double upper95 = 0.0;     ///< Wilson score 95 % upper bound (3/n-like when n_over = 0)
};
Exceedance exceedance(const std::vector<double>& values, double limit);

/// Sobol indices of one key: first order S and total ST, each with its bootstrap interval.
struct SobolIndex {
  double s = 0.0, s_lo = 0.0, s_hi = 0.0;
  double st = 0.0, st_lo = 0.0, st_hi = 0.0;
};
struct SobolOptions {
  int n_bootstrap = 200;      ///< >= 0; 0: no intervals (lo = hi = the estimate)
  double level = 0.95;        ///< (0, 1): the percentile interval's coverage
  std::uint64_t seed = 1;     ///< of the resampling (the same resamples for every output)
};
/// Indices from Saltelli's design: fa = f(A), fb = f(B) (n each), fab column i = f(A with
/// column i from B) (n × d). f0 and V are the mean and variance of fa and fb together;
/// S_i = mean((fb − f0) (fab_i − fa)) / V (Saltelli et al. 2010, centred: the same expectation,
/// and without the centring a response whose mean is many times its spread, as a resonance peak
/// over uncertain pads, gets indices of ±50 from 32 points), ST_i = mean((fa − fab_i)²) / (2 V)
/// (Jansen 1999). Intervals: percentiles of the estimates over n_bootstrap resamples of the
/// n base points. NaN everywhere when V = 0 (the response does not vary).
std::vector<SobolIndex> sobol_indices(const Vector& fa, const Vector& fb, const Matrix& fab, const SobolOptions& options);

}  // namespace viaduct::study
