#include "viaduct/model/damping.hpp"

#include <cmath>

#include "viaduct/core/eigensolvers.hpp"
#include "viaduct/core/error.hpp"

namespace viaduct::model {

std::pair<double, double> rayleigh_coefficients(double f1_hz, double ratio1, double f2_hz,
                                                double ratio2) {
  if (!(f1_hz > 0.0 && f2_hz > f1_hz)) throw InputError("Rayleigh damping needs 0 < f1 < f2");
  const double w1 = 2.0 * M_PI * f1_hz, w2 = 2.0 * M_PI * f2_hz;
  const double den = w2 * w2 - w1 * w1;
  const double a0 = 2.0 * w1 * w2 * (ratio1 * w2 - ratio2 * w1) / den;
  const double a1 = 2.0 * (ratio2 * w2 - ratio1 * w1) / den;
  return {a0, a1};
}

Matrix structural_damping(const SparseMatrix& Ms, const SparseMatrix& Ks, const BridgeDamping& d) {
  const Matrix M = Matrix(Ms), K = Matrix(Ks);
  switch (d.kind) {
    case DampingKind::none: return Matrix::Zero(M.rows(), M.cols());
    case DampingKind::rayleigh: {
      const auto [a0, a1] = rayleigh_coefficients(d.f1_hz, d.ratio1, d.f2_hz, d.ratio2);
      return a0 * M + a1 * K;
    }
    case DampingKind::modal: {
      if (d.ratio == 0.0) return Matrix::Zero(M.rows(), M.cols());
      Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> es(K, M);
      if (es.info() != Eigen::Success) throw SolverError("span eigenproblem failed (modal damping)");
      const Vector w = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
      const Matrix MPhi = M * es.eigenvectors();  // Φ is M-normalised
      const Matrix C = MPhi * (2.0 * d.ratio * w).asDiagonal() * MPhi.transpose();
      return 0.5 * (C + C.transpose());  // exactly symmetric
    }
  }
  return Matrix::Zero(M.rows(), M.cols());
}

}  // namespace viaduct::model
