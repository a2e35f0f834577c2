#include "viaduct/model/modes.hpp"

#include <cmath>

#include "viaduct/core/error.hpp"

namespace viaduct::model {

Modes compute_modes(const Structure& s, Index n_modes) {
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
