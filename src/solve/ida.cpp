#include "viaduct/solve/ida.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>

#include <Eigen/SparseCholesky>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "checks.hpp"
#include "sundials.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve {

namespace {
using sun::check;
using sun::check_ptr;
using sun::flag_name;
using sun::ContextPtr;
using sun::VectorPtr;
using sun::MatrixPtr;
using sun::SolverPtr;
using sun::IdaMemDeleter;
std::string short_num(double v) { return format_number(v, 6); }

// Shared with the C callbacks through user_data.
struct Problem {
  const SecondOrderSystem* sys = nullptr;
  Index n = 0;
  // M, C, K on one common pattern (explicit zeros), column-major: values per column entry.
  SparseMatrix Mu, Cu, Ku;
  mutable Vector f, tmp;
  std::exception_ptr error;  // first exception thrown inside a callback
  std::string last_message;  // last SUNDIALS message
  LogSink log;
};

int residual(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void* user) {
  auto* P = static_cast<Problem*>(user);
  try {
    const Index n = P->n;
    const Eigen::Map<const Vector> u(N_VGetArrayPointer(yy), n), v(N_VGetArrayPointer(yy) + n, n);
    const Eigen::Map<const Vector> ud(N_VGetArrayPointer(yp), n), vd(N_VGetArrayPointer(yp) + n, n);
    Eigen::Map<Vector> r1(N_VGetArrayPointer(rr), n), r2(N_VGetArrayPointer(rr) + n, n);
    r1 = ud - v;
    P->f.setZero();
    P->sys->force(t, P->f);
    r2.noalias() = P->Mu * vd;
    r2.noalias() += P->Cu * v;
    r2.noalias() += P->Ku * u;
    r2 -= P->f;
    return 0;
  } catch (...) {
    if (!P->error) P->error = std::current_exception();
    return -1;  // unrecoverable: IDASolve returns and the exception is rethrown
  }
}

void make_pattern(const Problem& P, SUNMatrix J) {
  const Index n = P.n;
  sunindextype* colptr = SUNSparseMatrix_IndexPointers(J);
  sunindextype* rows = SUNSparseMatrix_IndexValues(J);
  sunindextype k = 0;
  for (Index j = 0; j < n; ++j) {
    colptr[j] = k;
    rows[k++] = j;
    for (SparseMatrix::InnerIterator it(P.Ku, j); it; ++it) rows[k++] = n + it.row();
  }
  for (Index j = 0; j < n; ++j) {
    colptr[n + j] = k;
    rows[k++] = j;
    for (SparseMatrix::InnerIterator it(P.Mu, j); it; ++it) rows[k++] = n + it.row();
  }
  colptr[2 * n] = k;
}

// J = [cj I, -I; K, cj M + C] in CSC. IDA zeroes the sparse matrix — pattern included — before
// every call (SUNMatZero_Sparse), so the pattern is laid down again each time.
int jacobian(realtype, realtype cj, N_Vector, N_Vector, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector,
             N_Vector) {
  auto* P = static_cast<Problem*>(user);
  const Index n = P->n;
  make_pattern(*P, J);
  realtype* data = SUNSparseMatrix_Data(J);
  sunindextype k = 0;
  for (Index j = 0; j < n; ++j) {  // u columns: cj at (j, j), K below
    data[k++] = cj;
    for (SparseMatrix::InnerIterator it(P->Ku, j); it; ++it) data[k++] = it.value();
  }
  for (Index j = 0; j < n; ++j) {  // v columns: -1 at (j, n + j), cj M + C below
    data[k++] = -1.0;
    SparseMatrix::InnerIterator m(P->Mu, j), c(P->Cu, j);
    for (; m; ++m, ++c) data[k++] = cj * m.value() + c.value();
  }
  return 0;
}

void error_handler(int code, const char* module, const char* function, char* msg, void* user) {
  auto* P = static_cast<Problem*>(user);
  std::string m = std::string(module ? module : "IDA") + "/" + (function ? function : "") + ": " + (msg ? msg : "");
  // Errors end in a SolverError that carries the message; warnings go to the log sink.
  if (code < 0) P->last_message = m;
  else if (P->log) P->log(LogLevel::warning, "SUNDIALS " + m);
}
// M, C and K refilled on the union of their patterns (P.Mu, P.Cu, P.Ku), so that the Jacobian
// [c_j I, −I; K, c_j M + C] is filled entry by entry without searching.
void on_union_pattern(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, Problem& P) {
  SparseMatrix pattern = M.cwiseAbs() + C.cwiseAbs() + K.cwiseAbs();
  pattern.makeCompressed();
  for (Index k = 0; k < pattern.nonZeros(); ++k) pattern.valuePtr()[k] = 0.0;
  P.Mu = pattern + M;
  P.Cu = pattern + C;
  P.Ku = pattern + K;
  P.Mu.makeCompressed(), P.Cu.makeCompressed(), P.Ku.makeCompressed();
  if (P.Mu.nonZeros() != pattern.nonZeros() || P.Cu.nonZeros() != pattern.nonZeros() ||
      P.Ku.nonZeros() != pattern.nonZeros())
    throw SolverError("IDA: internal error: matrices do not share the union pattern");
}

// The system's load discontinuities inside (eps_t, t_end), sorted, those closer than eps_t merged.
std::vector<double> stop_times(const SecondOrderSystem& sys, double t_end, double eps_t) {
  std::vector<double> events = sys.discontinuities(t_end);
  std::sort(events.begin(), events.end());
  events.erase(std::remove_if(events.begin(), events.end(), [&](double e) { return !(e > eps_t && e < t_end); }),
               events.end());
  events.erase(std::unique(events.begin(), events.end(), [&](double a, double b) { return b - a <= eps_t; }),
               events.end());
  return events;
}

}  // namespace

Summary ida(const SecondOrderSystem& sys, const TimeGrid& grid, const IdaOptions& opt, const StepObserver& observe) {
  const auto wall0 = std::chrono::steady_clock::now();
  require_valid(grid, "IDA");
  require_valid(opt, "IDA");
  const double t_end = grid.t_end, dt_out = grid.dt;
  Problem P;
  P.sys = &sys;
  P.n = sys.n_dofs();
  P.log = opt.log;
  const Index n = P.n;
  const SparseMatrix &M = sys.mass(), &C = sys.damping(), &K = sys.stiffness();
  detail::require_square_system(M, C, K, "IDA");
  on_union_pattern(M, C, K, P);
  P.f = Vector::Zero(n);
  Eigen::SimplicialLDLT<SparseMatrix> lm(M);
  if (lm.info() != Eigen::Success) throw SolverError("IDA: mass matrix is not positive definite");

  SUNContext raw_ctx = nullptr;
  if (SUNContext_Create(nullptr, &raw_ctx) != 0) throw SolverError("IDA: SUNContext_Create failed");
  ContextPtr ctx(raw_ctx);
  VectorPtr yy(check_ptr(N_VNew_Serial(2 * n, ctx.get()), "N_VNew_Serial"));
  VectorPtr yp(check_ptr(N_VNew_Serial(2 * n, ctx.get()), "N_VNew_Serial"));
  VectorPtr avtol(check_ptr(N_VNew_Serial(2 * n, ctx.get()), "N_VNew_Serial"));
  for (N_Vector v : {yy.get(), yp.get(), avtol.get()}) sun::use_fast_ops(v);
  Eigen::Map<Vector> y(N_VGetArrayPointer(yy.get()), 2 * n), ydot(N_VGetArrayPointer(yp.get()), 2 * n);
  Eigen::Map<Vector> at(N_VGetArrayPointer(avtol.get()), 2 * n);
  at.head(n).setConstant(opt.atol_disp);
  at.tail(n).setConstant(opt.atol_vel);

  // Consistent start (from rest) at t: u̇ = v, v̇ = M⁻¹(f(t⁺) − C v − K u).
  const double eps_t = 1e-9 * std::max(1.0, t_end);
  auto consistent = [&](double t_plus) {
    P.f.setZero();
    sys.force(t_plus, P.f);
    ydot.head(n) = y.tail(n);
    ydot.tail(n) = lm.solve(P.f - C * y.tail(n) - K * y.head(n));
  };
  y.setZero();
  consistent(0.0);

  std::unique_ptr<void, IdaMemDeleter> mem(check_ptr(IDACreate(ctx.get()), "IDACreate"));
  void* ida_mem = mem.get();
  check(IDASetErrHandlerFn(ida_mem, error_handler, &P), "IDASetErrHandlerFn");
  check(IDAInit(ida_mem, residual, 0.0, yy.get(), yp.get()), "IDAInit");
  check(IDASVtolerances(ida_mem, opt.rtol, avtol.get()), "IDASVtolerances");
  check(IDASetUserData(ida_mem, &P), "IDASetUserData");
  check(IDASetMaxOrd(ida_mem, opt.max_order), "IDASetMaxOrd");
  check(IDASetMaxNumSteps(ida_mem, opt.max_steps_per_output), "IDASetMaxNumSteps");
  if (opt.max_step > 0.0) check(IDASetMaxStep(ida_mem, opt.max_step), "IDASetMaxStep");
  const sunindextype nnz = 2 * n + 2 * P.Ku.nonZeros();
  MatrixPtr J(check_ptr(SUNSparseMatrix(2 * n, 2 * n, nnz, CSC_MAT, ctx.get()), "SUNSparseMatrix"));
  make_pattern(P, J.get());
  SolverPtr LS(check_ptr(SUNLinSol_KLU(yy.get(), J.get(), ctx.get()), "SUNLinSol_KLU"));
  check(IDASetLinearSolver(ida_mem, LS.get(), J.get()), "IDASetLinearSolver");
  check(IDASetJacFn(ida_mem, jacobian), "IDASetJacFn");

  const std::vector<double> events = stop_times(sys, t_end, eps_t);
  std::size_t next_event = 0;

  Summary s;
  s.kernel = Kernel::ida;
  Vector u(n), v(n), a(n);
  auto emit = [&](Index k, double t) {
    u = y.head(n), v = y.tail(n), a = ydot.tail(n);
    if (!u.allFinite()) throw SolverError("IDA: state became non-finite at t = " + short_num(t) + " s");
    if (observe) observe(k, t, u, v, a);
  };
  auto solve_to = [&](double tout, double tstop) {
    check(IDASetStopTime(ida_mem, tstop), "IDASetStopTime");
    realtype tret = 0.0;
    const int flag = IDASolve(ida_mem, tout, &tret, yy.get(), yp.get(), IDA_NORMAL);
    if (P.error) std::rethrow_exception(P.error);
    if (flag < 0)
      throw SolverError("IDA failed at t = " + short_num(tret) + " s (" + flag_name(flag) + ")" +
                        (P.last_message.empty() ? "" : ": " + P.last_message));
    return tret;
  };

  emit(0, 0.0);
  const Index n_out = grid.n_steps();
  double t_now = 0.0;
  for (Index k = 1; k <= n_out; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
    const double tout = std::min(k * dt_out, t_end + 0.5 * dt_out);
    // Cross every discontinuity before tout: stop exactly there and restart consistently.
    while (next_event < events.size() && events[next_event] <= tout - eps_t) {
      const double te = events[next_event++];
      if (te > t_now) t_now = solve_to(te, te);
      consistent(te + eps_t);
      sun::add_counters(ida_mem, s);  // IDAReInit zeroes them
      check(IDAReInit(ida_mem, te, yy.get(), yp.get()), "IDAReInit");
      ++s.n_restarts;
    }
    const double tstop = next_event < events.size() ? events[next_event] : std::max(t_end, tout) + dt_out;
    t_now = solve_to(tout, tstop);
    emit(k, k * dt_out);
  }
  sun::add_counters(ida_mem, s);
  s.n_samples = n_out + 1;
  s.n_dofs = n;
  s.t_reached = n_out * dt_out;
  s.stop_reason = "t_end reached";
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return s;
}

}  // namespace viaduct::solve
