#pragma once
// Private to src/study: the tabulated modal loads of a unit axle along the load path
// (simulation.cpp builds it and folds it over a train for the peaks kernel: fold_train).

#include <cstddef>
#include <vector>

namespace viaduct::study {

struct ModalPathTable {
  std::vector<double> x0, h, inv_h;  // per path element
  /// Per element: 4 cubic coefficients (powers of the element coordinate ξ in [0, 1]) per load
  /// channel, then per static-correction output (flexibility), `stride` values in all.
  std::vector<double> coef;
  std::size_t m = 0, n_out = 0, stride = 0;
  bool flex = false;
  double x_start = 0.0, x_end = 0.0;
};

}  // namespace viaduct::study
