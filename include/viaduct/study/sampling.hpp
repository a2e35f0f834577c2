#pragma once
/// \file Sampled studies: distributions of a key's factor, sampling designs (random, Latin
/// hypercube, Sobol sequence), correlated inputs through a Gaussian copula, and the Saltelli
/// design of Sobol sensitivity indices.
///
/// A sampled input is the factor on a scenario key's reference value (the value the scenario
/// gives), as the factors of one-at-a-time and grid sweeps are: key = reference × factor.
/// Everything here is deterministic in (design, seed) on any platform: the random numbers come
/// from std::mt19937_64's bits (whose sequence the standard fixes), never from the
/// implementation-defined std::*_distribution.

#include <cstdint>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::study {

/// Φ(x), the standard normal distribution function (accurate in both tails: erfc).
double normal_cdf(double x);
/// Q(x) = 1 − Φ(x) without cancellation for large x.
double normal_sf(double x);
/// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation refined by one Halley step on erfc
/// (relative error ~1e-15 over (1e-300, 1 − 1e-16)); ±infinity at 0 and 1, NaN outside [0, 1].
double normal_quantile(double p);

enum class DistributionKind { uniform, normal, lognormal, truncated };

/// A factor's distribution. uniform: low, high. normal: mean, sd. lognormal: the mean and sd of
/// the factor itself (not of its logarithm). truncated: the normal (mean, sd) restricted to
/// [low, high].
struct Distribution {
  DistributionKind kind = DistributionKind::uniform;
  double low = 0.0, high = 0.0;  ///< [-] uniform and truncated: 0 <= low < high
  double mean = 1.0, sd = 0.0;   ///< [-] normal, lognormal, truncated: sd > 0; lognormal mean > 0
  /// The factor whose probability of not being exceeded is u, u in (0, 1).
  double quantile(double u) const;
  /// The smallest and largest factor the distribution gives with more than 1e-9 probability
  /// outside them (uniform and truncated: its bounds), for checking the key's rule at both ends.
  std::pair<double, double> support() const;
  /// Factors are multipliers of a key's value: they must not fall below 0. A normal whose
  /// probability below 0 exceeds 1e-9 (mean < 6 sd) is refused, as is a truncation interval
  /// holding under 1e-12 of the normal's probability. `why` names the field and the rule.
  bool is_valid(std::string* why) const;
};
/// "uniform" ... "truncated"; InputError-free: returns false for another name.
bool distribution_kind_of(const std::string& name, DistributionKind* kind);

enum class SamplingMethod { random, lhs, sobol };
bool sampling_method_of(const std::string& name, SamplingMethod* method);

/// The Sobol low-discrepancy sequence in up to max_dimensions() dimensions, with the direction
/// numbers of Joe and Kuo (2008, new-joe-kuo-6.21201), points in Gray-code order (point 0 is the
/// origin), 32 bits per coordinate. Point i is computed directly, so shards need no state.
class SobolSequence {
 public:
  static constexpr int max_dimensions() { return 32; }
  /// d in [1, max_dimensions()]; InputError beyond.
  explicit SobolSequence(int d);
  int dimensions() const { return d_; }
  /// Coordinate j of point i as its 32 bits (the unit coordinate is bits / 2^32).
  std::uint32_t bits(std::uint64_t i, int j) const;

 private:
  int d_;
  std::vector<std::uint32_t> v_;  // direction numbers, 32 per dimension
};

/// n points in (0, 1)^d, one per row: random (independent uniforms), lhs (Latin hypercube: each
/// column holds one point in each of the n strata [k/n, (k+1)/n), at a random place in it) or
/// sobol (points 0 .. n−1 of the sequence with a random digital shift from the seed, which keeps
/// its stratification (a (t, m, d)-net at powers of 2) and keeps coordinates off 0; each
/// coordinate is the centre of its 2^-32 cell). d <= SobolSequence::max_dimensions() for sobol.
Matrix unit_design(SamplingMethod method, Index n, int d, std::uint64_t seed);

/// Maps independent uniforms (rows of u) to uniforms whose underlying normals have correlation
/// matrix `r` (Gaussian copula, as Nataf's transformation): z = Φ⁻¹(u), z ← z Lᵀ with r = L Lᵀ,
/// u ← Φ(z). InputError naming "sweep.correlations" when r is not a symmetric positive
/// definite correlation matrix (unit diagonal, entries in [-1, 1]).
Matrix correlate(const Matrix& u, const Matrix& r);

/// The inputs of a sampled study: one row per sample, one column per varied key (factors).
/// With Sobol indices (Saltelli's design), sample j·(d + 2) + b of the n·(d + 2) holds, for
/// base point j: b = 0 row j of A, b = 1 row j of B, b = 2 + i row j of A with column i from B
/// (A and B: two independent designs of n points, for sobol the first and last d coordinates of
/// a 2d-dimensional sequence). Interleaving keeps every base point's d + 2 samples together, so
/// a contiguous shard of the samples holds whole groups.
struct SampleDesign {
  Matrix factors;             ///< (samples × d)
  int d = 0;                  ///< varied keys
  Index n_base = 0;           ///< n
  bool saltelli = false;      ///< the (d + 2)-interleaved layout above
  /// Block of a sample: 0 (A), 1 (B) or 2 + i (A with column i from B); 0 without Saltelli.
  int block(Index sample) const { return saltelli ? int(sample % (d + 2)) : 0; }
  /// Samples that are independent draws of the joint distribution (A and B rows; every row
  /// without Saltelli): the percentiles and the exceedance probability use these.
  bool independent(Index sample) const { return block(sample) <= 1; }
};

struct SampleSpec {
  std::vector<Distribution> distributions;  ///< one per varied key
  SamplingMethod method = SamplingMethod::lhs;
  Index n = 0;                              ///< samples (base points with sensitivity); >= 2
  std::uint64_t seed = 1;
  bool sensitivity = false;                 ///< Saltelli's design for Sobol indices
  Matrix correlation;                       ///< empty, or d × d (refused with sensitivity)
};

/// The design of a spec: unit points (unit_design, correlated when asked), mapped through each
/// key's quantile function.
SampleDesign sample_design(const SampleSpec& spec);

}  // namespace viaduct::study
