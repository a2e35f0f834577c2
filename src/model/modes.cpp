#include "viaduct/model/modes.hpp"

#include <cmath>

#include "viaduct/core/error.hpp"

namespace viaduct::model {

Modes compute_modes(const Structure& s, Index n_modes) {
  if (s.n_dofs > kMaxDenseModeDofs)
    throw InputError("the dense eigen solver takes at most " + std::to_string(kMaxDenseModeDofs) +
                     " DOFs and this model has " + std::to_string(s.n_dofs) +
                     " (coarsen bridge.element_size or track.rail_elements_per_bay, or shorten the track)");
  const Matrix K = Matrix(s.K), M = Matrix(s.M);
  Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> es(K, M);
  if (es.info() != Eigen::Success) throw SolverError("eigenproblem failed (is M positive definite?)");
  const Index n = (n_modes <= 0 || n_modes > s.n_dofs) ? s.n_dofs : n_modes;
  Modes m;
  m.frequency_hz = es.eigenvalues().head(n).cwiseMax(0.0).cwiseSqrt() / (2.0 * M_PI);
  m.shape = es.eigenvectors().leftCols(n);
  return m;
}

}  // namespace viaduct::model
