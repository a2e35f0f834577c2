#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include <Eigen/SparseCholesky>

#include "viaduct/core/eigensolvers.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/solve/modal.hpp"
#include "viaduct/solve/newmark.hpp"

using namespace viaduct;
using namespace viaduct::solve;

namespace {
// n masses in a chain between two walls; force F(t) on one DOF.
class Chain : public SecondOrderSystem {
 public:
  Chain(int n, double m, double k, double a0, double a1, Index loaded, std::function<double(double)> F)
      : loaded_(loaded), F_(std::move(F)) {
    std::vector<Triplet> tm, tk;
    for (int i = 0; i < n; ++i) {
      tm.emplace_back(i, i, m * (1.0 + 0.3 * i));
      tk.emplace_back(i, i, 2 * k);
      if (i > 0) tk.emplace_back(i, i - 1, -k), tk.emplace_back(i - 1, i, -k);
    }
    M_.resize(n, n), K_.resize(n, n);
    M_.setFromTriplets(tm.begin(), tm.end());
    K_.setFromTriplets(tk.begin(), tk.end());
    C_ = a0 * M_ + a1 * K_;
  }
  const SparseMatrix& mass() const override { return M_; }
  const SparseMatrix& damping() const override { return C_; }
  const SparseMatrix& stiffness() const override { return K_; }
  void force(double t, Vector& f) const override {
    f.setZero();
    f[loaded_] = F_(t);
  }
  // All modes of the chain.
  void modes(Matrix& shape, Vector& omega) const {
    Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> es{Matrix(K_), Matrix(M_)};
    shape = es.eigenvectors();
    omega = es.eigenvalues().cwiseSqrt();
  }
  SparseMatrix M_, C_, K_;
  Index loaded_;
  std::function<double(double)> F_;
};

Functional at(Index d) { return Functional{{d}, {1.0}}; }

// Runs the reduction (output 0: displacement at DOF 0; output 1: the acceleration compared) and
// Newmark at the same step on `sys`; returns the largest differences relative to Newmark's peaks
// of u[0] and of a[dof_acc].
std::pair<double, double> modal_vs_newmark(const Chain& sys, const ModalReduction& red, Index dof_acc, double dt,
                                           double t_end) {
  const ModalOptions mo;
  const TimeGrid g{dt, t_end};
  std::vector<double> md, ma;
  red.integrate(sys, g, mo, [&](Index, double, const Vector& d, const Vector& a) {
    md.push_back(d[0]);
    ma.push_back(a[1]);
  });
  const NewmarkOptions no;
  std::vector<double> nd, na;
  newmark(sys, g, no, [&](Index, double, const Vector& u, const Vector&, const Vector& a) {
    nd.push_back(u[0]);
    na.push_back(a[dof_acc]);
  });
  REQUIRE(nd.size() == md.size());
  double pd = 0, ed = 0, pa = 0, ea = 0;
  for (std::size_t k = 0; k < nd.size(); ++k) {
    pd = std::max(pd, std::abs(nd[k]));
    ed = std::max(ed, std::abs(nd[k] - md[k]));
    pa = std::max(pa, std::abs(na[k]));
    ea = std::max(ea, std::abs(na[k] - ma[k]));
  }
  REQUIRE(pd > 0);
  REQUIRE(pa > 0);
  return {ed / pd, ea / pa};
}
}  // namespace

TEST_CASE("the modal step is exact for constant and linear loads at any step size") {
  // Closed forms from rest; tolerance 1e-11 relative: the matrix exponential is accurate to
  // rounding, and the step (0.37 s, ω dt = 7) is far beyond any stability limit of a scheme
  // that is not exact.
  const double w = 2 * M_PI * 3.0, dt = 0.37;
  for (double z : {0.0, 0.05, 0.7}) {
    const auto c = exact_step_coefficients(w, z, dt);
    double q = 0, qd = 0;
    for (int k = 1; k <= 20; ++k) {
      const double qn = c[0] * q + c[1] * qd + c[2] * 1.0 + c[3] * 1.0;
      qd = c[4] * q + c[5] * qd + c[6] * 1.0 + c[7] * 1.0;
      q = qn;
      const double t = k * dt, wd = w * std::sqrt(1 - z * z);
      const double exact = (1 - std::exp(-z * w * t) * (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t))) / (w * w);
      REQUIRE(q == Approx(exact).epsilon(1e-11).margin(1e-14));
    }
  }
  // p(t) = t, undamped: q = (t - sin(ω t)/ω)/ω².
  const auto c = exact_step_coefficients(w, 0.0, dt);
  double q = 0, qd = 0;
  for (int k = 1; k <= 20; ++k) {
    const double p0 = (k - 1) * dt, p1 = k * dt;
    const double qn = c[0] * q + c[1] * qd + c[2] * p0 + c[3] * p1;
    qd = c[4] * q + c[5] * qd + c[6] * p0 + c[7] * p1;
    q = qn;
    const double t = k * dt;
    REQUIRE(q == Approx((t - std::sin(w * t) / w) / (w * w)).epsilon(1e-11));
  }
}

TEST_CASE("modal superposition with every mode matches converged Newmark") {
  // Rayleigh damping is diagonal in the modes, so with all modes the two methods solve the same
  // equations: they must agree to Newmark's own error at dt = 1e-4 s (about 1e-6 here).
  const Chain sys(6, 10.0, 4e4, 0.5, 1e-4, 2, [](double t) { return 100.0 * std::sin(17.0 * t) * std::exp(-t); });
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  const ModalReduction red(sys.M_, sys.C_, sys.K_, shape, omega, {at(0), at(4)}, false);
  REQUIRE(red.max_damping_coupling() < 1e-9);
  const auto [err_d, err_a] = modal_vs_newmark(sys, red, 4, 1e-4, 2.0);
  REQUIRE(err_d < 1e-4);
  REQUIRE(err_a < 1e-4);
}

TEST_CASE("the static correction restores the quasi-static response of dropped modes") {
  // A slowly ramped load (1000 s ramp, lowest period ~0.1 s) is quasi-static: u = K⁻¹ f. With one
  // mode the displacement under the load is far off; the correction makes it exact to the
  // tiny dynamic part (< 1e-6 relative).
  const Chain sys(8, 10.0, 4e4, 0.5, 1e-4, 6, [](double t) { return 1000.0 * std::min(t / 1000.0, 1.0); });
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  Vector f = Vector::Zero(8);
  f[6] = 1000.0;
  Eigen::SimplicialLDLT<SparseMatrix> lk(sys.K_);
  const double u_static = lk.solve(f)[6];
  auto final_disp = [&](bool correction) {
    const ModalReduction red(sys.M_, sys.C_, sys.K_, shape.leftCols(1), omega.head(1), {at(6)}, correction);
    const ModalOptions mo;
    const TimeGrid g{0.5, 1200.0};  // exact per step: a coarse step is fine
    double last = 0;
    red.integrate(sys, g, mo, [&](Index, double, const Vector& d, const Vector&) { last = d[0]; });
    return last;
  };
  REQUIRE(std::abs(final_disp(false) - u_static) > 0.3 * u_static);
  REQUIRE(final_disp(true) == Approx(u_static).epsilon(1e-6));
}

TEST_CASE("non-proportional damping is measured, invalid bases and options are refused") {
  Chain sys(4, 10.0, 4e4, 0.0, 0.0, 1, [](double) { return 1.0; });
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  sys.C_.coeffRef(0, 0) += 50.0;  // one local dashpot: couples the modes
  const ModalReduction red(sys.M_, sys.C_, sys.K_, shape, omega, {at(0)}, true);
  REQUIRE(red.max_damping_coupling() > 0.05);
  REQUIRE((red.zeta().array() > 0).all());
  Vector w0 = omega;
  w0[0] = 0.0;
  REQUIRE_THROWS_WITH(ModalReduction(sys.M_, sys.C_, sys.K_, shape, w0, {at(0)}, false), Catch::Contains("zero frequency"));
  REQUIRE_THROWS_WITH(ModalReduction(sys.M_, sys.C_, sys.K_, shape.topRows(3), omega, {at(0)}, false),
                      Catch::Contains("wrong number of rows"));
  REQUIRE_THROWS_WITH(ModalReduction(sys.M_, sys.C_, sys.K_, shape, omega, {at(9)}, false), Catch::Contains("out of range"));
  REQUIRE_THROWS_WITH(red.integrate(sys, TimeGrid{0.0, 1.0}, ModalOptions{}, nullptr),
                      Catch::Contains("TimeGrid::dt = 0: violated constraint dt > 0"));
}

TEST_CASE("a reduction for the coupled vehicle kernels keeps the real modes and the flexibility they drop") {
  // A chain with a local dashpot (Φᵀ C Φ not diagonal), two of eight modes kept, the wheels on
  // DOFs 2, 3 and 5 and one output (DOF 4). The reduced matrices are Φᵀ M Φ, Φᵀ C Φ and Φᵀ K Φ of
  // the mass-normalised shapes; the residual flexibility between the contact DOFs and to the
  // output is K⁻¹ − Φ Ω⁻² Φᵀ (to rounding: 1e-10 of K⁻¹'s largest term); the coupled damping
  // is kept as it is (no complex coordinates are built), and integrate() refuses the reduction.
  Chain sys(8, 10.0, 4e4, 0.0, 0.0, 1, [](double) { return 1.0; });
  sys.C_.coeffRef(0, 0) += 300.0;
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  const std::vector<Index> contact = {5, 2, 3};
  const ModalReduction red(sys.M_, sys.C_, sys.K_, 3.0 * shape.leftCols(2), omega.head(2), {at(4)}, true, contact);
  REQUIRE(red.coupled());
  REQUIRE_FALSE(red.complex_modes());
  const Matrix& phi = red.shapes();
  const Matrix I = Matrix::Identity(2, 2);
  CHECK((phi.transpose() * (sys.M_ * phi) - I).norm() < 1e-12);
  const auto& cm = red.coupled_matrices();
  CHECK((Matrix(cm.M) - I).norm() == 0.0);
  const Matrix Cm = phi.transpose() * (sys.C_ * phi);
  CHECK(std::abs(Cm(0, 1)) > 0.1 * std::sqrt(Cm(0, 0) * Cm(1, 1)));  // the dashpot couples the two modes
  CHECK((Matrix(cm.C) - Cm).norm() < 1e-12 * Cm.norm());
  CHECK((Matrix(cm.K) - Matrix(omega.head(2).cwiseAbs2().asDiagonal())).norm() < 1e-12 * omega[1] * omega[1]);
  const Matrix Kinv = Matrix(sys.K_).inverse();
  const Matrix R = Kinv - phi * omega.head(2).cwiseAbs2().cwiseInverse().asDiagonal() * phi.transpose();
  const double tol = 1e-10 * Kinv.cwiseAbs().maxCoeff();
  for (std::size_t a = 0; a < contact.size(); ++a) {
    REQUIRE(red.contact_slot(contact[a]) == static_cast<Index>(a));
    CHECK(std::abs(red.contact_output_residual()(static_cast<Index>(a), 0) - R(contact[a], 4)) < tol);
    for (std::size_t b = 0; b < contact.size(); ++b)
      CHECK(std::abs(red.contact_residual()(static_cast<Index>(a), static_cast<Index>(b)) - R(contact[a], contact[b])) < tol);
  }
  CHECK(red.contact_slot(0) == -1);
  CHECK(red.contact_slot(99) == -1);
  CHECK_THROWS_WITH(red.integrate(sys, TimeGrid{0.01, 1.0}, ModalOptions{}, nullptr),
                    Catch::Contains("built for the coupled vehicle kernels"));
  for (const bool correction : {true, false}) {  // the contact DOFs are checked with or without the correction
    CHECK_THROWS_WITH(ModalReduction(sys.M_, sys.C_, sys.K_, shape.leftCols(2), omega.head(2), {at(4)}, correction, {2, 2}),
                      Catch::Contains("contact DOF given twice"));
    CHECK_THROWS_WITH(ModalReduction(sys.M_, sys.C_, sys.K_, shape.leftCols(2), omega.head(2), {at(4)}, correction, {8}),
                      Catch::Contains("contact DOF out of range"));
  }
  // The uncoupled reduction of the same modes integrates complex coordinates instead.
  CHECK(ModalReduction(sys.M_, sys.C_, sys.K_, shape.leftCols(2), omega.head(2), {at(4)}, true).complex_modes());
}

TEST_CASE("coupled (non-proportional) damping: complex modes with every mode match converged Newmark") {
  // A chain with two local dashpots: Φᵀ C Φ is far from diagonal. With all modes the complex
  // formulation solves the same equations as Newmark, so they agree to Newmark's error at
  // dt = 1e-4 s (~1e-6); dropping the coupling would be off by tens of per cent here.
  Chain sys(6, 10.0, 4e4, 0.0, 0.0, 2, [](double t) { return 100.0 * std::sin(23.0 * t) * (t < 0.6 ? 1.0 : 0.0); });
  sys.C_.coeffRef(0, 0) += 400.0;
  sys.C_.coeffRef(5, 5) += 900.0;
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  const ModalReduction red(sys.M_, sys.C_, sys.K_, shape, omega, {at(0), at(3)}, false);
  REQUIRE(red.complex_modes());
  REQUIRE(red.max_damping_coupling() > 0.1);
  const auto [ed, ea] = modal_vs_newmark(sys, red, 3, 1e-4, 1.5);
  REQUIRE(ed < 1e-4);
  REQUIRE(ea < 1e-4);
}

namespace {
// Largest relative distance from each of the `count` lowest complex eigenvalues of (M, C, K) to
// the nearest eigenvalue of the system projected on the mass-normalised basis B.
double low_eigenvalue_error(const Chain& sys, const Matrix& B, Index count) {
  auto eig = [](const Matrix& M, const Matrix& C, const Matrix& K) {
    const Index n = M.rows();
    const Matrix Mi = M.inverse();
    Matrix A = Matrix::Zero(2 * n, 2 * n);
    A.topRightCorner(n, n).setIdentity();
    A.bottomLeftCorner(n, n) = -Mi * K;
    A.bottomRightCorner(n, n) = -Mi * C;
    Eigen::EigenSolver<Matrix> es(A);
    Eigen::VectorXcd l = es.eigenvalues();
    std::sort(l.data(), l.data() + l.size(), [](auto a, auto b) { return std::abs(a) < std::abs(b); });
    return l;
  };
  const Matrix M(sys.M_), C(sys.C_), K(sys.K_);
  const Eigen::VectorXcd full = eig(M, C, K);
  const Eigen::VectorXcd red = eig(B.transpose() * M * B, B.transpose() * C * B, B.transpose() * K * B);
  double worst = 0.0;
  for (Index i = 0; i < count; ++i) {
    double d = 1e300;
    for (Index j = 0; j < red.size(); ++j) d = std::min(d, std::abs(red[j] - full[i]));
    worst = std::max(worst, d / std::abs(full[i]));
  }
  return worst;
}
}  // namespace

TEST_CASE("damping vectors carry the low complex modes past a truncated basis") {
  // A 40-mass chain with strong local dashpots (a track's pads in miniature): the low complex
  // modes leak into high undamped modes. R C Φ lies in R·range(C), so C needs a rank above
  // 3 m for three blocks to be independent: 20 dashpots between neighbours.
  Chain sys(40, 10.0, 4e4, 0.0, 0.0, 2, [](double) { return 0.0; });
  for (int i = 1; i < 40; i += 2) {
    const double c = 1500.0 + 700.0 * (i % 3);
    sys.C_.coeffRef(i, i) += c;
    sys.C_.coeffRef(i - 1, i - 1) += c;
    sys.C_.coeffRef(i, i - 1) -= c;
    sys.C_.coeffRef(i - 1, i) -= c;
  }
  Matrix shape;
  Vector omega;
  sys.modes(shape, omega);
  for (Index j = 0; j < shape.cols(); ++j) shape.col(j) /= std::sqrt(shape.col(j).dot(sys.M_ * shape.col(j)));
  const Index m = 6;
  const Matrix phi = shape.leftCols(m);
  const Vector w = omega.head(m);
  Vector w1, w2;
  const Matrix b1 = damping_enriched_basis(sys.M_, sys.C_, sys.K_, phi, w, 1, &w1);
  const Matrix b2 = damping_enriched_basis(sys.M_, sys.C_, sys.K_, phi, w, 2, &w2);
  REQUIRE(b1.cols() == 2 * m);
  REQUIRE(b2.cols() == 3 * m);
  // A Ritz basis: M-orthonormal, K-diagonal with the returned frequencies, the modes first.
  for (const auto* p : {&b1, &b2}) {
    const Matrix& b = *p;
    const Vector& wb = p == &b1 ? w1 : w2;
    REQUIRE((b.transpose() * (sys.M_ * b) - Matrix::Identity(b.cols(), b.cols())).cwiseAbs().maxCoeff() < 1e-10);
    const Matrix kr = b.transpose() * (sys.K_ * b);
    REQUIRE((kr - Matrix(wb.cwiseAbs2().asDiagonal())).cwiseAbs().maxCoeff() < 1e-9 * wb.cwiseAbs2().maxCoeff());
    REQUIRE((b.leftCols(m) - phi).cwiseAbs().maxCoeff() == 0.0);
  }
  const double e0 = low_eigenvalue_error(sys, phi, 4), e1 = low_eigenvalue_error(sys, b1, 4),
               e2 = low_eigenvalue_error(sys, b2, 4);
  INFO("relative error of the 4 lowest complex eigenvalues: modes " << e0 << ", +1 block " << e1 << ", +2 " << e2);
  REQUIRE(e0 > 1e-3);  // the case is one where truncation misses the damping
  REQUIRE(e1 < e0 / 10);
  REQUIRE(e2 < e1);
  // A cap on the Ritz frequencies (the output's Nyquist limit) just below the top pair: fewer
  // seeds, every pair below the cap, the basis still M-orthonormal.
  const double cap = 0.999 * w1.tail(m).maxCoeff();
  Vector wc;
  const Matrix bc = damping_enriched_basis(sys.M_, sys.C_, sys.K_, phi, w, 1, &wc, cap);
  REQUIRE(bc.cols() > m);
  REQUIRE(bc.cols() < b1.cols());
  REQUIRE(wc.tail(bc.cols() - m).maxCoeff() <= cap);
  REQUIRE((bc.transpose() * (sys.M_ * bc) - Matrix::Identity(bc.cols(), bc.cols())).cwiseAbs().maxCoeff() < 1e-10);
  // Classical damping: nothing to carry, the modes come back alone.
  Chain rayleigh(40, 10.0, 4e4, 0.5, 1e-4, 2, [](double) { return 0.0; });
  Matrix rs;
  Vector rw, rw_out;
  rayleigh.modes(rs, rw);
  for (Index j = 0; j < rs.cols(); ++j) rs.col(j) /= std::sqrt(rs.col(j).dot(rayleigh.M_ * rs.col(j)));
  REQUIRE(damping_enriched_basis(rayleigh.M_, rayleigh.C_, rayleigh.K_, rs.leftCols(m), rw.head(m), 2, &rw_out).cols() == m);
  REQUIRE(damping_enriched_basis(sys.M_, sys.C_, sys.K_, phi, w, 0, &rw_out).cols() == m);
  REQUIRE_THROWS_AS(damping_enriched_basis(sys.M_, sys.C_, sys.K_, phi, w, -1, &rw_out), InputError);
}
