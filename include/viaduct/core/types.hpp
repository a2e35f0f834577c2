#pragma once
/// \file Eigen aliases used across viaduct. All quantities are SI unless a name says otherwise.

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace viaduct {

using Index = Eigen::Index;
using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
/// Column-major sparse matrix; symmetric operators are stored in full (both triangles).
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

}  // namespace viaduct
