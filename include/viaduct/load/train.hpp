#pragma once
/// \file Trains as lists of constant axle loads.

#include <string>
#include <vector>

namespace viaduct::load {

/// A train of constant axle loads. Axle i is `offset[i]` metres behind the first axle.
/// Most axles a train may have (a 1.5 km freight train has about 400).
constexpr std::size_t kMaxAxles = 10000;

struct Train {
  std::string name;
  std::vector<double> offset;  ///< [m] first 0, non-decreasing
  std::vector<double> load;    ///< [N] per axle, > 0

  std::size_t n_axles() const { return offset.size(); }
  double length() const { return offset.empty() ? 0.0 : offset.back(); }  ///< [m] first to last axle
  double total_load() const;                                               ///< [N]
  /// Throws InputError naming the train and the broken rule.
  void validate() const;
};

/// Eurocode HSLM-A train (EN 1991-2 Annex E) from its table row: N coaches of length D with
/// articulated bogies of axle spacing d, axle load P. Power cars: axles at 0, 3, 14, 17 m;
/// 3.525 m to the end coach's first axle; symmetric tail; 2N + 14 axles.
struct HslmRow {
  int n_coaches = 0;          ///< N
  double coach_length = 0.0;  ///< [m] D
  double bogie_spacing = 0.0; ///< [m] d
  double axle_load = 0.0;     ///< [N] P
};
Train hslm_a(const std::string& name, const HslmRow& row);
/// The ten table rows A1…A10 (REFERENCE.md §3); index 1..10.
HslmRow hslm_a_row(int number);

/// `n_axles` equal loads `load` [N] spaced `spacing` [m].
Train regular_train(const std::string& name, int n_axles, double spacing, double load);

/// The train's characteristic distance d [m]: the wavelength λ in [min_m, max_m] at which its
/// loads add up best, |Σ P_k exp(−2πi x_k/λ)| (the first term of ERRI D214's train signature);
/// the longest λ within 1 % of the best, so that a regular train gives its spacing, not a
/// fraction of it. Resonance of a span with frequency f is expected at v = f·d/j. 0 for fewer
/// than two axles.
double characteristic_distance(const Train& t, double min_m = 5.0, double max_m = 50.0);

}  // namespace viaduct::load
