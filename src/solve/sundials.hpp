#pragma once
// RAII handles and return-code checks for SUNDIALS IDA (private to src/solve: ida.cpp and
// coupled_ida.cpp share them). Every failure becomes a SolverError naming the call and IDA's flag.

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <type_traits>

#include <Eigen/Core>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve::sun {

// RAII for the C handles.
struct ContextDeleter {
  void operator()(SUNContext c) const { SUNContext_Free(&c); }
};
struct IdaMemDeleter {
  void operator()(void* m) const { IDAFree(&m); }
};
struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct SolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
using ContextPtr = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter>;
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using MatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using SolverPtr = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, SolverDeleter>;

// IDAGetReturnFlagName returns a malloc'ed string the caller frees.
inline std::string flag_name(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string s = name ? name : std::to_string(flag);
  std::free(name);
  return s;
}

inline void check(int flag, const char* what) {
  if (flag < 0) throw SolverError(std::string("IDA: ") + what + " failed (" + flag_name(flag) + ")");
}
template <class T>
inline T* check_ptr(T* p, const char* what) {
  if (!p) throw SolverError(std::string("IDA: ") + what + " failed (out of memory?)");
  return p;
}

// The serial vector's hot operations on Eigen maps. Debian's SUNDIALS 6.4 is built without
// optimisation, so its own loops cost more than the residuals of a small system; the ops table of
// a vector is copied to its clones, so setting it on the vectors IDA is given reaches all of IDA's.
namespace fast {
using Map = Eigen::Map<Eigen::VectorXd>;
inline Map vec(N_Vector v) { return {NV_DATA_S(v), static_cast<Eigen::Index>(NV_LENGTH_S(v))}; }
inline void linearsum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) { vec(z) = a * vec(x) + b * vec(y); }
inline void constant(realtype c, N_Vector z) { vec(z).setConstant(c); }
inline void prod(N_Vector x, N_Vector y, N_Vector z) { vec(z) = vec(x).cwiseProduct(vec(y)); }
inline void div(N_Vector x, N_Vector y, N_Vector z) { vec(z) = vec(x).cwiseQuotient(vec(y)); }
inline void scale(realtype c, N_Vector x, N_Vector z) { vec(z) = c * vec(x); }
inline void abs(N_Vector x, N_Vector z) { vec(z) = vec(x).cwiseAbs(); }
inline void inv(N_Vector x, N_Vector z) { vec(z) = vec(x).cwiseInverse(); }
inline void addconst(N_Vector x, realtype b, N_Vector z) { vec(z) = vec(x).array() + b; }
inline realtype dotprod(N_Vector x, N_Vector y) { return vec(x).dot(vec(y)); }
inline realtype maxnorm(N_Vector x) { return vec(x).size() ? vec(x).cwiseAbs().maxCoeff() : 0.0; }
inline realtype wsqrsum(N_Vector x, N_Vector w) { return vec(x).cwiseProduct(vec(w)).squaredNorm(); }
inline realtype wrmsnorm(N_Vector x, N_Vector w) {
  const auto n = static_cast<double>(NV_LENGTH_S(x));
  return n > 0 ? std::sqrt(wsqrsum(x, w) / n) : 0.0;
}
// z = Σ c_i X_i; z may be X[0].
inline int linearcombination(int nv, realtype* c, N_Vector* X, N_Vector z) {
  Map zm = vec(z);
  if (nv < 1) return -1;
  if (z == X[0]) zm *= c[0];
  else zm = c[0] * vec(X[0]);
  for (int i = 1; i < nv; ++i) zm += c[i] * vec(X[i]);
  return 0;
}
// Z_i = a_i x + Y_i.
inline int scaleaddmulti(int nv, realtype* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  for (int i = 0; i < nv; ++i) vec(Z[i]) = a[i] * vec(x) + vec(Y[i]);
  return 0;
}
}  // namespace fast

/// Sets the fast operations on a serial vector (its clones inherit them).
inline void use_fast_ops(N_Vector v) {
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = fast::linearsum;
  o->nvconst = fast::constant;
  o->nvprod = fast::prod;
  o->nvdiv = fast::div;
  o->nvscale = fast::scale;
  o->nvabs = fast::abs;
  o->nvinv = fast::inv;
  o->nvaddconst = fast::addconst;
  o->nvdotprod = fast::dotprod;
  o->nvmaxnorm = fast::maxnorm;
  o->nvwrmsnorm = fast::wrmsnorm;
  o->nvwsqrsumlocal = fast::wsqrsum;
  o->nvlinearcombination = fast::linearcombination;
  o->nvscaleaddmulti = fast::scaleaddmulti;
}

/// Adds IDA's counters since its last (re)initialisation to the summary: IDAReInit zeroes them,
/// so a kernel that restarts calls this before each IDAReInit and once at the end.
inline void add_counters(void* ida_mem, Summary& s) {
  long v = 0;
  check(IDAGetNumSteps(ida_mem, &v), "IDAGetNumSteps");
  s.n_steps += v;
  check(IDAGetNumResEvals(ida_mem, &v), "IDAGetNumResEvals");
  s.n_residuals += v;
  check(IDAGetNumJacEvals(ida_mem, &v), "IDAGetNumJacEvals");
  s.n_factorisations += v;
  check(IDAGetNumErrTestFails(ida_mem, &v), "IDAGetNumErrTestFails");
  s.n_rejected_steps += v;
  check(IDAGetNumNonlinSolvConvFails(ida_mem, &v), "IDAGetNumNonlinSolvConvFails");
  s.n_nonlinear_failures += v;
  int order = 0;
  check(IDAGetLastOrder(ida_mem, &order), "IDAGetLastOrder");
  if (order > 0) s.last_order = order;
}

}  // namespace viaduct::solve::sun
