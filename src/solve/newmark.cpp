#include "viaduct/solve/newmark.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "checks.hpp"
#include "lanes.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve {

namespace {
std::string num(double v) { return format_number(v, 6); }
}  // namespace

NewmarkOptions NewmarkOptions::hht(double alpha) {
  NewmarkOptions o;
  o.alpha = alpha;
  o.beta = (1.0 - alpha) * (1.0 - alpha) / 4.0;
  o.gamma = (1.0 - 2.0 * alpha) / 2.0;
  return o;
}

bool NewmarkOptions::unconditionally_stable() const {
  constexpr double tol = 1e-12;  // hht()'s (1 - 2α)/2 and (1 - α)²/4 in floating point
  return alpha >= -1.0 / 3.0 - 1e-15 && alpha <= 0.0 && gamma >= 0.5 - alpha - tol && 2.0 * beta >= gamma - tol;
}

double NewmarkOptions::spectral_radius(double omega_dt, double xi) const {
  // One step of M a₁ + (1+α)(C v₁ + K u₁) − α(C v₀ + K u₀) = 0 with u₁ = u₀ + v₀ + (½ − β) a₀ + β a₁,
  // v₁ = v₀ + (1 − γ) a₀ + γ a₁ in units of dt (v·dt, a·dt²): A x₁ = B x₀, x = (u, v, a).
  const double W = omega_dt, al = alpha;
  Eigen::Matrix3d A, B;
  if (std::isinf(W)) {  // the equation of motion divided by Ω², Ω → ∞: (1+α) u₁ = α u₀
    A.row(0) << 1.0 + al, 0.0, 0.0;
    B.row(0) << al, 0.0, 0.0;
  } else {
    A.row(0) << (1.0 + al) * W * W, (1.0 + al) * 2.0 * xi * W, 1.0;
    B.row(0) << al * W * W, al * 2.0 * xi * W, 0.0;
  }
  A.row(1) << 1.0, 0.0, -beta;
  B.row(1) << 1.0, 1.0, 0.5 - beta;
  A.row(2) << 0.0, 1.0, -gamma;
  B.row(2) << 0.0, 1.0, 1.0 - gamma;
  const Eigen::Matrix3d amp = A.fullPivLu().solve(B);
  return amp.eigenvalues().cwiseAbs().maxCoeff();
}

bool NewmarkOptions::is_valid(std::string* why) const {
  OptionsCheck c("NewmarkOptions", why);
  if (!(c.require(beta > 0.0, "beta", beta, "beta > 0") &&
        c.require(gamma >= 0.5, "gamma", gamma, "gamma >= 0.5 (gamma < 0.5 adds negative damping)") &&
        c.require(alpha >= -1.0 / 3.0 - 1e-15 && alpha <= 0.0, "alpha", alpha, "HHT alpha in [-1/3, 0]")))
    return false;
  if (alpha == 0.0 || unconditionally_stable()) return true;
  // HHT outside its stable set amplifies the highest modes at every step (spectral radius > 1):
  // 1.2e24 m of deflection in a run that exits 0, never a result.
  const std::string hht = " with alpha = " + format_number(alpha, 6) + " (HHT is unstable at every step size otherwise; alpha's own are beta = (1 - alpha)²/4 = " +
                          format_number((1.0 - alpha) * (1.0 - alpha) / 4.0, 6) + ", gamma = (1 - 2 alpha)/2 = " +
                          format_number((1.0 - 2.0 * alpha) / 2.0, 6) + ")";
  if (gamma < 0.5 - alpha - 1e-12) return c.fail("gamma", format_number(gamma, 6), "gamma >= 1/2 - alpha = " + format_number(0.5 - alpha, 6) + hht);
  return c.fail("beta", format_number(beta, 6), "2 beta >= gamma = " + format_number(gamma, 6) + hht);
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

namespace {
// Refuses a conditionally stable scheme beyond its limit, then factors the effective matrix
// S = M + (1+α)γ dt C + (1+α)β dt² K (once per run or batch).
void factor_effective(double dt, const NewmarkOptions& opt, const SparseMatrix& M, const SparseMatrix& C,
                      const SparseMatrix& K, Eigen::SimplicialLDLT<SparseMatrix>& ls) {
  const double b = opt.beta, g = opt.gamma, al = opt.alpha;
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
  const SparseMatrix S = M + ((1.0 + al) * g * dt) * C + ((1.0 + al) * b * dt * dt) * K;
  ls.compute(S);
  if (ls.info() != Eigen::Success)
    throw SolverError("Newmark: effective matrix is not positive definite (negative mass or stiffness?)");
}
}  // namespace

Summary newmark(const SecondOrderSystem& sys, const TimeGrid& grid, const NewmarkOptions& opt,
                const StepObserver& observe, const Vector* u0, const Vector* v0) {
  const auto wall0 = std::chrono::steady_clock::now();
  require_valid(grid, "Newmark");
  require_valid(opt, "Newmark");
  const SparseMatrix& M = sys.mass();
  const SparseMatrix& C = sys.damping();
  const SparseMatrix& K = sys.stiffness();
  const Index n = detail::require_square_system(M, C, K, "Newmark");
  const double dt = grid.dt, b = opt.beta, g = opt.gamma, al = opt.alpha;

  Eigen::SimplicialLDLT<SparseMatrix> ls;
  factor_effective(dt, opt, M, C, K, ls);

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
  const Index n_steps = grid.n_steps();
  if (observe) observe(0, 0.0, u, v, a);

  for (Index k = 1; k <= n_steps; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
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
  return detail::fixed_step_summary(Kernel::newmark, n_steps, dt, n, 0, 1, detail::seconds_since(wall0));
}

}  // namespace viaduct::solve

// ---------------------------------------------------------------------------------------------
// Batched Newmark: up to four cases in the lanes of one vector value.

namespace viaduct::solve {

namespace {

// The factorisation of S in a form the lanes loop walks directly, everything in the permuted
// ordering of the LDLᵀ (so no permutation per step): C and K merged on one row pattern (one pass
// computes C w1 + K w2), L strictly lower by columns, 1/D.
struct BatchPlan {
  Index n = 0;
  std::vector<Index> perm;  // original DOF -> permuted
  std::vector<Index> row_ptr, col;
  std::vector<double> cval, kval;
  std::vector<Index> l_ptr, l_row;   // L by columns (rows below the diagonal)
  std::vector<double> l_val, inv_d;
  std::vector<Index> lr_ptr, lr_col;  // L by rows (columns left of the diagonal)
  std::vector<double> lr_val;
};

// Σ_q w[q] · x[idx[q]] over [q0, q1), with four partial sums: the sum is a chain of dependent
// additions otherwise, and its latency (not the arithmetic) would set the pace.
VIADUCT_ALWAYS_INLINE void gather_dot(const double* w, const Index* idx, Index q0, Index q1, const lanes* x,
                                      lanes& sum) {
  const lanes zero = {0.0, 0.0, 0.0, 0.0};
  lanes s0 = zero, s1 = zero, s2 = zero, s3 = zero;
  Index q = q0;
  for (; q + 4 <= q1; q += 4) {
    s0 += w[q] * x[idx[q]];
    s1 += w[q + 1] * x[idx[q + 1]];
    s2 += w[q + 2] * x[idx[q + 2]];
    s3 += w[q + 3] * x[idx[q + 3]];
  }
  for (; q < q1; ++q) s0 += w[q] * x[idx[q]];
  sum = (s0 + s1) + (s2 + s3);
}

BatchPlan make_plan(const SparseMatrix& C, const SparseMatrix& K, const Eigen::SimplicialLDLT<SparseMatrix>& ls) {
  BatchPlan p;
  p.n = C.rows();
  const auto n = static_cast<std::size_t>(p.n);
  p.perm.resize(n);
  const auto& P = ls.permutationP();
  for (std::size_t i = 0; i < n; ++i) p.perm[i] = P.size() > 0 ? P.indices()[static_cast<Index>(i)] : static_cast<Index>(i);
  // Union pattern of P C Pᵀ and P K Pᵀ, row by row.
  std::vector<std::vector<std::pair<Index, std::pair<double, double>>>> rows(n);
  auto add = [&](const SparseMatrix& A, bool is_c) {
    for (Index j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
        const Index r = p.perm[static_cast<std::size_t>(it.row())], c = p.perm[static_cast<std::size_t>(it.col())];
        auto& row = rows[static_cast<std::size_t>(r)];
        auto at = std::find_if(row.begin(), row.end(), [&](const auto& e) { return e.first == c; });
        if (at == row.end()) row.push_back({c, {0.0, 0.0}}), at = row.end() - 1;
        (is_c ? at->second.first : at->second.second) += it.value();
      }
  };
  add(C, true);
  add(K, false);
  p.row_ptr.push_back(0);
  for (auto& row : rows) {
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& e : row) {
      p.col.push_back(e.first);
      p.cval.push_back(e.second.first);
      p.kval.push_back(e.second.second);
    }
    p.row_ptr.push_back(static_cast<Index>(p.col.size()));
  }
  const SparseMatrix& L = ls.matrixL().nestedExpression();
  p.l_ptr.push_back(0);
  for (Index j = 0; j < L.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(L, j); it; ++it)
      if (it.row() > j) {
        p.l_row.push_back(it.row());
        p.l_val.push_back(it.value());
      }
    p.l_ptr.push_back(static_cast<Index>(p.l_row.size()));
  }
  // The same L by rows, for the forward substitution as gathers.
  std::vector<std::vector<std::pair<Index, double>>> lrows(n);
  for (Index j = 0; j < L.outerSize(); ++j)
    for (Index q = p.l_ptr[static_cast<std::size_t>(j)]; q < p.l_ptr[static_cast<std::size_t>(j) + 1]; ++q)
      lrows[static_cast<std::size_t>(p.l_row[static_cast<std::size_t>(q)])].push_back({j, p.l_val[static_cast<std::size_t>(q)]});
  p.lr_ptr.push_back(0);
  for (const auto& row : lrows) {
    for (const auto& e : row) {
      p.lr_col.push_back(e.first);
      p.lr_val.push_back(e.second);
    }
    p.lr_ptr.push_back(static_cast<Index>(p.lr_col.size()));
  }
  const Vector& D = ls.vectorD();
  for (Index i = 0; i < D.size(); ++i) p.inv_d.push_back(1.0 / D[i]);
  return p;
}

struct BatchRun {
  const BatchPlan* plan;
  const std::vector<BatchCase>* cases;
  std::vector<Functional> outputs;  // permuted DOFs
  double dt, beta, gamma, alpha;
  bool check_finite;
  Index n_steps[kLanes];
  Index n_max;
  lanes* a;  // initial accelerations (permuted, per lane), then the working state
  std::vector<BatchHistories>* out;
};

VIADUCT_ALWAYS_INLINE void batch_loop(BatchRun& R) {
  const BatchPlan& P = *R.plan;
  const auto n = static_cast<std::size_t>(P.n);
  const std::size_t nc = R.cases->size(), no = R.outputs.size();
  const lanes zero = {0.0, 0.0, 0.0, 0.0};
  std::vector<double> store((8 * n + 1) * kLanes, 0.0);
  lanes* at = align_lanes(store.data());
  lanes *u = at, *v = at + n, *ut = at + 2 * n, *vt = at + 3 * n, *w1 = at + 4 * n, *w2 = at + 5 * n,
        *f = at + 6 * n, *fp = at + 7 * n;
  lanes* a = R.a;
  const double dt = R.dt, b = R.beta, g = R.gamma, al = R.alpha;
  const double c1 = dt * dt * (0.5 - b), c2 = dt * (1.0 - g), c3 = dt * dt * b, c4 = dt * g;
  const bool hht = al != 0.0;
  std::vector<SparseForce> entries(nc);
  for (auto& e : entries) e.dof.reserve(64), e.value.reserve(64);
  std::vector<Vector> dense(nc);
  std::vector<std::size_t> touched, touched_prev;  // permuted DOFs set in f (and in fp)
  bool all_touched = false, all_touched_prev = false;
  auto record = [&](Index k) {
    for (std::size_t o = 0; o < no; ++o) {
      const Functional& fn = R.outputs[o];
      lanes d = zero, ac = zero;
      for (std::size_t q = 0; q < fn.dof.size(); ++q) {
        const auto i = static_cast<std::size_t>(fn.dof[q]);
        d += fn.weight[q] * u[i];
        ac += fn.weight[q] * a[i];
      }
      for (std::size_t l = 0; l < nc; ++l)
        if (k <= R.n_steps[l]) {
          (*R.out)[l].disp(k, static_cast<Index>(o)) = d[l];
          (*R.out)[l].acc(k, static_cast<Index>(o)) = ac[l];
        }
    }
  };
  // f ← f(t) for every lane (zeroing only what the last use of the buffer set).
  auto fill = [&](double t) {
    if (all_touched) {
      for (std::size_t i = 0; i < n; ++i) f[i] = zero;
    } else {
      for (std::size_t i : touched) f[i] = zero;
    }
    touched.clear();
    all_touched = false;
    for (std::size_t l = 0; l < nc; ++l) {
      const SecondOrderSystem& sys = *(*R.cases)[l].system;
      if (sys.force_entries(t, entries[l])) {
        for (std::size_t e = 0; e < entries[l].dof.size(); ++e) {
          const auto i = static_cast<std::size_t>(P.perm[static_cast<std::size_t>(entries[l].dof[e])]);
          f[i][l] += entries[l].value[e];
          touched.push_back(i);
        }
      } else {
        if (dense[l].size() != P.n) dense[l] = Vector::Zero(P.n);
        sys.force(t, dense[l]);
        for (std::size_t i = 0; i < n; ++i) f[static_cast<std::size_t>(P.perm[i])][l] = dense[l][static_cast<Index>(i)];
        all_touched = true;
      }
    }
  };
  fill(0.0);
  record(0);
  for (Index k = 1; k <= R.n_max; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
    const double t = static_cast<double>(k) * dt;
    if (hht) {  // keep f(t − dt) as fp
      std::swap(f, fp);
      std::swap(touched, touched_prev);
      std::swap(all_touched, all_touched_prev);
    }
    fill(t);
    // Predictors, and the arguments of C and K.
    for (std::size_t i = 0; i < n; ++i) {
      ut[i] = u[i] + dt * v[i] + c1 * a[i];
      vt[i] = v[i] + c2 * a[i];
    }
    const lanes* x1 = vt;
    const lanes* x2 = ut;
    if (hht) {
      for (std::size_t i = 0; i < n; ++i) {
        w1[i] = (1.0 + al) * vt[i] - al * v[i];
        w2[i] = (1.0 + al) * ut[i] - al * u[i];
      }
      x1 = w1;
      x2 = w2;
    }
    // rhs = (1+α) f − α f_prev − C x1 − K x2, written into a.
    // rhs, then S a = rhs by L z = rhs (gathers by rows), D y = z, Lᵀ a = y (gathers by columns).
    const Index* col = P.col.data();
    for (std::size_t i = 0; i < n; ++i) {
      const lanes r = hht ? (1.0 + al) * f[i] - al * fp[i] : f[i];
      const Index q0 = P.row_ptr[i], q1 = P.row_ptr[i + 1];
      lanes sc, sk, sl;
      gather_dot(P.cval.data(), col, q0, q1, x1, sc);
      gather_dot(P.kval.data(), col, q0, q1, x2, sk);
      gather_dot(P.lr_val.data(), P.lr_col.data(), P.lr_ptr[i], P.lr_ptr[i + 1], a, sl);
      a[i] = r - sc - sk - sl;
    }
    for (std::size_t j = 0; j < n; ++j) a[j] *= P.inv_d[j];
    for (std::size_t j = n; j-- > 0;) {
      lanes sl;
      gather_dot(P.l_val.data(), P.l_row.data(), P.l_ptr[j], P.l_ptr[j + 1], a, sl);
      a[j] -= sl;
    }
    for (std::size_t i = 0; i < n; ++i) {
      u[i] = ut[i] + c3 * a[i];
      v[i] = vt[i] + c4 * a[i];
    }
    if (R.check_finite && (k % 64 == 0 || k == R.n_max)) {
      lanes s = zero;
      for (std::size_t i = 0; i < n; ++i) s += u[i];
      for (std::size_t l = 0; l < nc; ++l)
        if (!std::isfinite(s[l]))
          throw SolverError("Newmark: state became non-finite by t = " + num(t) + " s (case " + std::to_string(l + 1) +
                            " of the batch)");
    }
    record(k);
  }
}

#ifdef VIADUCT_HAVE_AVX2_VARIANT
VIADUCT_TARGET_AVX2 void batch_loop_avx2(BatchRun& R) { batch_loop(R); }
#endif

}  // namespace

std::vector<BatchHistories> newmark_batch(const std::vector<BatchCase>& cases, double dt, const NewmarkOptions& opt,
                                          const std::vector<Functional>& outputs) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (cases.empty() || cases.size() > kNewmarkBatch)
    throw InputError("Newmark batch: 1 to " + std::to_string(kNewmarkBatch) + " cases, got " +
                     std::to_string(cases.size()));
  require_valid(opt, "Newmark");
  if (!cases[0].system) throw InputError("Newmark batch: a case without a system");
  const SecondOrderSystem& s0 = *cases[0].system;
  const SparseMatrix& M = s0.mass();
  const SparseMatrix& C = s0.damping();
  const SparseMatrix& K = s0.stiffness();
  const Index n = detail::require_square_system(M, C, K, "Newmark");
  BatchRun R;
  R.n_max = 0;
  for (std::size_t l = 0; l < cases.size(); ++l) {
    const SecondOrderSystem* sys = cases[l].system;
    if (!sys) throw InputError("Newmark batch: a case without a system");
    if (&sys->mass() != &M || &sys->damping() != &C || &sys->stiffness() != &K)
      throw InputError("Newmark batch: every case must use the same M, C and K");
    const TimeGrid grid{dt, cases[l].t_end};
    require_valid(grid, "Newmark");
    R.n_steps[l] = grid.n_steps();
    R.n_max = std::max(R.n_max, R.n_steps[l]);
  }
  const double b = opt.beta, g = opt.gamma, al = opt.alpha;
  Eigen::SimplicialLDLT<SparseMatrix> ls;
  factor_effective(dt, opt, M, C, K, ls);
  const BatchPlan plan = make_plan(C, K, ls);
  R.plan = &plan;
  R.cases = &cases;
  for (const Functional& fn : outputs) {
    if (fn.dof.size() != fn.weight.size()) throw InputError("Newmark batch: output with mismatched dofs and weights");
    Functional p = fn;
    for (Index& d : p.dof) {
      if (d < 0 || d >= n) throw InputError("Newmark batch: output DOF out of range");
      d = plan.perm[static_cast<std::size_t>(d)];
    }
    R.outputs.push_back(std::move(p));
  }
  R.dt = dt, R.beta = b, R.gamma = g, R.alpha = al, R.check_finite = opt.check_finite;

  // From rest: M a0 = f(0), per case.
  std::vector<double> a_store((static_cast<std::size_t>(n) + 1) * kLanes, 0.0);
  R.a = align_lanes(a_store.data());
  {
    Eigen::SimplicialLDLT<SparseMatrix> lm(M);
    if (lm.info() != Eigen::Success) throw SolverError("Newmark: mass matrix is not positive definite");
    Vector f0(n);
    for (std::size_t l = 0; l < cases.size(); ++l) {
      f0.setZero();
      cases[l].system->force(0.0, f0);
      const Vector a0 = lm.solve(f0);
      for (Index i = 0; i < n; ++i) R.a[static_cast<std::size_t>(plan.perm[static_cast<std::size_t>(i)])][l] = a0[i];
    }
  }
  std::vector<BatchHistories> out(cases.size());
  for (std::size_t l = 0; l < cases.size(); ++l) {
    const auto rows = R.n_steps[l] + 1, cols = static_cast<Index>(outputs.size());
    out[l].disp.setZero(rows, cols);
    out[l].acc.setZero(rows, cols);
  }
  R.out = &out;
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  if (cpu_has_avx2()) batch_loop_avx2(R);
  else batch_loop(R);
#else
  batch_loop(R);
#endif
  const double wall = detail::seconds_since(wall0);
  for (std::size_t l = 0; l < cases.size(); ++l) {
    out[l].summary = detail::fixed_step_summary(Kernel::newmark_batch, R.n_steps[l], dt, n, 0, 1,
                                                wall / static_cast<double>(cases.size()));
  }
  return out;
}

}  // namespace viaduct::solve
