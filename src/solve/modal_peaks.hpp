#pragma once
// The fused modal peaks kernel (private to src/solve; Integrator::run_batch reaches it).

#include <vector>

#include "viaduct/core/options.hpp"
#include "viaduct/solve/integrator.hpp"

namespace viaduct::solve::detail {

struct PeaksCase {
  double speed = 0.0;  ///< [m/s] > 0
  double t_end = 0.0;  ///< [s] > 0
};

struct PeaksCaseResult {
  Vector max_abs_disp, max_abs_acc;  ///< per recorded output
  Vector max_disp, min_disp;         ///< signed extremes of the deflection per output (max >= 0 >= min: from rest)
  Vector max_sum, min_sum;           ///< signed extremes of each sum of outputs (OutputSum), when asked for
  Matrix acc;                        ///< n_samples × (acc_outputs or n_outputs) when record_acc
  Summary summary;
};

/// Cases of the moving loads `L` at their speeds, four per SIMD pass, on the grid k·dt: running
/// maxima of the reduction's first n_outputs outputs, the signed extremes of `sums` of them (their
/// load channels among L's extra channels) and, with record_acc, the accelerations of the first
/// acc_outputs of them (-1: all).
/// InputError for invalid cases, loads folded for another reduction or histories over
/// max_history_bytes; SolverError when a state stops being finite.
std::vector<PeaksCaseResult> modal_peaks(const ModalReduction& r, const MovingChannels& L,
                                         const std::vector<PeaksCase>& cases, double dt, std::size_t n_outputs,
                                         bool record_acc, double max_history_bytes,
                                         const std::vector<OutputSum>& sums = {}, Index acc_outputs = -1);

}  // namespace viaduct::solve::detail
