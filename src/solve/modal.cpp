#include "viaduct/solve/modal.hpp"

#include <chrono>
#include <complex>
#include <cmath>

#include "viaduct/core/eigensolvers.hpp"
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <unsupported/Eigen/MatrixFunctions>

#include "checks.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve {

namespace {
std::string modal_num(double v) { return format_number(v, 6); }
}  // namespace

bool ModalOptions::is_valid(std::string* why) const {
  (void)why;  // every value of check_finite is valid
  return true;
}

Matrix ModalReduction::static_channel_weights() const {
  if (!complex_) return out_static_;
  Matrix w = Matrix::Zero(out_shape_.rows(), n_channels());
  for (Index j = 0; j < w.rows(); ++j)
    for (Index k = 0; k < lambda_.size(); ++k) {
      const std::complex<double> st = weight_[k] * c_static_(j, k);
      const Index c = channel_[static_cast<std::size_t>(k)];
      w(j, c) += st.real();
      if (weight_[k] == 2.0) w(j, c + 1) -= st.imag();
    }
  return w;
}

ModalReduction::ComplexForm ModalReduction::complex_form() const {
  ComplexForm f;
  if (!complex_) throw InputError("modal reduction: complex_form() of classical modes");
  const Index nk = lambda_.size();
  f.disp.resize(out_shape_.rows(), nk);
  f.acc.resize(out_shape_.rows(), nk);
  for (Index k = 0; k < nk; ++k) {
    f.lambda.push_back(lambda_[k]);
    f.channel.push_back(channel_[static_cast<std::size_t>(k)]);
    f.pair.push_back(weight_[k] == 2.0);
    f.disp.col(k) = weight_[k] * c_disp_.col(k);
    f.acc.col(k) = weight_[k] * c_acc_.col(k);
  }
  return f;
}

Matrix damping_enriched_basis(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                              const Matrix& shapes, const Vector& omega, int blocks, Vector* omega_out,
                              double max_omega) {
  const Index n = M.rows(), m = shapes.cols();
  if (blocks < 0) throw InputError("damping enrichment: blocks must be >= 0");
  if (shapes.rows() != n || omega.size() != m) throw InputError("damping enrichment: shapes and omega do not match");
  if (omega_out) *omega_out = omega;
  if (blocks == 0 || m == 0 || m >= n) return shapes;  // every mode kept: R = 0
  Eigen::SimplicialLDLT<SparseMatrix> kf(K);
  if (kf.info() != Eigen::Success) throw SolverError("damping enrichment: the stiffness matrix cannot be factored");
  const Vector om2inv = omega.cwiseAbs2().cwiseInverse();  // R x = K⁻¹ x − Φ Ω⁻² Φᵀ x
  // The enrichment seeded by the n_seed lowest modes: shapes, ω, and the highest Ritz ω.
  struct Built {
    Matrix shapes;
    Vector omega;
    double top = 0.0;
  };
  auto build = [&](Index n_seed) {
    Built r{shapes, omega, 0.0};
    Matrix basis = shapes;  // M-orthonormal columns
    Matrix block = shapes.leftCols(n_seed);
    for (int b = 0; b < blocks && block.cols() > 0; ++b) {
      const Matrix cb = C * block;
      const Matrix full = kf.solve(cb);  // K⁻¹ C b: the scale against which R C b is judged
      Matrix rcb = full;
      rcb.noalias() -= shapes * (om2inv.asDiagonal() * (shapes.transpose() * cb));
      Matrix kept(n, 0);
      for (Index j = 0; j < rcb.cols(); ++j) {
        const double scale = std::sqrt(std::max(full.col(j).dot(M * full.col(j)), 0.0));
        if (!(scale > 0.0)) continue;
        Vector v = rcb.col(j);
        // two passes of M-orthogonal Gram–Schmidt against everything kept so far
        for (int pass = 0; pass < 2; ++pass) {
          const Vector mv = M * v;
          v.noalias() -= basis * (basis.transpose() * mv);
          if (kept.cols() > 0) v.noalias() -= kept * (kept.transpose() * mv);
        }
        // Classical damping leaves rounding only (C φ ∝ M φ, so R C φ = 0): dropped here.
        const double norm = std::sqrt(std::max(v.dot(M * v), 0.0));
        if (!(norm > 1e-8 * scale)) continue;
        kept.conservativeResize(n, kept.cols() + 1);
        kept.col(kept.cols() - 1) = v / norm;
      }
      if (kept.cols() == 0) break;
      Matrix grown(n, basis.cols() + kept.cols());
      grown << basis, kept;
      basis.swap(grown);
      block = kept;
    }
    if (basis.cols() == m) return r;
    // Rayleigh–Ritz on the enrichment: Φ is K-orthogonal to it, so only its block needs solving.
    const Matrix E = basis.rightCols(basis.cols() - m);
    Matrix Kr = E.transpose() * (K * E);
    Kr = 0.5 * (Kr + Kr.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Matrix> es(Kr);
    if (es.info() != Eigen::Success) throw SolverError("damping enrichment: the Ritz eigenproblem failed");
    const Vector lam = es.eigenvalues();
    if (!(lam.minCoeff() > 0.0)) throw SolverError("damping enrichment: a Ritz vector has no stiffness");
    r.shapes.resize(n, basis.cols());
    r.shapes.leftCols(m) = shapes;
    r.shapes.rightCols(E.cols()) = E * es.eigenvectors();
    r.omega.resize(basis.cols());
    r.omega.head(m) = omega;
    r.omega.tail(E.cols()) = lam.cwiseSqrt();
    r.top = r.omega.tail(E.cols()).maxCoeff();
    return r;
  };
  Built best = build(m);
  if (max_omega > 0.0 && best.top > max_omega) {
    // Fewer seeds span a subspace, so the highest Ritz ω can only fall (Cauchy interlacing):
    // bisect for the most seeds whose Ritz pairs all stay at or below max_omega.
    Index lo = 0, hi = m;  // build(lo) fits (no seed: nothing added), build(hi) does not
    best = build(0);
    while (hi - lo > 1) {
      const Index mid = (lo + hi) / 2;
      Built t = build(mid);
      if (t.top <= max_omega) {
        lo = mid;
        best = std::move(t);
      } else {
        hi = mid;
      }
    }
  }
  if (omega_out) *omega_out = best.omega;
  return best.shapes;
}

std::array<std::complex<double>, 3> complex_step_coefficients(std::complex<double> lambda, double dt) {
  // α = I₁ − I₂, β = I₂ with I₁ = (E − 1)/λ and I₂ = (E − 1 − λh)/(λ² h) (series for small |λh|).
  using cd = std::complex<double>;
  const cd z = lambda * dt, e = std::exp(z);
  cd I1, I2;
  if (std::abs(z) < 1e-3) {
    I1 = dt * (1.0 + z / 2.0 + z * z / 6.0 + z * z * z / 24.0);
    I2 = dt * (0.5 + z / 6.0 + z * z / 24.0 + z * z * z / 120.0);
  } else {
    I1 = (e - 1.0) / lambda;
    I2 = (e - 1.0 - z) / (lambda * z);
  }
  return {e, I1 - I2, I2};
}

std::array<double, 8> exact_step_coefficients(double omega, double zeta, double dt) {
  // z = [q, q̇, p, ṗ]: ż = F z with ṗ constant over the step; z₁ = exp(F dt) z₀.
  Eigen::Matrix4d F = Eigen::Matrix4d::Zero();
  F(0, 1) = 1.0;
  F(1, 0) = -omega * omega;
  F(1, 1) = -2.0 * zeta * omega;
  F(1, 2) = 1.0;
  F(2, 3) = 1.0;
  const Eigen::Matrix4d E = (F * dt).exp();
  // ṗ = (p₁ - p₀)/dt.
  return {E(0, 0), E(0, 1), E(0, 2) - E(0, 3) / dt, E(0, 3) / dt,
          E(1, 0), E(1, 1), E(1, 2) - E(1, 3) / dt, E(1, 3) / dt};
}

ModalReduction::ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                               const Matrix& shapes, const Vector& omega,
                               const std::vector<Functional>& outputs, bool static_correction)
    : ModalReduction(M, C, K, shapes, omega, outputs, static_correction, nullptr) {}

ModalReduction::ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                               const Matrix& shapes, const Vector& omega,
                               const std::vector<Functional>& outputs, bool static_correction,
                               const std::vector<Index>& contact_dofs)
    : ModalReduction(M, C, K, shapes, omega, outputs, static_correction, &contact_dofs) {}

ModalReduction::ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                               const Matrix& shapes, const Vector& omega,
                               const std::vector<Functional>& outputs, bool static_correction,
                               const std::vector<Index>* contact_dofs)
    : static_correction_(static_correction) {
  const Index n = detail::require_square_system(M, C, K, "modal reduction"), m = shapes.cols();
  n_dofs_ = n;
  if (shapes.rows() != n) throw InputError("modal reduction: mode shapes have the wrong number of rows");
  if (m < 1) throw InputError("modal reduction: at least one mode is needed");
  if (omega.size() != m) throw InputError("modal reduction: one frequency per mode is needed");
  if (!shapes.allFinite() || !omega.allFinite())
    throw InputError("modal reduction: non-finite mode shape or frequency");
  for (Index i = 0; i < m; ++i)
    if (!(omega[i] > 0.0))
      throw InputError("modal reduction: mode " + std::to_string(i + 1) +
                       " has zero frequency (a mechanism: add supports or bearings)");

  Matrix phi = shapes;
  for (Index i = 0; i < m; ++i) {
    const double mi = phi.col(i).dot(M * phi.col(i));
    if (!(mi > 0.0)) throw InputError("modal reduction: mode " + std::to_string(i + 1) + " has no mass");
    phi.col(i) /= std::sqrt(mi);
  }
  omega_ = omega;
  const Matrix Cm = phi.transpose() * (C * phi);
  zeta_.resize(m);
  for (Index i = 0; i < m; ++i) zeta_[i] = std::max(Cm(i, i), 0.0) / (2.0 * omega[i]);
  double max_off = 0.0, max_diag = 0.0;
  for (Index i = 0; i < m; ++i) {
    max_diag = std::max(max_diag, std::abs(Cm(i, i)));
    for (Index j = 0; j < m; ++j) {
      if (i == j) continue;
      max_off = std::max(max_off, std::abs(Cm(i, j)));
      if (Cm(i, i) > 0.0 && Cm(j, j) > 0.0)
        max_coupling_ = std::max(max_coupling_, std::abs(Cm(i, j)) / std::sqrt(Cm(i, i) * Cm(j, j)));
    }
  }
  // Off-diagonal terms above rounding of the projection: integrate complex modes.
  complex_ = max_off > 1e-10 * std::max(max_diag, 1e-300);

  const Index n_out = static_cast<Index>(outputs.size());
  out_shape_ = Matrix::Zero(n_out, m);
  for (Index j = 0; j < n_out; ++j) {
    const Functional& fn = outputs[j];
    if (fn.dof.size() != fn.weight.size()) throw InputError("modal reduction: output with mismatched dofs and weights");
    for (std::size_t k = 0; k < fn.dof.size(); ++k) {
      if (fn.dof[k] < 0 || fn.dof[k] >= n) throw InputError("modal reduction: output DOF out of range");
      out_shape_.row(j) += fn.weight[k] * phi.row(fn.dof[k]);
    }
  }
  out_static_ = out_shape_ * omega.cwiseAbs2().cwiseInverse().asDiagonal();
  out_rows_ = out_shape_;
  out_static_rows_ = out_static_;
  if (contact_dofs) {  // the coupled kernels integrate Φᵀ C Φ as it is: no load channels
    coupled_ = true;
    complex_ = false;
    contact_slot_.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t i = 0; i < contact_dofs->size(); ++i) {
      const Index d = (*contact_dofs)[i];
      if (d < 0 || d >= n) throw InputError("modal reduction: contact DOF out of range");
      if (contact_slot_[static_cast<std::size_t>(d)] >= 0) throw InputError("modal reduction: contact DOF given twice");
      contact_slot_[static_cast<std::size_t>(d)] = static_cast<Index>(i);
    }
    CoupledMatrices& cm = coupled_matrices_;
    cm.M.resize(m, m);
    cm.M.setIdentity();
    std::vector<Eigen::Triplet<double>> kt;
    for (Index j = 0; j < m; ++j) kt.emplace_back(j, j, omega[j] * omega[j]);
    cm.K.resize(m, m);
    cm.K.setFromTriplets(kt.begin(), kt.end());
    cm.C = (0.5 * (Cm + Cm.transpose())).sparseView(0.0, 0.0);  // symmetric to rounding
  } else if (!complex_) {
    load_rows_ = phi;
  } else {
    build_complex_basis(phi, Cm, omega);
  }
  shapes_ = std::move(phi);
  if (static_correction) build_static_correction(K, outputs, contact_dofs);
}

namespace {
// On a few fixed pseudo-random probes x (matrix-vector products: the check costs O(n²) beside
// the O(n³) decomposition): A'V'x = V'Λx and V'⁻¹V'x = x. SolverError when either fails.
void check_complex_basis(const Matrix& A, const Eigen::MatrixXcd& V, const Eigen::MatrixXcd& Vinv, const Eigen::VectorXcd& lam_v) {
  const Index n2 = A.rows();
  const Eigen::MatrixXcd Ac = A.cast<std::complex<double>>();
  double r_eig = 0.0, r_inv = 0.0;
  for (int probe = 0; probe < 3; ++probe) {
    Eigen::VectorXcd x(n2);
    for (Index i = 0; i < n2; ++i) x[i] = std::complex<double>(std::cos(0.7 * i + probe), std::sin(1.3 * i * (probe + 1)));
    const Eigen::VectorXcd Vx = V * x;
    r_eig = std::max(r_eig, (Ac * Vx - V * (lam_v.asDiagonal() * x)).norm() / (Ac.norm() * Vx.norm()));
    r_inv = std::max(r_inv, (Vinv * Vx - x).norm() / x.norm());
  }
  if (!(r_eig < 1e-8 && r_inv < 1e-6))
    throw SolverError("modal reduction: the complex modes are not accurate (eigen-residual " + modal_num(r_eig) +
                      ", inverse residual " + modal_num(r_inv) + "): the damping makes the basis ill-conditioned; "
                      "lower modal.max_frequency_hz or modal.n_modes");
}
}  // namespace

void ModalReduction::build_complex_basis(const Matrix& phi, const Matrix& Cm, const Vector& omega) {
  const Index n = phi.rows(), m = phi.cols();
  // ẋ = A x + B p with x = [q; q̇], A = [0 I; -Ω² -Cm], B = [0; I]; A = V Λ V⁻¹, y = V⁻¹ x.
  // Solved in the scaled state x' = [Ω q; q̇] (A' = [0 Ω; −Ω −Cm] = D A D⁻¹, D = diag(Ω, I)):
  // with frequencies from 10 Hz to tens of kHz the unscaled A spans ω² over ten decades and
  // its eigenvectors come out inaccurate; A' has entries of size ω. Then V = D⁻¹ V'.
  Matrix A = Matrix::Zero(2 * m, 2 * m);
  A.topRightCorner(m, m) = omega.asDiagonal();
  A.bottomLeftCorner(m, m) = -Matrix(omega.asDiagonal());
  A.bottomRightCorner(m, m) = -Cm;
  Eigen::EigenSolver<Matrix> es(A);
  if (es.info() != Eigen::Success) throw SolverError("modal reduction: the complex eigenproblem failed");
  const CVector lam = es.eigenvalues();
  const CMatrix vec = es.eigenvectors();
  // Keep one coordinate per conjugate pair (Im λ > 0) and every real one; rebuild V with exact
  // conjugate partners so that the dropped coordinates are exactly the conjugates of the kept.
  const double scale = lam.cwiseAbs().maxCoeff();
  std::vector<Index> kept;
  for (Index k = 0; k < 2 * m; ++k)
    if (lam[k].imag() >= -1e-12 * scale) {
      if (std::abs(lam[k].imag()) <= 1e-12 * scale || lam[k].imag() > 0) kept.push_back(k);
    }
  CMatrix V(2 * m, 2 * m);
  Index col = 0;
  std::vector<bool> is_pair;
  for (Index k : kept) {
    const bool pair = lam[k].imag() > 1e-12 * scale;
    is_pair.push_back(pair);
    if (pair) {
      V.col(col++) = vec.col(k);
      V.col(col++) = vec.col(k).conjugate();
    } else {
      V.col(col++) = vec.col(k).real().cast<std::complex<double>>();
    }
  }
  if (col != 2 * m)
    throw SolverError("modal reduction: the damped eigenvalues do not come in conjugate pairs (defective system?)");
  Eigen::PartialPivLU<CMatrix> lu(V);
  const CMatrix Vinv = lu.inverse();
  if (!Vinv.allFinite()) throw SolverError("modal reduction: complex mode basis is singular");
  // A wrong decomposition must not pass for a result: check A' V' = V' Λ and V'⁻¹ V' = I.
  {
    CVector lam_v(2 * m);
    Index c = 0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      lam_v[c++] = lam[kept[k]];
      if (is_pair[k]) lam_v[c++] = std::conj(lam[kept[k]]);
    }
    check_complex_basis(A, V, Vinv, lam_v);
  }
  const auto nk = static_cast<Index>(kept.size());
  lambda_.resize(nk);
  weight_.resize(nk);
  channel_.assign(static_cast<std::size_t>(nk), 0);
  // Columns of V / rows of V⁻¹ for each kept coordinate.
  CMatrix Vk(2 * m, nk), Gk(nk, m);
  Index n_ch = 0;
  col = 0;
  for (Index k = 0; k < nk; ++k) {
    const Index src = kept[static_cast<std::size_t>(k)];
    lambda_[k] = is_pair[static_cast<std::size_t>(k)] ? lam[src] : std::complex<double>(lam[src].real(), 0.0);
    weight_[k] = is_pair[static_cast<std::size_t>(k)] ? 2.0 : 1.0;
    Vk.col(k) = V.col(col);
    Gk.row(k) = Vinv.row(col).tail(m);  // V⁻¹ B: the rows' q̇ part
    channel_[static_cast<std::size_t>(k)] = n_ch;
    n_ch += is_pair[static_cast<std::size_t>(k)] ? 2 : 1;
    col += is_pair[static_cast<std::size_t>(k)] ? 2 : 1;
  }
  // Load channels: u_k = G_k Φᵀ f = (Φ G_kᵀ)ᵀ f, split into real and imaginary parts.
  const CMatrix psi = phi.cast<std::complex<double>>() * Gk.transpose();  // n × nk
  Matrix L(n, n_ch);
  for (Index k = 0; k < nk; ++k) {
    const Index c = channel_[static_cast<std::size_t>(k)];
    L.col(c) = psi.col(k).real();
    if (weight_[k] == 2.0) L.col(c + 1) = psi.col(k).imag();
  }
  load_rows_ = L;
  const CMatrix S = out_shape_.cast<std::complex<double>>();
  const CMatrix Vtop = omega.cwiseInverse().asDiagonal() * Vk.topRows(m), Vbot = Vk.bottomRows(m);  // V = D⁻¹ V'
  c_disp_ = S * Vtop;  // q = V_top y
  c_acc_ = S * Vbot;   // q̈ = V_bot ẏ = V_bot (Λ y + u)
  c_static_ = out_static_.cast<std::complex<double>>() * Vbot;  // p = V_bot u (all coordinates)
}

namespace {
// R = K⁻¹ − Φ Ω⁻² Φᵀ between `dofs` (rows and columns), a block of columns at a time (lk: K factored).
Matrix contact_flexibility(const Eigen::SimplicialLDLT<SparseMatrix>& lk, const Matrix& phi, const Vector& omega,
                           const std::vector<Index>& dofs) {
  const Index n = phi.rows(), np = static_cast<Index>(dofs.size());
  const Matrix flex = phi * omega.cwiseInverse().cwiseAbs2().asDiagonal();  // Φ Ω⁻²
  Matrix R(np, np);
  constexpr Index kBlock = 256;
  for (Index c0 = 0; c0 < np; c0 += kBlock) {
    const Index nc = std::min(kBlock, np - c0);
    Matrix E = Matrix::Zero(n, nc), phi_c(nc, phi.cols());
    for (Index j = 0; j < nc; ++j) {
      E(dofs[static_cast<std::size_t>(c0 + j)], j) = 1.0;
      phi_c.row(j) = phi.row(dofs[static_cast<std::size_t>(c0 + j)]);
    }
    Matrix X = lk.solve(E);
    if (lk.info() != Eigen::Success || !X.allFinite())
      throw SolverError("static correction: K is singular (is the structure supported?)");
    X.noalias() -= flex * phi_c.transpose();
    for (Index i = 0; i < np; ++i) R.block(i, c0, 1, nc) = X.row(dofs[static_cast<std::size_t>(i)]);
  }
  return 0.5 * (R + R.transpose());  // symmetric to rounding
}
}  // namespace

void ModalReduction::build_static_correction(const SparseMatrix& K, const std::vector<Functional>& outputs,
                                             const std::vector<Index>* contact_dofs) {
  const Index n = K.rows(), n_out = static_cast<Index>(outputs.size());
  Eigen::SimplicialLDLT<SparseMatrix> lk(K);
  if (lk.info() != Eigen::Success)
    throw SolverError("static correction: K cannot be factored (is the structure supported?)");
  Matrix out_flex = Matrix::Zero(n, n_out);
  for (Index j = 0; j < n_out; ++j) {
    Vector c = Vector::Zero(n);
    for (std::size_t k = 0; k < outputs[j].dof.size(); ++k) c[outputs[j].dof[k]] += outputs[j].weight[k];
    out_flex.col(j) = lk.solve(c);
    if (lk.info() != Eigen::Success || !out_flex.col(j).allFinite())
      throw SolverError("static correction: K is singular (is the structure supported?)");
  }
  out_flex_rows_ = out_flex;
  if (!contact_dofs) return;
  // The coupled kernels' share: the wheels' forces through the dropped modes, between the contact
  // DOFs and from them to the outputs (the rows of K⁻¹ cⱼ above less the kept modes' S Ω⁻²).
  const std::vector<Index>& dofs = *contact_dofs;  // checked by the constructor (contact_slot_)
  contact_residual_ = contact_flexibility(lk, shapes_, omega_, dofs);
  contact_output_residual_.resize(static_cast<Index>(dofs.size()), n_out);
  for (std::size_t i = 0; i < dofs.size(); ++i)
    contact_output_residual_.row(static_cast<Index>(i)) =
        out_flex.row(dofs[i]) - shapes_.row(dofs[i]) * out_static_.transpose();
}

namespace {
// Projects a SecondOrderSystem's nodal loads (sparse entries when offered, else dense).
class SystemForce : public ModalForce {
 public:
  SystemForce(const SecondOrderSystem& sys, const ModalReduction& r) : sys_(sys), r_(r) {
    entries_.dof.reserve(64);
    entries_.value.reserve(64);
    sparse_ = sys.force_entries(0.0, entries_);
    if (!sparse_) f_ = Vector::Zero(sys.n_dofs());
  }
  void project(double t, double* p, double* g, double*, double*) override {
    const auto mm = static_cast<std::size_t>(r_.n_channels()), no = static_cast<std::size_t>(r_.n_outputs());
    std::fill(p, p + mm, 0.0);
    if (g) std::fill(g, g + no, 0.0);
    const double* phi = r_.load_rows().data();
    const double* flex = r_.flexibility_rows().data();
    if (sparse_) {
      sys_.force_entries(t, entries_);
      for (std::size_t k = 0; k < entries_.dof.size(); ++k) {
        const auto d = static_cast<std::size_t>(entries_.dof[k]);
        const double v = entries_.value[k];
        const double* row = phi + d * mm;
        for (std::size_t i = 0; i < mm; ++i) p[i] += v * row[i];
        if (g) {
          const double* fr = flex + d * no;
          for (std::size_t j = 0; j < no; ++j) g[j] += v * fr[j];
        }
      }
    } else {
      f_.setZero();
      sys_.force(t, f_);
      Eigen::Map<Vector>(p, r_.n_channels()).noalias() = r_.load_rows().transpose() * f_;
      if (g) Eigen::Map<Vector>(g, r_.n_outputs()).noalias() = r_.flexibility_rows().transpose() * f_;
    }
  }

 private:
  const SecondOrderSystem& sys_;
  const ModalReduction& r_;
  SparseForce entries_;
  Vector f_;
  bool sparse_ = false;
};
}  // namespace

Summary ModalReduction::integrate(const SecondOrderSystem& sys, const TimeGrid& grid, const ModalOptions& opt,
                                  const OutputObserver& observe) const {
  if (sys.n_dofs() != n_dofs()) throw InputError("modal superposition: the system does not match the reduction");
  SystemForce force(sys, *this);
  return integrate(force, grid, opt, observe);
}

Summary ModalReduction::integrate(ModalForce& force, const TimeGrid& grid, const ModalOptions& opt,
                                  const OutputObserver& observe) const {
  require_valid(grid, "modal superposition");
  require_valid(opt, "modal superposition");
  if (coupled_)
    throw InputError("modal superposition: this reduction was built for the coupled vehicle kernels (it has no load channels)");
  if (complex_) return integrate_complex(force, grid, opt, observe);
  const auto wall0 = std::chrono::steady_clock::now();
  const Index n = n_dofs(), m = n_modes(), n_out = out_shape_.rows();
  const double dt = grid.dt;

  // Per-mode step coefficients. The loop below is written with raw arrays: with a handful of
  // modes, Eigen's per-expression overhead would dominate the step.
  std::vector<double> c8(static_cast<std::size_t>(8 * m));
  for (Index i = 0; i < m; ++i) {
    const auto c = exact_step_coefficients(omega_[i], zeta_[i], dt);
    for (std::size_t k = 0; k < 8; ++k) c8[static_cast<std::size_t>(8 * i) + k] = c[k];
  }
  const auto mm = static_cast<std::size_t>(m), no = static_cast<std::size_t>(n_out);
  std::vector<double> two_zw(mm), w2(mm);
  for (std::size_t i = 0; i < mm; ++i) {
    two_zw[i] = 2.0 * zeta_[static_cast<Index>(i)] * omega_[static_cast<Index>(i)];
    w2[i] = omega_[static_cast<Index>(i)] * omega_[static_cast<Index>(i)];
  }

  std::vector<double> q(mm, 0.0), qd(mm, 0.0), qdd(mm, 0.0), p(mm, 0.0), p_prev(mm, 0.0), p2(mm, 0.0);
  Vector disp(n_out), acc(n_out), flex_f = Vector::Zero(n_out), flex_f2 = Vector::Zero(n_out);
  const bool flex = static_correction_, flex2 = flex && force.has_second_derivative();
  const double* S = out_rows_.data();          // row-major n_out × m
  const double* Ss = out_static_rows_.data();  // row-major n_out × m
  auto load = [&](double t) {
    force.project(t, p.data(), flex ? flex_f.data() : nullptr, flex2 ? p2.data() : nullptr,
                  flex2 ? flex_f2.data() : nullptr);
  };
  auto emit = [&](Index k, double t) {
    for (std::size_t j = 0; j < no; ++j) {
      const double* sj = S + j * mm;
      double dj = 0.0, aj = 0.0;
      for (std::size_t i = 0; i < mm; ++i) {
        dj += sj[i] * q[i];
        aj += sj[i] * qdd[i];
      }
      if (flex) {
        const double* ssj = Ss + j * mm;
        dj += flex_f[static_cast<Index>(j)];
        for (std::size_t i = 0; i < mm; ++i) dj -= ssj[i] * p[i];
      }
      if (flex2) {
        const double* ssj = Ss + j * mm;
        aj += flex_f2[static_cast<Index>(j)];
        for (std::size_t i = 0; i < mm; ++i) aj -= ssj[i] * p2[i];
      }
      disp[static_cast<Index>(j)] = dj;
      acc[static_cast<Index>(j)] = aj;
    }
    if (observe) observe(k, t, disp, acc);
  };

  load(0.0);
  qdd = p;  // from rest
  emit(0, 0.0);
  const Index n_steps = grid.n_steps();
  for (Index k = 1; k <= n_steps; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
    const double t = k * dt;
    p_prev.swap(p);
    load(t);
    double sum = 0.0;
    for (std::size_t i = 0; i < mm; ++i) {
      const double* c = &c8[8 * i];
      const double qi = q[i], qdi = qd[i];
      q[i] = c[0] * qi + c[1] * qdi + c[2] * p_prev[i] + c[3] * p[i];
      qd[i] = c[4] * qi + c[5] * qdi + c[6] * p_prev[i] + c[7] * p[i];
      qdd[i] = p[i] - two_zw[i] * qd[i] - w2[i] * q[i];
      sum += q[i];
    }
    if (opt.check_finite && !std::isfinite(sum))
      throw SolverError("modal superposition: state became non-finite at t = " + modal_num(t) + " s");
    emit(k, t);
  }
  return detail::fixed_step_summary(Kernel::modal, n_steps, dt, n, m, 0, detail::seconds_since(wall0));
}

Summary ModalReduction::integrate_complex(ModalForce& force, const TimeGrid& grid, const ModalOptions& opt,
                                          const OutputObserver& observe) const {
  using cd = std::complex<double>;
  const auto wall0 = std::chrono::steady_clock::now();
  const Index n_out = out_shape_.rows(), nk = lambda_.size(), n_ch = n_channels();
  const auto nkk = static_cast<std::size_t>(nk), no = static_cast<std::size_t>(n_out);
  const double h = grid.dt;
  // y₁ = E y₀ + α u₀ + β u₁ for u linear over the step.
  std::vector<cd> E(nkk), al(nkk), be(nkk), lam(nkk);
  for (std::size_t k = 0; k < nkk; ++k) {
    lam[k] = lambda_[static_cast<Index>(k)];
    const auto eab = complex_step_coefficients(lam[k], h);
    E[k] = eab[0], al[k] = eab[1], be[k] = eab[2];
  }
  // Real arithmetic on split real/imaginary arrays: std::complex products carry NaN/Inf
  // recovery calls (C99 Annex G) that would dominate this loop.
  std::vector<double> Er(nkk), Ei(nkk), ar(nkk), ai(nkk), br(nkk), bi(nkk);
  for (std::size_t k = 0; k < nkk; ++k) {
    Er[k] = E[k].real(), Ei[k] = E[k].imag();
    ar[k] = al[k].real(), ai[k] = al[k].imag();
    br[k] = be[k].real(), bi[k] = be[k].imag();
  }
  const bool flex = static_correction_;
  std::vector<double> ch(static_cast<std::size_t>(n_ch), 0.0);
  std::vector<double> yr(nkk, 0.0), yi(nkk, 0.0), ur(nkk, 0.0), ui(nkk, 0.0), pr(nkk, 0.0), pi(nkk, 0.0);
  std::vector<double> ch2(static_cast<std::size_t>(n_ch), 0.0), u2r(nkk, 0.0), u2i(nkk, 0.0);
  const bool flex2 = flex && force.has_second_derivative();
  Vector disp(n_out), acc(n_out), flex_f = Vector::Zero(n_out), flex_f2 = Vector::Zero(n_out);
  // Output rows, weighted (2 for a conjugate pair), split: Re(c z) = cr zr - ci zi.
  std::vector<double> Dr(no * nkk), Di(no * nkk), Lr(no * nkk), Li(no * nkk), Ar(no * nkk), Ai(no * nkk),
      Sr(no * nkk), Si(no * nkk);
  for (std::size_t j = 0; j < no; ++j)
    for (std::size_t k = 0; k < nkk; ++k) {
      const double w = weight_[static_cast<Index>(k)];
      const auto jj = static_cast<Index>(j), kk = static_cast<Index>(k);
      const cd d = w * c_disp_(jj, kk), a = w * c_acc_(jj, kk), al_ = a * lam[k], st = w * c_static_(jj, kk);
      const std::size_t o = j * nkk + k;
      Dr[o] = d.real(), Di[o] = d.imag(), Ar[o] = a.real(), Ai[o] = a.imag();
      Lr[o] = al_.real(), Li[o] = al_.imag(), Sr[o] = st.real(), Si[o] = st.imag();
    }
  auto load = [&](double t) {
    force.project(t, ch.data(), flex ? flex_f.data() : nullptr, flex2 ? ch2.data() : nullptr,
                  flex2 ? flex_f2.data() : nullptr);
    for (std::size_t k = 0; k < nkk; ++k) {
      const auto c = static_cast<std::size_t>(channel_[k]);
      const bool pair = weight_[static_cast<Index>(k)] == 2.0;
      ur[k] = ch[c];
      ui[k] = pair ? ch[c + 1] : 0.0;
      if (flex2) {
        u2r[k] = ch2[c];
        u2i[k] = pair ? ch2[c + 1] : 0.0;
      }
    }
  };
  auto emit = [&](Index step, double t) {
    for (std::size_t j = 0; j < no; ++j) {
      const std::size_t o = j * nkk;
      double dj = 0.0, aj = 0.0, sj = 0.0;
      for (std::size_t k = 0; k < nkk; ++k) {
        dj += Dr[o + k] * yr[k] - Di[o + k] * yi[k];
        aj += Lr[o + k] * yr[k] - Li[o + k] * yi[k] + Ar[o + k] * ur[k] - Ai[o + k] * ui[k];
      }
      if (flex)
        for (std::size_t k = 0; k < nkk; ++k) sj += Sr[o + k] * ur[k] - Si[o + k] * ui[k];
      if (flex2) {
        double s2 = 0.0;
        for (std::size_t k = 0; k < nkk; ++k) s2 += Sr[o + k] * u2r[k] - Si[o + k] * u2i[k];
        aj += flex_f2[static_cast<Index>(j)] - s2;
      }
      disp[static_cast<Index>(j)] = flex ? dj + flex_f[static_cast<Index>(j)] - sj : dj;
      acc[static_cast<Index>(j)] = aj;
    }
    if (observe) observe(step, t, disp, acc);
  };
  load(0.0);
  emit(0, 0.0);
  const Index n_steps = grid.n_steps();
  for (Index step = 1; step <= n_steps; ++step) {
    check_cancel(step);  // the Python package's Ctrl-C
    const double t = step * h;
    pr.swap(ur);
    pi.swap(ui);
    load(t);
    double sum = 0.0;
    for (std::size_t k = 0; k < nkk; ++k) {
      const double r = Er[k] * yr[k] - Ei[k] * yi[k] + ar[k] * pr[k] - ai[k] * pi[k] + br[k] * ur[k] - bi[k] * ui[k];
      const double i = Er[k] * yi[k] + Ei[k] * yr[k] + ar[k] * pi[k] + ai[k] * pr[k] + br[k] * ui[k] + bi[k] * ur[k];
      yr[k] = r;
      yi[k] = i;
      sum += r;
    }
    if (opt.check_finite && !std::isfinite(sum))
      throw SolverError("modal superposition: state became non-finite at t = " + modal_num(t) + " s");
    emit(step, t);
  }
  return detail::fixed_step_summary(Kernel::modal_complex, n_steps, h, n_dofs(), n_modes(), 0, detail::seconds_since(wall0));
}

}  // namespace viaduct::solve
