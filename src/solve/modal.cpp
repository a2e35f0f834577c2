#include "viaduct/solve/modal.hpp"

#include <chrono>
#include <cmath>

#include <Eigen/SparseCholesky>
#include <unsupported/Eigen/MatrixFunctions>

#include "viaduct/core/error.hpp"

namespace viaduct::solve {

namespace {
std::string num(double v) { return format_number(v, 6); }
}  // namespace

bool ModalOptions::is_valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(std::isfinite(dt) && dt > 0.0)) return fail("dt must be > 0 [s], got " + num(dt));
  if (!(std::isfinite(t_end) && t_end > 0.0)) return fail("t_end must be > 0 [s], got " + num(t_end));
  if (t_end / dt > 2e9) return fail("t_end/dt exceeds 2e9 steps");
  return true;
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
    : static_correction_(static_correction) {
  const Index n = M.rows(), m = shapes.cols();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n)
    throw InputError("modal reduction: M, C and K must be square and of one size");
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
  phi_rows_ = phi;
  omega_ = omega;
  const Matrix Cm = phi.transpose() * (C * phi);
  zeta_.resize(m);
  for (Index i = 0; i < m; ++i) zeta_[i] = std::max(Cm(i, i), 0.0) / (2.0 * omega[i]);
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < m; ++j)
      if (i != j && Cm(i, i) > 0.0 && Cm(j, j) > 0.0)
        max_coupling_ = std::max(max_coupling_, std::abs(Cm(i, j)) / std::sqrt(Cm(i, i) * Cm(j, j)));

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
  if (static_correction) {
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
  }
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
  void project(double t, double* p, double* g) override {
    const auto mm = static_cast<std::size_t>(r_.n_modes()), no = static_cast<std::size_t>(r_.n_outputs());
    std::fill(p, p + mm, 0.0);
    if (g) std::fill(g, g + no, 0.0);
    const double* phi = r_.shape_rows().data();
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
      Eigen::Map<Vector>(p, r_.n_modes()).noalias() = r_.shape_rows().transpose() * f_;
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

ModalSummary ModalReduction::integrate(const SecondOrderSystem& sys, const ModalOptions& opt,
                                       const OutputObserver& observe) const {
  if (sys.n_dofs() != n_dofs()) throw InputError("modal superposition: the system does not match the reduction");
  SystemForce force(sys, *this);
  return integrate(force, opt, observe);
}

ModalSummary ModalReduction::integrate(ModalForce& force, const ModalOptions& opt,
                                       const OutputObserver& observe) const {
  const auto wall0 = std::chrono::steady_clock::now();
  std::string why;
  if (!opt.is_valid(&why)) throw InputError("modal superposition: " + why);
  const Index n = n_dofs(), m = n_modes(), n_out = out_shape_.rows();
  const double dt = opt.dt;

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

  std::vector<double> q(mm, 0.0), qd(mm, 0.0), qdd(mm, 0.0), p(mm, 0.0), p_prev(mm, 0.0);
  Vector disp(n_out), acc(n_out), flex_f = Vector::Zero(n_out);
  const bool flex = static_correction_;
  const double* S = out_rows_.data();          // row-major n_out × m
  const double* Ss = out_static_rows_.data();  // row-major n_out × m
  auto load = [&](double t) { force.project(t, p.data(), flex ? flex_f.data() : nullptr); };
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
      disp[static_cast<Index>(j)] = dj;
      acc[static_cast<Index>(j)] = aj;
    }
    if (observe) observe(k, t, disp, acc);
  };

  load(0.0);
  qdd = p;  // from rest
  emit(0, 0.0);
  const Index n_steps = static_cast<Index>(std::ceil(opt.t_end / dt - 1e-9));
  for (Index k = 1; k <= n_steps; ++k) {
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
      throw SolverError("modal superposition: state became non-finite at t = " + num(t) + " s");
    emit(k, t);
  }
  ModalSummary s;
  s.n_steps = n_steps;
  s.n_modes = m;
  s.n_dofs = n;
  s.t_reached = n_steps * dt;
  s.stop_reason = "t_end reached";
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return s;
}

}  // namespace viaduct::solve
