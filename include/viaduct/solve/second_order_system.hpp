#pragma once
/// \file The one abstraction integrators see: M a + C v + K u = f(t) with constant sparse
/// symmetric M (positive definite), C and K (positive semi-definite).

#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::solve {

/// A recorded quantity y = Σ weight[k] · u[dof[k]] (e.g. deflection at a point of a beam).
struct Functional {
  std::vector<Index> dof;
  std::vector<double> weight;
};

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual const SparseMatrix& mass() const = 0;
  virtual const SparseMatrix& damping() const = 0;
  virtual const SparseMatrix& stiffness() const = 0;
  Index n_dofs() const { return mass().rows(); }
  /// Writes f(t) into f (already sized n_dofs; overwrite every entry). Must not allocate:
  /// it is called once per time step.
  virtual void force(double t, Vector& f) const = 0;
  /// Optional sparse form of f(t): clears `out`, appends the nonzero entries and returns true;
  /// returns false when the system does not offer it (integrators then use force()). Must not
  /// allocate once `out` has grown to its working size.
  /// Times in (0, t_end) where f(t) jumps (adaptive integrators stop and restart there).
  virtual std::vector<double> discontinuities(double t_end) const {
    (void)t_end;
    return {};
  }
  virtual bool force_entries(double t, SparseForce& out) const {
    (void)t;
    (void)out;
    return false;
  }
};

}  // namespace viaduct::solve
