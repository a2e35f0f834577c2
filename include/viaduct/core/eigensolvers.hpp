#pragma once
/// \file Eigen's dense eigensolvers on Eigen::MatrixXd, compiled once (src/core/eigensolvers.cpp)
/// instead of in every translation unit that uses them: each costs 5 to 13 s of compile time per
/// unit (EigenSolver the most), and seven units used them (#37 item 6: CI within 15 minutes;
/// docs/benchmarks.md). Include this header, not <Eigen/Eigenvalues>, where one of these solvers is
/// constructed from a MatrixXd; the code generated is the same, so are the results.

#include <Eigen/Eigenvalues>

extern template class Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;
extern template Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>&
Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>::compute<Eigen::MatrixXd>(const Eigen::EigenBase<Eigen::MatrixXd>&, int);
extern template class Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>;
extern template class Eigen::EigenSolver<Eigen::MatrixXd>;
extern template Eigen::EigenSolver<Eigen::MatrixXd>&
Eigen::EigenSolver<Eigen::MatrixXd>::compute<Eigen::MatrixXd>(const Eigen::EigenBase<Eigen::MatrixXd>&, bool);
