#pragma once
/// \file The quasi-static response of a case (the same train crawling: no inertia, no damping)
/// and the dynamic increments φ′dyn = max|dynamic| / max|static| − 1 per quantity (EN 1991-2
/// 6.4.6.5), for the deflections of the stations and the load effects of a run.

#include <string>
#include <vector>

#include "viaduct/load/train.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// One quantity's dynamic and quasi-static maxima.
struct DynamicIncrement {
  std::string name;          ///< the history column: <station>_disp_m, <station>_moment_Nm, span1_start_rot_rad ...
  double max_dynamic = 0.0;  ///< max |y| over the run
  double max_static = 0.0;   ///< max |y| of the quasi-static response over the same samples
  double phi_dyn = 0.0;      ///< max_dynamic / max_static − 1 (NaN when max_static is 0)
};

struct QuasiStaticResult {
  /// Per quantity, in the order of `names`: the response to the loads at each sample time of the
  /// run, u(t) = K⁻¹ f(t) (the model's static FE solution, exact at the nodes).
  std::vector<std::string> names;
  std::vector<Vector> value;
  std::vector<DynamicIncrement> increments;  ///< against the run's histories
};

/// The quasi-static response of `train` at `speed` at the samples of `run` (simulate()'s result
/// for the same case), for every deck station's deflection and every load effect the model was
/// prepared with: one sparse factorisation of K, one solve per quantity (its influence line
/// z = K⁻¹ c), then zᵀ f(t) per sample. SolverError when K cannot be factorised.
QuasiStaticResult quasi_static(const PreparedModel& m, const load::Train& train, double speed, double load_factor,
                               const RunResult& run);

}  // namespace viaduct::study
