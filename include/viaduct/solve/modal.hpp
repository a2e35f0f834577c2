#pragma once
/// \file Modal superposition of a SecondOrderSystem: a truncated eigenbasis, one exact
/// per-step solution of each modal equation for piecewise-linear loads, and an optional
/// static (mode-acceleration) correction of displacements.
///
/// Theory (docs/accuracy.md): with u ≈ Φ q, Φᵀ M Φ = I, Φᵀ K Φ = Ω², and ζᵢ = φᵢᵀ C φᵢ / (2 ωᵢ)
/// (the off-diagonal terms of Φᵀ C Φ are dropped: exact for Rayleigh or modal damping, an
/// approximation for the track's discrete dashpots, measured by `viaduct tradeoff`), every mode
/// obeys q̈ᵢ + 2ζᵢωᵢ q̇ᵢ + ωᵢ² qᵢ = φᵢᵀ f(t). Between two samples the modal load is taken linear
/// and the equation is solved exactly (augmented 4×4 matrix exponential), so the scheme has no
/// stability limit and no period error; the only time-discretisation error is the linear
/// interpolation of the load. The static correction adds the quasi-static response of the
/// truncated modes to displacements: u = Φ q + (K⁻¹ − Φ Ω⁻² Φᵀ) f.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::solve {

/// A recorded quantity y = Σ weight[k] · u[dof[k]] (e.g. deflection at a point of a beam).
struct Functional {
  std::vector<Index> dof;
  std::vector<double> weight;
};

struct ModalOptions {
  double dt = 1e-3;    ///< [s] output and load-sampling interval, > 0
  double t_end = 1.0;  ///< [s] last time, > 0 (steps: ceil(t_end/dt))
  /// Throw SolverError when the modal state stops being finite.
  bool check_finite = true;
  bool is_valid(std::string* why) const;
};

struct ModalSummary {
  Index n_steps = 0;
  Index n_modes = 0;
  Index n_dofs = 0;
  double t_reached = 0.0;  ///< [s]
  double wall_s = 0.0;     ///< [s] integration only (the reduction is built beforehand)
  std::string stop_reason;
};

/// Called at t = 0 and after every step with the outputs (one entry per Functional):
/// disp = y(t) (static correction included when enabled), acc = ÿ(t) from the modes.
using OutputObserver = std::function<void(Index step, double t, const Vector& disp, const Vector& acc)>;

/// Loads that project themselves onto a ModalReduction (faster than nodal entries when the
/// projection can be tabulated, e.g. moving axles). Stateful: called with non-decreasing t.
class ModalForce {
 public:
  virtual ~ModalForce() = default;
  /// Writes p = Φᵀ f(t) (n_modes values) and, when `g` is not null (static correction),
  /// g = (K⁻¹ cⱼ)ᵀ f(t) (one value per output). Must not allocate.
  virtual void project(double t, double* p, double* g) = 0;
};

/// A modal model of (M, C, K) for a fixed set of outputs. Built once (it solves K for the static
/// correction), then integrate() may be called concurrently for any number of load cases.
class ModalReduction {
 public:
  /// shapes: n_dofs × n_modes eigenvectors of K φ = ω² M φ (any scaling: they are
  /// mass-normalised here); omega [rad/s] >= 0 their circular frequencies. static_correction
  /// needs K non-singular. Throws InputError for inconsistent sizes, a zero mode or a
  /// non-finite value, SolverError when K cannot be factored for the correction.
  ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                 const Matrix& shapes, const Vector& omega, const std::vector<Functional>& outputs,
                 bool static_correction);

  Index n_modes() const { return omega_.size(); }
  Index n_dofs() const { return phi_rows_.rows(); }
  const Vector& omega() const { return omega_; }  ///< [rad/s]
  const Vector& zeta() const { return zeta_; }    ///< [-] per mode
  bool static_correction() const { return static_correction_; }
  /// Largest |(Φᵀ C Φ)ᵢⱼ| / sqrt(cᵢᵢ cⱼⱼ) over i ≠ j: the damping coupling that is neglected
  /// (0 for proportional damping).
  double max_damping_coupling() const { return max_coupling_; }

  /// Integrates from rest with the loads of `sys` (its matrices are not used: they must be the
  /// ones this reduction was built from). Allocation-free per step.
  ModalSummary integrate(const SecondOrderSystem& sys, const ModalOptions& opt,
                         const OutputObserver& observe) const;
  /// The same with loads that project themselves.
  ModalSummary integrate(ModalForce& force, const ModalOptions& opt, const OutputObserver& observe) const;

  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// Mass-normalised mode shapes, row-major n_dofs × n_modes (row d: every mode at DOF d).
  const RowMatrix& shape_rows() const { return phi_rows_; }
  /// Static-correction flexibilities, row-major n_dofs × n_outputs (empty without correction).
  const RowMatrix& flexibility_rows() const { return out_flex_rows_; }
  Index n_outputs() const { return out_shape_.rows(); }

 private:
  RowMatrix phi_rows_;  // n × m
  Vector omega_, zeta_;
  Matrix out_shape_, out_static_;  // n_out × m: outputs of the modes, and the same / ω²
  RowMatrix out_rows_, out_static_rows_;  // the same, row-major for the step loop
  RowMatrix out_flex_rows_;  // n × n_out: K⁻¹ cⱼᵀ (empty without static correction)
  bool static_correction_ = false;
  double max_coupling_ = 0.0;
};

/// Exact one-step coefficients of q̈ + 2ζω q̇ + ω² q = p(t), p linear over the step:
/// q₁ = a[0] q₀ + a[1] q̇₀ + a[2] p₀ + a[3] p₁ and q̇₁ = a[4] q₀ + a[5] q̇₀ + a[6] p₀ + a[7] p₁.
std::array<double, 8> exact_step_coefficients(double omega, double zeta, double dt);

}  // namespace viaduct::solve
