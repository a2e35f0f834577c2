#pragma once
/// \file Eigen aliases used across viaduct. All quantities are SI unless a name says otherwise.

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

namespace viaduct {

using Index = Eigen::Index;
using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
/// Column-major sparse matrix; symmetric operators are stored in full (both triangles).
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

/// Nonzero entries of a sparse load vector, reused from step to step (clear() keeps capacity).
struct SparseForce {
  std::vector<Index> dof;     ///< DOF index, in [0, n_dofs); a DOF may appear more than once
  std::vector<double> value;  ///< [N] or [N m], added up per DOF
  void clear() {
    dof.clear();
    value.clear();
  }
  void add(Index d, double v) {
    dof.push_back(d);
    value.push_back(v);
  }
};

}  // namespace viaduct
