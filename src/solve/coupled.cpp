#include "viaduct/solve/coupled.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "checks.hpp"
#include "contacts.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve {

bool LinearVehicle::is_valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = "LinearVehicle::" + m;
    return false;
  };
  const Index n = M.rows();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n)
    return fail("M, C, K: must be square and of one size");
  if (!M.allFinite() || !C.allFinite() || !K.allFinite()) return fail("M, C, K: must be finite");
  if (!M.isApprox(M.transpose()) || !C.isApprox(C.transpose()) || !K.isApprox(K.transpose()))
    return fail("M, C, K: must be symmetric");
  const std::size_t nw = wheel_dof.size();
  if (nw == 0) return fail("wheel_dof: at least one contact");
  if (static_cast<std::size_t>(static_load.size()) != nw || static_cast<std::size_t>(contact_stiffness.size()) != nw)
    return fail("static_load, contact_stiffness: one value per contact");
  for (std::size_t w = 0; w < nw; ++w) {
    const Index d = wheel_dof[w];
    if (d < 0 || d >= n) return fail("wheel_dof[" + std::to_string(w) + "] = " + std::to_string(d) + ": out of range");
    for (std::size_t q = 0; q < w; ++q)
      if (wheel_dof[q] == d) return fail("wheel_dof: contacts " + std::to_string(q) + " and " + std::to_string(w) + " share a DOF");
    const double p0 = static_load[static_cast<Index>(w)], k = contact_stiffness[static_cast<Index>(w)];
    if (!(std::isfinite(p0) && p0 > 0.0))
      return fail("static_load[" + std::to_string(w) + "] = " + format_number(p0) + ": violated constraint > 0");
    if (!(k > 0.0) || std::isnan(k))
      return fail("contact_stiffness[" + std::to_string(w) + "] = " + format_number(k) + ": violated constraint > 0");
  }
  return true;
}

namespace {

std::string cnum(double v) { return format_number(v, 6); }

// Columns of S⁻¹ at the DOFs the wheels touch, computed once each (one sparse solve) and kept while
// they are used; the least recently used is dropped when the cache is full (the wheels move on).
class InverseColumns {
 public:
  InverseColumns(const Eigen::SimplicialLDLT<SparseMatrix>& ls, Index n, std::size_t capacity)
      : ls_(ls), n_(n), capacity_(capacity), e_(Vector::Zero(n)) {}
  const Vector& get(Index dof, Index step) {
    auto it = slot_.find(dof);
    if (it != slot_.end()) {
      last_[it->second] = step;
      return cols_[it->second];
    }
    std::size_t s = cols_.size();
    if (cols_.size() >= capacity_) {
      const auto oldest = std::min_element(last_.begin(), last_.end());
      if (*oldest < step) {
        s = static_cast<std::size_t>(oldest - last_.begin());
        slot_.erase(dof_[s]);
      }
    }
    if (s == cols_.size()) {
      cols_.emplace_back(n_);
      dof_.push_back(-1);
      last_.push_back(step);
    }
    e_[dof] = 1.0;
    cols_[s] = ls_.solve(e_);
    e_[dof] = 0.0;
    dof_[s] = dof;
    last_[s] = step;
    slot_[dof] = s;
    ++computed_;
    return cols_[s];
  }
  Index computed() const { return computed_; }

 private:
  const Eigen::SimplicialLDLT<SparseMatrix>& ls_;
  Index n_;
  std::size_t capacity_;
  Vector e_;
  std::unordered_map<Index, std::size_t> slot_;
  std::vector<Vector> cols_;
  std::vector<Index> dof_, last_;
  Index computed_ = 0;
};

void require_vehicle(const LinearVehicle& veh, const char* who) {
  std::string why;
  if (!veh.is_valid(&why)) throw InputError(std::string(who) + ": " + why);
}

}  // namespace

namespace {

// One coupled run: the factorisations, the state, and one step of Newmark / HHT-α (docs/vehicles.md).
// With α: M a₁ + (1+α)(C v₁ + K u₁ − Nᵀ(P0 + p)₁) − α(C v₀ + K u₀ − Nᵀ(P0 + p)₀) = 0 for the structure,
// the same for the vehicles with −B p, and the contact law at t₁.
class CoupledRun {
 public:
  CoupledRun(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, const LinearVehicle& veh,
             const ContactPath& path, double dt, const NewmarkOptions& opt)
      : M_(M), C_(C), K_(K), veh_(veh), path_(path), n_(M.rows()), nv_(veh.n_dofs()), nw_(veh.n_contacts()),
        dt_(dt), b_(opt.beta), g_(opt.gamma), al_(opt.alpha), check_(opt.check_finite), ct_(nw_),
        cols_(ls_, n_, 8 * nw_ + 64) {
    const double w = 1.0 + al_;
    ls_.compute(SparseMatrix(M + (w * g_ * dt) * C + (w * b_ * dt * dt) * K));
    if (ls_.info() != Eigen::Success) throw SolverError("coupled Newmark: the structure's effective matrix is not positive definite");
    lv_.compute(veh.M + (w * g_ * dt) * veh.C + (w * b_ * dt * dt) * veh.K);
    if (lv_.info() != Eigen::Success)
      throw SolverError("coupled Newmark: the vehicles' effective matrix is not positive definite (a DOF without mass, spring or dashpot?)");
    const Index nwi = static_cast<Index>(nw_);
    // Y = S_v⁻¹ B, G = Bᵀ Y: the vehicles' flexibility at their wheels (constant).
    Matrix B = Matrix::Zero(nv_, nwi);
    for (std::size_t q = 0; q < nw_; ++q) B(veh.wheel_dof[q], static_cast<Index>(q)) = 1.0;
    Y_ = lv_.solve(B);
    G_.resize(nwi, nwi);
    for (Index q = 0; q < nwi; ++q) G_.row(q) = Y_.row(veh.wheel_dof[static_cast<std::size_t>(q)]);
    const double c = w * b_ * dt * dt;
    spring_.resize(nwi);  // 1/((1+α) k β dt²): the contact springs' share (0 for rigid contacts)
    rigid_.assign(nw_, false);
    for (Index q = 0; q < nwi; ++q) {
      const bool rigid = std::isinf(veh.contact_stiffness[q]);
      // A rigid wheel with mass follows the rail (acceleration rows); a massless one keeps the
      // displacement row, an algebraic equation of the springs above it (no multiplier to amplify).
      rigid_[static_cast<std::size_t>(q)] = rigid && veh.M(veh.wheel_dof[static_cast<std::size_t>(q)], veh.wheel_dof[static_cast<std::size_t>(q)]) > 0.0;
      any_rigid_ = any_rigid_ || rigid_[static_cast<std::size_t>(q)];
      spring_[q] = rigid ? 0.0 : 1.0 / (veh.contact_stiffness[q] * c);
    }
    u_ = v_ = a_ = f_ = f_old_ = rhs_ = ut_ = vt_ = as_ = Vector::Zero(n_);
    z_ = zv_ = za_ = zt_ = zvt_ = av_ = Vector::Zero(nv_);
    force_ = veh.static_load;
    p_ = gap_ = Vector::Zero(nwi);
    X_.resize(n_, nwi);
    A_.resize(nwi, nwi);
    on_.assign(nw_, false);
  }

  // The state at rest at t = 0: the vehicles in equilibrium on a smooth rail, the structure under
  // the static loads of the wheels already on it.
  void start() {
    ct_.read(path_, 0.0, n_);
    for (Index q = 0; q < static_cast<Index>(nw_); ++q)
      if (ct_.r[q] != 0.0)
        throw InputError("coupled Newmark: the irregularity under wheel " + std::to_string(q) + " is " + cnum(ct_.r[q]) +
                         " m at t = 0; the vehicles start in static equilibrium on a smooth rail (taper the profile in)");
    contact_loads(force_, f_);
    Eigen::SimplicialLDLT<SparseMatrix> lm(M_);
    if (lm.info() != Eigen::Success) throw SolverError("coupled Newmark: mass matrix is not positive definite");
    a_ = lm.solve(f_);
  }

  void step(double t) {
    const double dt = dt_, b = b_, g = g_, al = al_, w = 1.0 + al, c = b * dt * dt;
    ut_ = u_ + dt * v_ + (dt * dt * (0.5 - b)) * a_;
    vt_ = v_ + (dt * (1.0 - g)) * a_;
    zt_ = z_ + dt * zv_ + (dt * dt * (0.5 - b)) * za_;
    zvt_ = zv_ + (dt * (1.0 - g)) * za_;
    // The previous step's contact loads (its positions, P0 + p) for α's share, then today's static ones.
    if (al != 0.0) contact_loads(force_, f_old_);
    ct_.read(path_, t, n_);
    if (any_rigid_) ct_.read_rates(path_, t, rigid_);
    flex_ = path_.residual_flexibility(t, Fr_);
    if (flex_ && any_rigid_)
      throw InputError("coupled Newmark: a rigid contact under a wheel with mass on a structure with a static correction "
                       "(ContactPath::residual_flexibility) is not supported: the correction's share of the rail would need the "
                       "contact forces' second derivative");
    contact_loads(veh_.static_load, f_);
    rhs_.noalias() = w * f_;
    rhs_.noalias() -= C_ * (w * vt_ - al * v_);
    rhs_.noalias() -= K_ * (w * ut_ - al * u_);
    if (al != 0.0) rhs_.noalias() -= al * f_old_;
    as_ = ls_.solve(rhs_);
    // The vehicles' right-hand side in work vectors (no allocation per step).
    zw_ = w * zvt_ - al * zv_;
    rv_.noalias() = -(veh_.C * zw_);
    zw_ = w * zt_ - al * z_;
    rv_.noalias() -= veh_.K * zw_;
    if (al != 0.0)
      for (std::size_t q = 0; q < nw_; ++q) rv_[veh_.wheel_dof[q]] += al * p_[static_cast<Index>(q)];
    av_ = lv_.solve(rv_);
    solve_contacts(k_, w, c);
    for (std::size_t q = 0; q < nw_; ++q)
      if (on_[q]) as_ += (w * p_[static_cast<Index>(q)]) * X_.col(static_cast<Index>(q));
    av_.noalias() -= w * (Y_ * p_);
    a_ = as_;
    za_ = av_;
    u_ = ut_ + c * a_;
    v_ = vt_ + (g * dt) * a_;
    z_ = zt_ + c * za_;
    zv_ = zvt_ + (g * dt) * za_;
    if (any_rigid_) follow_rail(t);
    force_ = veh_.static_load + p_;
    if (check_ && !(u_.allFinite() && z_.allFinite() && p_.allFinite()))
      throw SolverError("coupled Newmark: state became non-finite at t = " + cnum(t) + " s");
  }

  CoupledState state() const { return CoupledState{u_, v_, a_, z_, zv_, za_, force_}; }
  const Vector& force() const { return force_; }
  Index cached() const { return cols_.computed(); }
  Index k_ = 0;  // the step number (the column cache's clock)

 private:
  // f = Σ Nᵀ P over the wheels on the structure (the contacts read last).
  void contact_loads(const Vector& P, Vector& f) const {
    f.setZero();
    for (std::size_t q = 0; q < nw_; ++q)
      for (std::size_t j = 0; j < ct_.dof[q].size(); ++j) f[ct_.dof[q][j]] += P[static_cast<Index>(q)] * ct_.weight[q][j];
  }

  // The contact forces p from (springs + G + N X + F/c_eff) p = gap / c_eff, with X = S⁻¹ Nᵀ
  // (cached columns) and F the static correction's flexibility between the wheels (its share of the
  // static loads P0 moved to the gap).
  //
  // A rigid wheel's row is its constraint on the accelerations, z̈ = N ü + 2 Ṅ u̇ + N̈ u + r̈ at the
  // step's end, with u = ũ + β dt² ü and u̇ = ṽ + γ dt ü: (G + Ñ X) p = (z̈_free − Ñ a_free − 2 Ṅ ṽ
  // − N̈ ũ − r̈)/(1+α), Ñ = N + 2γ dt Ṅ + β dt² N̈ (no 1/dt² in it: the force converges as dt → 0).
  void solve_contacts(Index k, double w, double c) {
    const double c_eff = w * c;
    for (std::size_t q = 0; q < nw_; ++q) {
      on_[q] = !ct_.dof[q].empty();
      if (!on_[q]) continue;
      auto xq = X_.col(static_cast<Index>(q));
      xq.setZero();
      for (std::size_t j = 0; j < ct_.dof[q].size(); ++j) xq += ct_.weight[q][j] * cols_.get(ct_.dof[q][j], k);
    }
    const double g2 = 2.0 * g_ * dt_;
    for (std::size_t q = 0; q < nw_; ++q) {
      const Index qi = static_cast<Index>(q);
      const Index d = veh_.wheel_dof[q];
      if (rigid_[q]) {
        auto tilde = [&](const auto& x) { return ct_.rail(q, x) + g2 * ct_.rate(q, x, 1) + c * ct_.rate(q, x, 2); };
        gap_[qi] = (av_[d] - (on_[q] ? tilde(as_) + 2.0 * ct_.rate(q, vt_, 1) + ct_.rate(q, ut_, 2) : 0.0) - ct_.ddr[qi]) / w;
        for (std::size_t j = 0; j < nw_; ++j) {
          const Index ji = static_cast<Index>(j);
          A_(qi, ji) = G_(qi, ji) + (on_[q] && on_[j] ? tilde(X_.col(ji)) : 0.0);
        }
        continue;
      }
      gap_[qi] = (zt_[d] + c * av_[d] - ct_.rail(q, ut_) - c * ct_.rail(q, as_) - ct_.r[qi]) / c_eff;
      for (std::size_t j = 0; j < nw_; ++j) {
        const Index ji = static_cast<Index>(j);
        A_(qi, ji) = G_(qi, ji) + (on_[q] && on_[j] ? ct_.rail(q, X_.col(ji)) : 0.0);
      }
      A_(qi, qi) += spring_[qi];
      if (flex_) {
        gap_[qi] -= Fr_.row(qi).dot(veh_.static_load) / c_eff;
        A_.row(qi) += Fr_.row(qi) / c_eff;
      }
    }
    if (!veh_.release) {
      if (any_rigid_) {  // the acceleration rows make A unsymmetric
        lu_.compute(A_);
        p_ = lu_.solve(gap_);
        if (!p_.allFinite()) throw SolverError("coupled Newmark: the contact system is singular");
        return;
      }
      la_.compute(A_);
      if (la_.info() != Eigen::Success) throw SolverError("coupled Newmark: the contact system is singular");
      p_ = la_.solve(gap_);
      return;
    }
    settle_contacts(k);
  }

  // Unilateral contact: a wheel whose total force would pull is released (P0 + p = 0) and taken
  // back when it would press into the rail again; the active set is iterated until the forces and
  // the gaps agree with it (releases first, then landings, so that it does not cycle).
  void settle_contacts(Index k) {
    const Index nwi = static_cast<Index>(nw_);
    for (int it = 0;; ++it) {
      if (it == 4 * nwi + 8)
        throw SolverError("coupled Newmark: the wheel-rail contacts did not settle at t = " + cnum(static_cast<double>(k) * dt_) + " s");
      act_.clear();
      for (Index q = 0; q < nwi; ++q) {
        if (active_[static_cast<std::size_t>(q)]) act_.push_back(q);
        else p_[q] = -veh_.static_load[q];
      }
      const Index na = static_cast<Index>(act_.size());
      if (na > 0) {
        Matrix& Aa = Aa_;  // resized only when the active set's size changes
        Vector& ra = ra_;
        Aa.resize(na, na);
        ra.resize(na);
        for (Index i = 0; i < na; ++i) {
          ra[i] = gap_[act_[static_cast<std::size_t>(i)]];
          for (Index q = 0; q < nwi; ++q)
            if (!active_[static_cast<std::size_t>(q)]) ra[i] -= A_(act_[static_cast<std::size_t>(i)], q) * p_[q];
          for (Index j = 0; j < na; ++j) Aa(i, j) = A_(act_[static_cast<std::size_t>(i)], act_[static_cast<std::size_t>(j)]);
        }
        if (any_rigid_) {  // the acceleration rows make A unsymmetric
          lu_.compute(Aa);
          pa_ = lu_.solve(ra);
          if (!pa_.allFinite()) throw SolverError("coupled Newmark: the contact system is singular");
        } else {
          la_.compute(Aa);
          if (la_.info() != Eigen::Success) throw SolverError("coupled Newmark: the contact system is singular");
          pa_ = la_.solve(ra);
        }
        for (Index i = 0; i < na; ++i) p_[act_[static_cast<std::size_t>(i)]] = pa_[i];
      }
      bool released = false, landed = false;
      for (Index q = 0; q < nwi; ++q)
        if (active_[static_cast<std::size_t>(q)] && veh_.static_load[q] + p_[q] < 0.0) active_[static_cast<std::size_t>(q)] = false, released = true;
      if (!released)
        for (Index q = 0; q < nwi; ++q) {
          if (active_[static_cast<std::size_t>(q)]) continue;
          // The compression the step would leave, relative to the static one, over c_eff.
          double d = gap_[q];
          for (Index j = 0; j < nwi; ++j) d -= (A_(q, j) - (j == q ? spring_[q] : 0.0)) * p_[j];
          // (a rigid wheel with mass in the air never lands here: follow_rail() refuses its impact)
          const bool presses = !rigid_[static_cast<std::size_t>(q)] &&
                               (spring_[q] == 0.0 ? d > 0.0 : veh_.static_load[q] + d / spring_[q] > 0.0);
          if (presses) active_[static_cast<std::size_t>(q)] = true, landed = true;
        }
      if (!released && !landed) return;
    }
  }

  // Rigid wheels on the rail take its position and velocity (the acceleration rows keep them there
  // to the step's accuracy; this removes the drift). A rigid wheel in the air that reaches the rail
  // lands with an impact, whose force the model cannot resolve: SolverError.
  void follow_rail(double t) {
    for (std::size_t q = 0; q < nw_; ++q) {
      if (!rigid_[q]) continue;
      const Index qi = static_cast<Index>(q), d = veh_.wheel_dof[q];
      const double level = ct_.rail(q, u_) + ct_.r[qi];
      if (!active_[q]) {
        if (z_[d] > level)
          throw SolverError("coupled Newmark: wheel " + std::to_string(q + 1) + " lands on the rail again at t = " + cnum(t) +
                            " s after leaving it: with a rigid contact the landing is an impact whose force grows without "
                            "bound as the step shrinks; use a Hertz contact (train.contact = \"hertz\"), or keep the wheels on the rail "
                            "(train.contact_release = false: a tensile force is then reported as a lost contact)");
        continue;
      }
      z_[d] = level;
      zv_[d] = ct_.rail(q, v_) + ct_.rate(q, u_, 1) + ct_.dr[qi];
    }
  }

  const SparseMatrix &M_, &C_, &K_;
  const LinearVehicle& veh_;
  const ContactPath& path_;
  Index n_, nv_;
  std::size_t nw_;
  double dt_, b_, g_, al_;
  bool check_;
  detail::Contacts ct_;
  Eigen::SimplicialLDLT<SparseMatrix> ls_;
  InverseColumns cols_;
  Eigen::LLT<Matrix> lv_;
  Eigen::LDLT<Matrix> la_;
  Eigen::PartialPivLU<Matrix> lu_;  // the contact system with rigid wheels' acceleration rows
  std::vector<bool> rigid_;         // per wheel: k = ∞ under a wheel with mass (follows the rail)
  bool any_rigid_ = false;
  Matrix Y_, G_, X_, A_, Fr_;
  bool flex_ = false;  // Fr_ holds the path's residual flexibility at this step
  Vector spring_, u_, v_, a_, f_, f_old_, rhs_, ut_, vt_, as_, z_, zv_, za_, zt_, zvt_, av_, force_, p_, gap_;
  std::vector<bool> on_;
  std::vector<bool> active_ = std::vector<bool>(nw_, true);  // wheels on the rail (unilateral contact)
  std::vector<Index> act_;
  Matrix Aa_;                 // the active contacts' system (unilateral contact)
  Vector ra_, pa_, rv_, zw_;  // work vectors of settle_contacts() and step()

 public:
  bool in_contact(std::size_t q) const { return active_[q]; }
};

}  // namespace

CoupledSummary coupled_newmark(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                               const LinearVehicle& veh, const ContactPath& path, const TimeGrid& grid,
                               const NewmarkOptions& opt, const CoupledObserver& observe, const DivergenceBound* bound) {
  const auto wall0 = std::chrono::steady_clock::now();
  require_valid(grid, "coupled Newmark");
  require_valid(opt, "coupled Newmark");
  if (!opt.unconditionally_stable())
    throw InputError("coupled Newmark: NewmarkOptions beta = " + cnum(opt.beta) + ", gamma = " + cnum(opt.gamma) +
                     ": only unconditionally stable schemes (2 beta >= gamma >= 1/2) with vehicles");
  require_vehicle(veh, "coupled Newmark");
  const Index n = detail::require_square_system(M, C, K, "coupled Newmark");
  CoupledRun run(M, C, K, veh, path, grid.dt, opt);
  run.start();
  CoupledSummary out;
  out.min_contact_force = run.force();
  out.max_contact_force = run.force();
  out.steps_released.assign(veh.n_contacts(), 0);
  std::vector<bool> was_on(veh.n_contacts(), true);
  if (observe) observe(0, 0.0, run.state());
  const Index n_steps = grid.n_steps();
  for (Index k = 1; k <= n_steps; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
    const double t = k * grid.dt;
    run.k_ = k;
    run.step(t);
    if (bound)
      for (std::size_t q = 0; q < veh.n_contacts(); ++q)
        check_contact(*bound, q, run.force()[static_cast<Index>(q)], t, [&] {
          return "the wheel-rail contact (" + std::string(std::isinf(veh.contact_stiffness[static_cast<Index>(q)]) ? "rigid" : "Hertz") +
                 ") or the time integration (Newmark/HHT beta = " + cnum(opt.beta) + ", gamma = " + cnum(opt.gamma) +
                 ", alpha = " + cnum(opt.alpha) + " at dt = " + cnum(grid.dt) + " s)";
        });
    out.min_contact_force = out.min_contact_force.cwiseMin(run.force());
    out.max_contact_force = out.max_contact_force.cwiseMax(run.force());
    for (std::size_t q = 0; q < veh.n_contacts(); ++q) {
      if (!run.in_contact(q)) {
        if (out.first_release_t < 0.0) out.first_release_t = t;
        ++out.steps_released[q];
      }
      if (run.in_contact(q) != was_on[q]) out.events.push_back(ContactEvent{q, t, run.in_contact(q)});
      was_on[q] = run.in_contact(q);
    }
    if (observe) observe(k, t, run.state());
  }
  out.airborne_s.resize(static_cast<Index>(veh.n_contacts()));
  for (std::size_t q = 0; q < veh.n_contacts(); ++q)
    out.airborne_s[static_cast<Index>(q)] = static_cast<double>(out.steps_released[q]) * grid.dt;
  out.n_cached_columns = run.cached();
  out.summary = detail::fixed_step_summary(Kernel::newmark_vehicles, n_steps, grid.dt, n, 0, 1, detail::seconds_since(wall0));
  return out;
}

Vector coupled_static(const SparseMatrix& K, const LinearVehicle& veh, const ContactPath& path, double t, Vector* z_out,
                      Vector* force_out) {
  require_vehicle(veh, "coupled static");
  const Index n = K.rows();
  if (K.cols() != n) throw InputError("coupled static: K must be square");
  Eigen::SimplicialLDLT<SparseMatrix> ls(K);
  if (ls.info() != Eigen::Success) throw SolverError("coupled static: the structure's stiffness matrix is singular");
  const std::size_t nw = veh.n_contacts();
  const Index nwi = static_cast<Index>(nw), nv = veh.n_dofs();
  detail::Contacts ct(nw);
  ct.read(path, t, n);
  Matrix X = Matrix::Zero(n, nwi);  // K⁻¹ N_wᵀ
  for (std::size_t w = 0; w < nw; ++w) {
    if (ct.dof[w].empty()) continue;
    Vector nt = Vector::Zero(n);
    for (std::size_t q = 0; q < ct.dof[w].size(); ++q) nt[ct.dof[w][q]] += ct.weight[w][q];
    X.col(static_cast<Index>(w)) = ls.solve(nt);
  }
  Matrix F(nwi, nwi);
  for (Index w = 0; w < nwi; ++w)
    for (Index q = 0; q < nwi; ++q) F(w, q) = ct.rail(static_cast<std::size_t>(w), X.col(q));
  Matrix Fr;  // a modal structure's static correction
  if (path.residual_flexibility(t, Fr)) F += Fr;
  // [K_v  B; Bᵀ  −(D + F)] [z; p] = [0; r + F P0].
  Matrix S = Matrix::Zero(nv + nwi, nv + nwi);
  Vector rhs = Vector::Zero(nv + nwi);
  S.topLeftCorner(nv, nv) = veh.K;
  for (Index w = 0; w < nwi; ++w) {
    const Index d = veh.wheel_dof[static_cast<std::size_t>(w)];
    S(d, nv + w) = 1.0;
    S(nv + w, d) = 1.0;
    if (!std::isinf(veh.contact_stiffness[w])) S(nv + w, nv + w) -= 1.0 / veh.contact_stiffness[w];
  }
  S.bottomRightCorner(nwi, nwi) -= F;
  rhs.tail(nwi) = ct.r + F * veh.static_load;
  Eigen::FullPivLU<Matrix> lu(S);
  if (!lu.isInvertible()) throw SolverError("coupled static: the vehicles are a mechanism on their wheels (singular system)");
  const Vector x = lu.solve(rhs);
  const Vector p = x.tail(nwi);
  if (z_out) *z_out = x.head(nv);
  if (force_out) *force_out = veh.static_load + p;
  return X * (veh.static_load + p);
}

}  // namespace viaduct::solve
