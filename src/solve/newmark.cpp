#include "viaduct/solve/newmark.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"

namespace viaduct::solve {

namespace {
std::string num(double v) { return format_number(v, 6); }
}  // namespace

NewmarkOptions NewmarkOptions::hht(double alpha, double dt, double t_end) {
  NewmarkOptions o;
  o.alpha = alpha;
  o.beta = (1.0 - alpha) * (1.0 - alpha) / 4.0;
  o.gamma = (1.0 - 2.0 * alpha) / 2.0;
  o.dt = dt;
  o.t_end = t_end;
  return o;
}

bool NewmarkOptions::unconditionally_stable() const {
  return gamma >= 0.5 && 2.0 * beta >= gamma - 1e-14;
}

bool NewmarkOptions::is_valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(std::isfinite(dt) && dt > 0.0)) return fail("dt must be > 0 [s], got " + num(dt));
  if (!(std::isfinite(t_end) && t_end > 0.0)) return fail("t_end must be > 0 [s], got " + num(t_end));
  if (!(std::isfinite(beta) && beta > 0.0)) return fail("beta must be > 0, got " + num(beta));
  if (!(std::isfinite(gamma) && gamma >= 0.5))
    return fail("gamma must be >= 0.5 (gamma < 0.5 adds negative damping), got " + num(gamma));
  if (!(std::isfinite(alpha) && alpha >= -1.0 / 3.0 - 1e-15 && alpha <= 0.0))
    return fail("HHT alpha must be in [-1/3, 0], got " + num(alpha));
  if (t_end / dt > 2e9) return fail("t_end/dt exceeds 2e9 steps");
  return true;
}

double estimate_max_omega(const SparseMatrix& M, const SparseMatrix& K) {
  Eigen::SimplicialLDLT<SparseMatrix> lm(M);
  if (lm.info() != Eigen::Success) throw SolverError("mass matrix is not positive definite");
  Vector x = Vector::Ones(M.rows());
  double lambda = 0.0;
  for (int it = 0; it < 200; ++it) {
    Vector y = lm.solve(K * x);
    const double n = y.norm();
    if (!(n > 0.0)) return 0.0;
    const double next = x.dot(K * x) / x.dot(M * x);
    x = y / n;
    if (it > 10 && std::abs(next - lambda) <= 1e-6 * next) {
      lambda = next;
      break;
    }
    lambda = next;
  }
  lambda = std::max(lambda, x.dot(K * x) / x.dot(M * x));
  return 1.02 * std::sqrt(std::max(lambda, 0.0));
}

NewmarkSummary newmark(const SecondOrderSystem& sys, const NewmarkOptions& opt,
                       const StepObserver& observe, const Vector* u0, const Vector* v0) {
  const auto wall0 = std::chrono::steady_clock::now();
  std::string why;
  if (!opt.is_valid(&why)) throw InputError("Newmark: " + why);
  const SparseMatrix& M = sys.mass();
  const SparseMatrix& C = sys.damping();
  const SparseMatrix& K = sys.stiffness();
  const Index n = M.rows();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n)
    throw InputError("Newmark: M, C and K must be square and of one size");
  const double dt = opt.dt, b = opt.beta, g = opt.gamma, al = opt.alpha;

  if (!opt.unconditionally_stable()) {
    // Conditionally stable (e.g. linear acceleration): undamped limit Ω = ω dt <= 1/sqrt(γ/2 - β).
    const double w_max = estimate_max_omega(M, K);
    const double limit = 1.0 / std::sqrt(g / 2.0 - b);
    if (w_max * dt > limit)
      throw SolverError("Newmark with beta = " + num(b) + ", gamma = " + num(g) +
                        " is only conditionally stable: needs dt <= " + num(limit / w_max) +
                        " s for the highest frequency " + num(w_max / (2 * M_PI)) +
                        " Hz, got dt = " + num(dt) + " s");
  }

  // Effective matrix S = M + (1+α)γ dt C + (1+α)β dt² K, factored once.
  const SparseMatrix S = M + ((1.0 + al) * g * dt) * C + ((1.0 + al) * b * dt * dt) * K;
  Eigen::SimplicialLDLT<SparseMatrix> ls(S);
  if (ls.info() != Eigen::Success)
    throw SolverError("Newmark: effective matrix is not positive definite (negative mass or stiffness?)");

  Vector u = u0 ? *u0 : Vector::Zero(n);
  Vector v = v0 ? *v0 : Vector::Zero(n);
  if (u.size() != n || v.size() != n) throw InputError("Newmark: initial state has the wrong size");
  Vector a(n), f(n), f_prev(n), rhs(n), ut(n), vt(n), w1(n), w2(n);
  f.setZero();
  sys.force(0.0, f);
  {
    Eigen::SimplicialLDLT<SparseMatrix> lm(M);
    if (lm.info() != Eigen::Success) throw SolverError("Newmark: mass matrix is not positive definite");
    rhs = f - C * v - K * u;
    a = lm.solve(rhs);
  }
  const Index n_steps = static_cast<Index>(std::ceil(opt.t_end / dt - 1e-9));
  if (observe) observe(0, 0.0, u, v, a);

  for (Index k = 1; k <= n_steps; ++k) {
    const double t = k * dt;
    f_prev.swap(f);
    sys.force(t, f);
    // Predictors.
    ut = u + dt * v + (dt * dt * (0.5 - b)) * a;
    vt = v + (dt * (1.0 - g)) * a;
    // rhs = (1+α) f_{n+1} - α f_n - C((1+α) ṽ - α v_n) - K((1+α) ũ - α u_n)
    if (al == 0.0) {
      rhs.noalias() = f;
      rhs.noalias() -= C * vt;
      rhs.noalias() -= K * ut;
    } else {
      w1 = (1.0 + al) * vt - al * v;
      w2 = (1.0 + al) * ut - al * u;
      rhs = (1.0 + al) * f - al * f_prev;
      rhs.noalias() -= C * w1;
      rhs.noalias() -= K * w2;
    }
    a = ls.solve(rhs);
    u = ut + (dt * dt * b) * a;
    v = vt + (dt * g) * a;
    if (opt.check_finite && !u.allFinite())
      throw SolverError("Newmark: state became non-finite at t = " + num(t) + " s");
    if (observe) observe(k, t, u, v, a);
  }
  NewmarkSummary s;
  s.n_steps = n_steps;
  s.n_dofs = n;
  s.t_reached = n_steps * dt;
  s.stop_reason = "t_end reached";
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return s;
}

}  // namespace viaduct::solve
