// SUNDIALS IDA on the coupled vehicle–structure system (declared in coupled.hpp): the residual,
// the reduced Newton solve, the contact events as roots (docs/vehicles.md, "IDA with vehicles").

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "checks.hpp"
#include "contacts.hpp"
#include "sundials.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve {

namespace coupled_ida_impl {

std::string tnum(double v) { return format_number(v, 6); }

// Largest structure the dense Schur complement takes (n² doubles: 72 MB).
constexpr Index kMaxStructure = 3000;

// Shared with the C callbacks through user_data. y = [u (n), v (n), z (n_v), w (n_v)]: the
// structure's and the vehicles' displacements and velocities.
struct Problem {
  const SparseMatrix *M = nullptr, *C = nullptr, *K = nullptr;
  const LinearVehicle* veh = nullptr;
  SparseMatrix Mv, Cv, Kv;  // the vehicles' matrices, sparse (a train's are block diagonal per coach)
  const ContactPath* path = nullptr;
  Index n = 0, nv = 0;
  std::size_t nw = 0;
  detail::Contacts ct;
  std::vector<char> on;  // per wheel, fixed between events: on the rail (spring force) or off it (0)
  Vector force;          // total contact force per wheel at the last evaluation (0 off the rail)
  Vector would;          // P0 + k (z − y − r): the force the spring would carry (the root function)
  // The reduced Newton matrix's factors (jacobian()): the vehicles' block D, sparse, and the
  // structure's Schur complement, dense; W the contacts' weights, E the wheels' unit columns.
  Eigen::SimplicialLDLT<SparseMatrix> ld;
  Eigen::LLT<Matrix> la;
  Matrix W, E, DE, A;
  Matrix Kd, Cd, Md;  // the structure's matrices, dense
  Vector kd;
  double cj = 0.0;
  Vector bu, bz, ru, rz, xu, xz;
  // Static correction (ContactPath::residual_flexibility): the flexibility F between the wheels
  // couples their contact laws, (1/k + F)_AA P_A = P0_A/k + g_A over the wheels A on the rail of
  // the structure (g = z − y − r); the Jacobian's Kj (contact_stiffness_matrix()) replaces diag(k).
  bool flex = false;
  Matrix Fr, Ca, Kj;  // Kj: the contacts' stiffness at the last Jacobian (the linear solves use it)
  Vector g, ga, pa, wt;
  std::vector<Index> act;
  Eigen::LDLT<Matrix> lc;
  std::exception_ptr error;
  std::string last_message;
  LogSink log;
  explicit Problem(std::size_t n_wheels) : ct(n_wheels), on(n_wheels, 1) {}

  // The contacts at t and the forces of state y.
  void forces(double t, const double* y) {
    ct.read(*path, t, n);
    flex = path->residual_flexibility(t, Fr);
    const Eigen::Map<const Vector> u(y, n), z(y + 2 * n, nv);
    if (flex) return coupled_forces(u, z);
    for (std::size_t w = 0; w < nw; ++w) {
      const Index wi = static_cast<Index>(w);
      const double k = veh->contact_stiffness[wi];
      would[wi] = veh->static_load[wi] + k * (z[veh->wheel_dof[w]] - ct.rail(w, u) - ct.r[wi]);
      force[wi] = on[w] ? would[wi] : 0.0;
    }
  }

  // The same with the static correction: the wheels on the rail of the structure solved together
  // (F couples them; a wheel on rigid ground or off the rail keeps its own law), and a wheel off
  // the rail would carry P0 + k (g − Σ F P), the rail under it bent by the others.
  void coupled_forces(const Eigen::Map<const Vector>& u, const Eigen::Map<const Vector>& z) {
    const Vector& k = veh->contact_stiffness;
    g.resize(static_cast<Index>(nw));
    act.clear();
    for (std::size_t w = 0; w < nw; ++w) {
      const Index wi = static_cast<Index>(w);
      g[wi] = z[veh->wheel_dof[w]] - ct.rail(w, u) - ct.r[wi];
      force[wi] = on[w] ? veh->static_load[wi] + k[wi] * g[wi] : 0.0;
      if (on[w] && !ct.dof[w].empty()) act.push_back(wi);
    }
    const Index na = static_cast<Index>(act.size());
    if (na > 0) {
      Ca.resize(na, na);
      ga.resize(na);
      for (Index i = 0; i < na; ++i) {
        const Index a = act[static_cast<std::size_t>(i)];
        for (Index j = 0; j < na; ++j) Ca(i, j) = Fr(a, act[static_cast<std::size_t>(j)]);
        Ca(i, i) += 1.0 / k[a];
        ga[i] = veh->static_load[a] / k[a] + g[a];
      }
      lc.compute(Ca);
      pa = lc.solve(ga);
      for (Index i = 0; i < na; ++i) force[act[static_cast<std::size_t>(i)]] = pa[i];
    }
    for (std::size_t w = 0; w < nw; ++w) {
      const Index wi = static_cast<Index>(w);
      would[wi] = on[w] ? force[wi] : veh->static_load[wi] + k[wi] * (g[wi] - Fr.row(wi).dot(force));
    }
  }

  // The contacts' stiffness matrix of the last forces(): k on the diagonal of the wheels on the
  // rail, ((1/k + F)_AA)⁻¹ over those on the structure (coupled_forces()).
  void contact_stiffness_matrix(Matrix& Kc) {
    const Index nwi = static_cast<Index>(nw), na = static_cast<Index>(act.size());
    Kc.setZero(nwi, nwi);
    for (Index w = 0; w < nwi; ++w)
      if (on[static_cast<std::size_t>(w)]) Kc(w, w) = veh->contact_stiffness[w];
    if (na == 0) return;
    const Matrix inv = lc.solve(Matrix::Identity(na, na));
    for (Index i = 0; i < na; ++i)
      for (Index j = 0; j < na; ++j) Kc(act[static_cast<std::size_t>(i)], act[static_cast<std::size_t>(j)]) = inv(i, j);
  }
};

// F = [u̇ − v; M v̇ + C v + K u − Σ Nᵀ P; ż − w; M_v ẇ + C_v w + K_v z + B (P − P0)].
int residual(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void* user) {
  auto* P = static_cast<Problem*>(user);
  try {
    const double* y = N_VGetArrayPointer(yy);
    const double* d = N_VGetArrayPointer(yp);
    double* r = N_VGetArrayPointer(rr);
    P->forces(t, y);
    const Index n = P->n, nv = P->nv;
    const LinearVehicle& veh = *P->veh;
    const Eigen::Map<const Vector> u(y, n), v(y + n, n), z(y + 2 * n, nv), zv(y + 2 * n + nv, nv);
    const Eigen::Map<const Vector> ud(d, n), vd(d + n, n), zd(d + 2 * n, nv), zvd(d + 2 * n + nv, nv);
    Eigen::Map<Vector> ru(r, n), rv(r + n, n), rz(r + 2 * n, nv), rzv(r + 2 * n + nv, nv);
    ru = ud - v;
    rv.noalias() = *P->M * vd;
    rv.noalias() += *P->C * v;
    rv.noalias() += *P->K * u;
    for (std::size_t w = 0; w < P->nw; ++w)
      for (std::size_t q = 0; q < P->ct.dof[w].size(); ++q)
        rv[P->ct.dof[w][q]] -= P->force[static_cast<Index>(w)] * P->ct.weight[w][q];
    rz = zd - zv;
    rzv.noalias() = P->Mv * zvd;
    rzv.noalias() += P->Cv * zv;
    rzv.noalias() += P->Kv * z;
    for (std::size_t w = 0; w < P->nw; ++w)
      rzv[veh.wheel_dof[w]] += P->force[static_cast<Index>(w)] - veh.static_load[static_cast<Index>(w)];
    return 0;
  } catch (...) {
    if (!P->error) P->error = std::current_exception();
    return -1;
  }
}

// Each wheel's would-be force: a root is a wheel leaving the rail or landing on it.
int roots(realtype t, N_Vector yy, N_Vector, realtype* g, void* user) {
  auto* P = static_cast<Problem*>(user);
  try {
    P->forces(t, N_VGetArrayPointer(yy));
    for (std::size_t w = 0; w < P->nw; ++w) g[w] = P->would[static_cast<Index>(w)];
    return 0;
  } catch (...) {
    if (!P->error) P->error = std::current_exception();
    return -1;
  }
}

// The Newton matrix ∂F/∂y + c_j ∂F/∂ẏ eliminates the velocities (v = c_j u − b_u, w = c_j z − b_z):
// what is left, for (u, z), is S = [A, B; Bᵀ, D] with A = K + c_j C + c_j² M + W k Wᵀ (W: the
// contacts' weight vectors as columns, k: the contact stiffnesses of the wheels on the rail),
// B = −W k E (E: the wheels' rows of the vehicles), D = K_v + c_j C_v + c_j² M_v + Eᵀ k E, symmetric
// positive definite. D is sparse (the coaches do not touch each other): factored sparse; then the
// Schur complement A − B D⁻¹ Bᵀ = K + c_j C + c_j² M + W (k − k G k) Wᵀ, G = E D⁻¹ Eᵀ the vehicles'
// flexibility at the wheels, dense n × n (the structure's modes). With the static correction the
// contacts' stiffness matrix Kj (Problem::contact_stiffness_matrix) stands for diag(k) throughout:
// D gets E Kj Eᵀ, the Schur complement W (Kj − Kj G Kj) Wᵀ. IDA's own matrix (a 1 × 1
// placeholder) is not used.
int jacobian(realtype t, realtype cj, N_Vector yy, N_Vector, N_Vector, SUNMatrix, void* user, N_Vector, N_Vector,
             N_Vector) {
  auto* P = static_cast<Problem*>(user);
  try {
    P->forces(t, N_VGetArrayPointer(yy));
    const Index n = P->n, nv = P->nv, nw = static_cast<Index>(P->nw);
    const LinearVehicle& veh = *P->veh;
    Vector& kd = P->kd;  // k on the rail, 0 off it
    for (Index w = 0; w < nw; ++w) kd[w] = P->on[static_cast<std::size_t>(w)] ? veh.contact_stiffness[w] : 0.0;
    SparseMatrix D = P->Kv + cj * P->Cv + (cj * cj) * P->Mv;
    auto wd = [&](Index w) { return veh.wheel_dof[static_cast<std::size_t>(w)]; };
    if (P->flex) {  // E Kj Eᵀ couples the wheels of every coach on the bridge
      P->contact_stiffness_matrix(P->Kj);
      std::vector<Eigen::Triplet<double>> tk;
      for (Index a = 0; a < nw; ++a)
        for (Index b = 0; b < nw; ++b)
          if (P->Kj(a, b) != 0.0) tk.emplace_back(wd(a), wd(b), P->Kj(a, b));
      SparseMatrix EKE(nv, nv);
      EKE.setFromTriplets(tk.begin(), tk.end());
      D += EKE;
    } else {
      for (Index w = 0; w < nw; ++w) D.coeffRef(wd(w), wd(w)) += kd[w];
    }
    P->ld.compute(D);
    if (P->ld.info() != Eigen::Success) return 1;  // recoverable: IDA retries with a smaller step
    P->E.setZero(nv, nw);
    for (Index w = 0; w < nw; ++w) P->E(wd(w), w) = 1.0;
    P->DE = P->ld.solve(P->E);  // D⁻¹ E
    Matrix H;
    if (P->flex) {
      H = P->Kj - P->Kj * (P->E.transpose() * P->DE) * P->Kj;
    } else {
      H = -(kd.asDiagonal() * (P->E.transpose() * P->DE) * kd.asDiagonal());
      H.diagonal() += kd;
    }
    P->W.setZero(n, nw);
    for (Index w = 0; w < nw; ++w)
      for (std::size_t q = 0; q < P->ct.dof[static_cast<std::size_t>(w)].size(); ++q)
        P->W(P->ct.dof[static_cast<std::size_t>(w)][q], w) += P->ct.weight[static_cast<std::size_t>(w)][q];
    P->A.noalias() = P->W * (H * P->W.transpose());
    P->A += P->Kd + cj * P->Cd + (cj * cj) * P->Md;
    P->la.compute(P->A);
    P->cj = cj;
    return P->la.info() == Eigen::Success ? 0 : 1;
  } catch (...) {
    if (!P->error) P->error = std::current_exception();
    return -1;
  }
}

// The linear solver IDA calls: J x = b through the factors the Jacobian callback made:
// x_u = (A − B D⁻¹ Bᵀ)⁻¹ (r_u − B D⁻¹ r_z), x_z = D⁻¹ (r_z − Bᵀ x_u), B y = −W k (E y).
int ls_solve(SUNLinearSolver LS, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto* P = static_cast<Problem*>(LS->content);
  const Index n = P->n, nv = P->nv;
  const double cj = P->cj;
  const double* bp = N_VGetArrayPointer(b);
  const LinearVehicle& veh = *P->veh;
  P->bu = Eigen::Map<const Vector>(bp, n);
  P->bz = Eigen::Map<const Vector>(bp + 2 * n, nv);
  P->ru = Eigen::Map<const Vector>(bp + n, n);
  P->ru.noalias() += *P->C * P->bu;
  P->ru.noalias() += cj * (*P->M * P->bu);
  P->rz = Eigen::Map<const Vector>(bp + 2 * n + nv, nv);
  P->rz.noalias() += P->Cv * P->bz;
  P->rz.noalias() += cj * (P->Mv * P->bz);
  P->xz = P->ld.solve(P->rz);  // D⁻¹ r_z
  const Index nw = static_cast<Index>(P->nw);
  if (P->flex) {  // B = −W Kc Eᵀ
    Vector& at = P->wt;
    at.resize(nw);
    for (Index w = 0; w < nw; ++w) at[w] = P->xz[veh.wheel_dof[static_cast<std::size_t>(w)]];
    P->ru.noalias() += P->W * (P->Kj * at);
    P->xu = P->la.solve(P->ru);
    at = P->Kj * (P->W.transpose() * P->xu);
    P->rz.setZero();
    for (Index w = 0; w < nw; ++w) P->rz[veh.wheel_dof[static_cast<std::size_t>(w)]] = at[w];
  } else {
    for (std::size_t w = 0; w < P->nw; ++w)  // r_u − B D⁻¹ r_z
      P->ru.noalias() += (P->kd[static_cast<Index>(w)] * P->xz[veh.wheel_dof[w]]) * P->W.col(static_cast<Index>(w));
    P->xu = P->la.solve(P->ru);
    P->rz.setZero();  // −Bᵀ x_u, at the wheels
    for (std::size_t w = 0; w < P->nw; ++w)
      P->rz[veh.wheel_dof[w]] = P->kd[static_cast<Index>(w)] * P->W.col(static_cast<Index>(w)).dot(P->xu);
  }
  P->xz.noalias() += P->ld.solve(P->rz);
  if (!(P->xu.allFinite() && P->xz.allFinite())) return SUNLS_PACKAGE_FAIL_REC;  // IDA retries, new Jacobian
  double* xp = N_VGetArrayPointer(x);
  Eigen::Map<Vector>(xp, n) = P->xu;
  Eigen::Map<Vector>(xp + n, n) = cj * P->xu - P->bu;
  Eigen::Map<Vector>(xp + 2 * n, nv) = P->xz;
  Eigen::Map<Vector>(xp + 2 * n + nv, nv) = cj * P->xz - P->bz;
  return SUNLS_SUCCESS;
}

SUNLinearSolver_Type ls_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID ls_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int ls_setup(SUNLinearSolver, SUNMatrix) { return SUNLS_SUCCESS; }  // the Jacobian callback factored
int ls_free(SUNLinearSolver LS) {
  if (!LS) return SUNLS_SUCCESS;
  LS->content = nullptr;  // the Problem is not owned
  SUNLinSolFreeEmpty(LS);
  return SUNLS_SUCCESS;
}

SUNLinearSolver reduced_solver(Problem& P, SUNContext ctx) {
  SUNLinearSolver LS = sun::check_ptr(SUNLinSolNewEmpty(ctx), "SUNLinSolNewEmpty");
  LS->ops->gettype = ls_type;
  LS->ops->getid = ls_id;
  LS->ops->setup = ls_setup;
  LS->ops->solve = ls_solve;
  LS->ops->free = ls_free;
  LS->content = &P;
  return LS;
}

void error_handler(int code, const char* module, const char* function, char* msg, void* user) {
  auto* P = static_cast<Problem*>(user);
  const std::string m = std::string(module ? module : "IDA") + "/" + (function ? function : "") + ": " + (msg ? msg : "");
  if (code < 0) P->last_message = m;
  else if (P->log) P->log(LogLevel::warning, "SUNDIALS " + m);
}

// The checks before any SUNDIALS object exists.
void require_inputs(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, const LinearVehicle& veh,
                    const TimeGrid& grid, const IdaOptions& opt) {
  require_valid(grid, "coupled IDA");
  require_valid(opt, "coupled IDA");
  std::string why;
  if (!veh.is_valid(&why)) throw InputError("coupled IDA: " + why);
  const Index n = detail::require_square_system(M, C, K, "coupled IDA");
  if (n > kMaxStructure)
    throw InputError("coupled IDA: a structure of " + std::to_string(n) + " DOFs exceeds the " +
                     std::to_string(kMaxStructure) + " its dense Newton matrix takes: integrate the structure's modes");
  for (std::size_t q = 0; q < veh.n_contacts(); ++q)
    if (std::isinf(veh.contact_stiffness[static_cast<Index>(q)]))
      throw InputError("coupled IDA: contact " + std::to_string(q) +
                       " is rigid, an index-3 constraint under a wheel with mass: IDA takes Hertz contacts "
                       "(train.contact = \"hertz\"), or use Newmark with HHT");
}

// One run: the SUNDIALS objects, the consistent restarts, the events, the outputs.
class Run {
 public:
  Run(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, const LinearVehicle& veh,
      const ContactPath& path, const TimeGrid& grid, const IdaOptions& opt, const CoupledObserver& observe)
      : veh_(veh), grid_(grid), observe_(observe), n_(M.rows()), nv_(veh.n_dofs()), N_(2 * (n_ + nv_)),
        nw_(veh.n_contacts()), P_(nw_), lm_(M), lmv_(veh.M), found_(nw_, 0), left_at_(nw_, 0.0) {
    if (lm_.info() != Eigen::Success) throw SolverError("coupled IDA: the structure's mass matrix is not positive definite");
    if (lmv_.info() != Eigen::Success)
      throw InputError("coupled IDA: the vehicles' mass matrix is not positive definite: IDA needs mass on every vehicle DOF");
    P_.M = &M, P_.C = &C, P_.K = &K, P_.veh = &veh, P_.path = &path;
    P_.Mv = veh.M.sparseView(), P_.Cv = veh.C.sparseView(), P_.Kv = veh.K.sparseView();
    P_.Kd = Matrix(K), P_.Cd = Matrix(C), P_.Md = Matrix(M);
    P_.n = n_, P_.nv = nv_, P_.nw = nw_, P_.log = opt.log;
    P_.force = P_.would = P_.kd = Vector::Zero(static_cast<Index>(nw_));
    P_.ct.read(path, 0.0, n_);
    for (Index q = 0; q < static_cast<Index>(nw_); ++q)
      if (P_.ct.r[q] != 0.0)
        throw InputError("coupled IDA: the irregularity under wheel " + std::to_string(q) + " is " + tnum(P_.ct.r[q]) +
                         " m at t = 0; the vehicles start in static equilibrium on a smooth rail (taper the profile in)");
    SUNContext raw_ctx = nullptr;
    if (SUNContext_Create(nullptr, &raw_ctx) != 0) throw SolverError("coupled IDA: SUNContext_Create failed");
    ctx_.reset(raw_ctx);
    yy_.reset(sun::check_ptr(N_VNew_Serial(N_, ctx_.get()), "N_VNew_Serial"));
    yp_.reset(sun::check_ptr(N_VNew_Serial(N_, ctx_.get()), "N_VNew_Serial"));
    rr_.reset(sun::check_ptr(N_VNew_Serial(N_, ctx_.get()), "N_VNew_Serial"));
    avtol_.reset(sun::check_ptr(N_VNew_Serial(N_, ctx_.get()), "N_VNew_Serial"));
    for (N_Vector v : {yy_.get(), yp_.get(), rr_.get(), avtol_.get()}) sun::use_fast_ops(v);
    Eigen::Map<Vector> at(N_VGetArrayPointer(avtol_.get()), N_);
    at.segment(0, n_).setConstant(opt.atol_disp);
    at.segment(n_, n_).setConstant(opt.atol_vel);
    at.segment(2 * n_, nv_).setConstant(opt.atol_disp);
    at.segment(2 * n_ + nv_, nv_).setConstant(opt.atol_vel);
    y().setZero();
    consistent(0.0);
    create(opt);
    s().kernel = Kernel::ida_vehicles;
    out_.steps_released.assign(nw_, 0);
    out_.airborne_s = Vector::Zero(static_cast<Index>(nw_));
    u_.resize(n_), v_.resize(n_), a_.resize(n_), z_.resize(nv_), zv_.resize(nv_), za_.resize(nv_);
  }

  CoupledSummary run(const std::vector<double>& breaks) {
    const double eps_t = 1e-9 * std::max(1.0, grid_.t_end);
    emit(0, 0.0);
    const Index n_out = grid_.n_steps();
    std::size_t next = 0;
    double t_now = 0.0;
    for (Index k = 1; k <= n_out; ++k) {
      check_cancel(k);  // the Python package's Ctrl-C
      const double tout = static_cast<double>(k) * grid_.dt;
      while (next < breaks.size() && breaks[next] <= tout - eps_t) {
        const double tb = breaks[next++];
        if (tb > t_now) t_now = solve_to(tb, tb, eps_t);
        restart(tb);
      }
      const double tstop = next < breaks.size() ? breaks[next] : std::max(grid_.t_end, tout) + grid_.dt;
      t_now = solve_to(tout, tstop, eps_t);
      emit(k, tout);
    }
    const double t_last = static_cast<double>(n_out) * grid_.dt;
    for (std::size_t w = 0; w < nw_; ++w)
      if (!P_.on[w]) out_.airborne_s[static_cast<Index>(w)] += t_last - left_at_[w];
    sun::add_counters(mem_.get(), s());
    s().n_samples = n_out + 1;
    s().n_dofs = n_;
    s().t_reached = t_last;
    s().stop_reason = "t_end reached";
    return out_;
  }

 private:
  Eigen::Map<Vector> y() { return {N_VGetArrayPointer(yy_.get()), N_}; }
  Eigen::Map<Vector> yd() { return {N_VGetArrayPointer(yp_.get()), N_}; }
  Summary& s() { return out_.summary; }

  void create(const IdaOptions& opt) {
    mem_.reset(sun::check_ptr(IDACreate(ctx_.get()), "IDACreate"));
    void* m = mem_.get();
    sun::check(IDASetErrHandlerFn(m, error_handler, &P_), "IDASetErrHandlerFn");
    sun::check(IDAInit(m, residual, 0.0, yy_.get(), yp_.get()), "IDAInit");
    sun::check(IDASVtolerances(m, opt.rtol, avtol_.get()), "IDASVtolerances");
    sun::check(IDASetUserData(m, &P_), "IDASetUserData");
    sun::check(IDASetMaxOrd(m, opt.max_order), "IDASetMaxOrd");
    sun::check(IDASetMaxNumSteps(m, opt.max_steps_per_output), "IDASetMaxNumSteps");
    if (opt.max_step > 0.0) sun::check(IDASetMaxStep(m, opt.max_step), "IDASetMaxStep");
    J_.reset(sun::check_ptr(SUNDenseMatrix(1, 1, ctx_.get()), "SUNDenseMatrix"));
    LS_.reset(reduced_solver(P_, ctx_.get()));
    sun::check(IDASetLinearSolver(m, LS_.get(), J_.get()), "IDASetLinearSolver");
    sun::check(IDASetJacFn(m, jacobian), "IDASetJacFn");
    if (veh_.release) {
      sun::check(IDARootInit(m, static_cast<int>(nw_), roots), "IDARootInit");
      sun::check(IDASetNoInactiveRootWarn(m), "IDASetNoInactiveRootWarn");
    }
  }

  // A consistent state at t: u̇ = v, ż = w, and the accelerations from the residual with them 0.
  void consistent(double t) {
    auto Y = y();
    auto D = yd();
    D.segment(0, n_) = Y.segment(n_, n_);
    D.segment(2 * n_, nv_) = Y.segment(2 * n_ + nv_, nv_);
    D.segment(n_, n_).setZero();
    D.segment(2 * n_ + nv_, nv_).setZero();
    if (residual(t, yy_.get(), yp_.get(), rr_.get(), &P_) != 0) std::rethrow_exception(P_.error);
    const Eigen::Map<const Vector> res(N_VGetArrayPointer(rr_.get()), N_);
    D.segment(n_, n_) = -lm_.solve(Vector(res.segment(n_, n_)));
    D.segment(2 * n_ + nv_, nv_) = -lmv_.solve(Vector(res.segment(2 * n_ + nv_, nv_)));
  }

  void restart(double t) {
    consistent(t);
    sun::add_counters(mem_.get(), s());  // IDAReInit zeroes them
    sun::check(IDAReInit(mem_.get(), t, yy_.get(), yp_.get()), "IDAReInit");
    ++s().n_restarts;
  }

  // A root: flip the law of each wheel whose would-be force crossed zero the way that changes it.
  void on_roots(double t) {
    sun::check(IDAGetRootInfo(mem_.get(), found_.data()), "IDAGetRootInfo");
    bool flipped = false;
    for (std::size_t w = 0; w < nw_; ++w) {
      if (P_.on[w] && found_[w] < 0) {
        P_.on[w] = 0, left_at_[w] = t, flipped = true;
        if (out_.first_release_t < 0.0) out_.first_release_t = t;
        out_.events.push_back(ContactEvent{w, t, false});
      } else if (!P_.on[w] && found_[w] > 0) {
        P_.on[w] = 1, flipped = true;
        out_.airborne_s[static_cast<Index>(w)] += t - left_at_[w];
        out_.events.push_back(ContactEvent{w, t, true});
      }
    }
    if (!flipped) return;
    // Contacts that flip again and again within a microsecond cannot settle: an error, not a hang.
    if (t - burst_t_ > 1e-6) burst_t_ = t, burst_n_ = 0;
    if (++burst_n_ > 1000)
      throw SolverError("coupled IDA: the wheel-rail contacts changed 1000 times within 1 µs at t = " + tnum(t) +
                        " s and did not settle (a step in the rail profile?)");
    restart(t);
  }

  // Integrates to tout without passing tstop, through any roots on the way.
  double solve_to(double tout, double tstop, double eps_t) {
    for (;;) {
      sun::check(IDASetStopTime(mem_.get(), tstop), "IDASetStopTime");
      realtype tret = 0.0;
          const int flag = IDASolve(mem_.get(), tout, &tret, yy_.get(), yp_.get(), IDA_NORMAL);
      if (P_.error) std::rethrow_exception(P_.error);
      if (flag < 0)
        throw SolverError("coupled IDA failed at t = " + tnum(tret) + " s (" + sun::flag_name(flag) + ")" +
                          (P_.last_message.empty() ? "" : ": " + P_.last_message));
      if (flag != IDA_ROOT_RETURN) return tret;
      on_roots(tret);
      if (tret >= tout - eps_t || tret >= tstop - eps_t) return tret;
    }
  }

  void emit(Index k, double t) {
    const auto Y = y();
    const auto D = yd();
    P_.forces(t, Y.data());
    u_ = Y.segment(0, n_), v_ = Y.segment(n_, n_), a_ = D.segment(n_, n_);
    z_ = Y.segment(2 * n_, nv_), zv_ = Y.segment(2 * n_ + nv_, nv_), za_ = D.segment(2 * n_ + nv_, nv_);
    if (!(u_.allFinite() && z_.allFinite())) throw SolverError("coupled IDA: state became non-finite at t = " + tnum(t) + " s");
    if (k == 0) out_.min_contact_force = out_.max_contact_force = P_.force;
    out_.min_contact_force = out_.min_contact_force.cwiseMin(P_.force);
    out_.max_contact_force = out_.max_contact_force.cwiseMax(P_.force);
    for (std::size_t w = 0; w < nw_; ++w)
      if (k > 0 && !P_.on[w]) ++out_.steps_released[w];
    if (observe_) observe_(k, t, CoupledState{u_, v_, a_, z_, zv_, za_, P_.force});
  }

  const LinearVehicle& veh_;
  const TimeGrid grid_;
  const CoupledObserver& observe_;
  Index n_, nv_, N_;
  std::size_t nw_;
  Problem P_;
  Eigen::SimplicialLDLT<SparseMatrix> lm_;
  Eigen::LLT<Matrix> lmv_;
  sun::ContextPtr ctx_;  // destroyed last: declared before everything made in it
  sun::VectorPtr yy_, yp_, rr_, avtol_;
  sun::MatrixPtr J_;
  sun::SolverPtr LS_;
  std::unique_ptr<void, sun::IdaMemDeleter> mem_;
  std::vector<int> found_;
  std::vector<double> left_at_;
  double burst_t_ = -1.0;  // the start of the current burst of contact events
  int burst_n_ = 0;
  CoupledSummary out_;
  Vector u_, v_, a_, z_, zv_, za_;
};

}  // namespace coupled_ida_impl

CoupledSummary coupled_ida(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, const LinearVehicle& veh,
                           const ContactPath& path, const TimeGrid& grid, const IdaOptions& opt,
                           const CoupledObserver& observe, const DivergenceBound* bound) {
  const auto wall0 = std::chrono::steady_clock::now();
  coupled_ida_impl::require_inputs(M, C, K, veh, grid, opt);
  const double eps_t = 1e-9 * std::max(1.0, grid.t_end);
  std::vector<double> breaks = path.breaks(grid.t_end);
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::remove_if(breaks.begin(), breaks.end(), [&](double e) { return !(e > eps_t && e < grid.t_end); }),
               breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end(), [&](double a, double b) { return b - a <= eps_t; }), breaks.end());
  // The guard's contact bound on every recorded sample, then the caller's observer.
  const CoupledObserver guarded = [&](Index k, double t, const CoupledState& x) {
    if (bound)
      for (Index q = 0; q < x.contact_force.size(); ++q)
        check_contact(*bound, static_cast<std::size_t>(q), x.contact_force[q], t,
                      [&] { return "IDA's error control (ida.rtol = " + coupled_ida_impl::tnum(opt.rtol) + ") on the wheel-rail contact"; });
    if (observe) observe(k, t, x);
  };
  coupled_ida_impl::Run run(M, C, K, veh, path, grid, opt, guarded);
  CoupledSummary out = run.run(breaks);
  out.summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace viaduct::solve
