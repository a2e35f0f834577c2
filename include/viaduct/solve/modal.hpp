#pragma once
/// \file Modal superposition of a SecondOrderSystem: a truncated eigenbasis, one exact
/// per-step solution of each modal equation for piecewise-linear loads, and an optional
/// static (mode-acceleration) correction of displacements.
///
/// Theory (docs/accuracy.md): with u ≈ Φ q, Φᵀ M Φ = I, Φᵀ K Φ = Ω², the reduced equations are
/// q̈ + Φᵀ C Φ q̇ + Ω² q = Φᵀ f(t). When Φᵀ C Φ is diagonal (Rayleigh or modal damping: "classical")
/// every mode is a damped oscillator solved exactly per step (augmented 4×4 matrix exponential).
/// When it is not (the track's discrete dashpots couple the modes, often strongly) the reduced
/// first-order system is diagonalised instead — complex modes — and each complex coordinate is
/// solved exactly per step; the coupling is never dropped. Between two samples the load is taken
/// linear, so the scheme has no stability limit and no period error; the only time-discretisation
/// error is that interpolation. The static correction adds the quasi-static response of the
/// truncated modes to displacements: u = Φ q + (K⁻¹ − Φ Ω⁻² Φᵀ) f.

#include <array>
#include <complex>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "viaduct/core/contact_path.hpp"
#include "viaduct/solve/options.hpp"
#include "viaduct/solve/second_order_system.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve {


/// Called at t = 0 and after every step with the outputs (one entry per Functional):
/// disp = y(t) (static correction included when enabled), acc = ÿ(t) from the modes.
using OutputObserver = std::function<void(Index step, double t, const Vector& disp, const Vector& acc)>;

/// Loads that project themselves onto a ModalReduction (faster than nodal entries when the
/// projection can be tabulated, e.g. moving axles). Stateful: called with non-decreasing t.
class ModalForce {
 public:
  virtual ~ModalForce() = default;
  /// Writes the load channels p = Lᵀ f(t) (ModalReduction::load_rows(), n_channels values) and,
  /// when `g` is not null (static correction), g = (K⁻¹ cⱼ)ᵀ f(t) (one value per output). When
  /// p2/g2 are not null (only if has_second_derivative()), also the same of f̈(t). Must not
  /// allocate.
  virtual void project(double t, double* p, double* g, double* p2, double* g2) = 0;
  /// True when project() can give f̈: the static correction then also corrects accelerations
  /// by the quasi-static acceleration of the dropped modes, (K⁻¹ − Φ Ω⁻² Φᵀ) f̈.
  virtual bool has_second_derivative() const { return false; }
};

/// A modal model of (M, C, K) for a fixed set of outputs. Built once (it solves K for the static
/// correction), then integrate() may be called concurrently for any number of load cases.
class ModalReduction {
 public:
  /// shapes: n_dofs × n_modes eigenvectors of K φ = ω² M φ, or any M- and K-orthogonal Ritz
  /// basis such as damping_enriched_basis() (any scaling: they are mass-normalised here);
  /// omega [rad/s] >= 0 their circular (Ritz) frequencies. static_correction
  /// needs K non-singular. Throws InputError for inconsistent sizes, a zero mode or a
  /// non-finite value, SolverError when K cannot be factored for the correction.
  ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                 const Matrix& shapes, const Vector& omega, const std::vector<Functional>& outputs,
                 bool static_correction);
  /// The same for the coupled vehicle kernels (Integrator::coupled_coordinates() == modal): the
  /// structure in its modes, the vehicles physical, the wheels touching `contact_dofs` (a
  /// structure's load path, each DOF once). Keeps the real mass-normalised modes (shapes()) and
  /// the reduced matrices (coupled_matrices(): I, Φᵀ C Φ in full — discrete dashpots stay coupled,
  /// the coupled kernels integrate it as it is —, Ω²); no load channels and no complex coordinates
  /// (integrate() refuses it). With the static correction, besides flexibility_rows() (the one
  /// static correction of the outputs), the dropped modes' flexibility R = K⁻¹ − Φ Ω⁻² Φᵀ between
  /// the contact DOFs (contact_residual(), dense: the caller bounds their number) and from them to
  /// the outputs (contact_output_residual()). Throws as the other constructor does.
  ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                 const Matrix& shapes, const Vector& omega, const std::vector<Functional>& outputs,
                 bool static_correction, const std::vector<Index>& contact_dofs);

  Index n_modes() const { return omega_.size(); }
  Index n_dofs() const { return n_dofs_; }
  const Vector& omega() const { return omega_; }  ///< [rad/s]
  const Vector& zeta() const { return zeta_; }    ///< [-] per mode
  bool static_correction() const { return static_correction_; }
  /// Largest |(Φᵀ C Φ)ᵢⱼ| / sqrt(cᵢᵢ cⱼⱼ) over i ≠ j (0 for proportional damping).
  double max_damping_coupling() const { return max_coupling_; }
  /// True when the damping couples the modes and complex modes are integrated.
  bool complex_modes() const { return complex_; }

  /// Integrates from rest on `grid` with the loads of `sys` (its matrices are not used: they must
  /// be the ones this reduction was built from). Allocation-free per step. Summary::wall_s:
  /// integration only (the reduction is built beforehand).
  Summary integrate(const SecondOrderSystem& sys, const TimeGrid& grid, const ModalOptions& opt,
                    const OutputObserver& observe) const;
  /// The same with loads that project themselves.
  Summary integrate(ModalForce& force, const TimeGrid& grid, const ModalOptions& opt,
                    const OutputObserver& observe) const;

  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// Load channels, row-major n_dofs × n_channels: channel values are Lᵀ f. Classical damping:
  /// the mass-normalised mode shapes (p = Φᵀ f). Complex modes: real and imaginary parts of the
  /// inputs of the kept complex coordinates.
  const RowMatrix& load_rows() const { return load_rows_; }
  Index n_channels() const { return load_rows_.cols(); }
  /// Static-correction flexibilities, row-major n_dofs × n_outputs (empty without correction).
  const RowMatrix& flexibility_rows() const { return out_flex_rows_; }
  Index n_outputs() const { return out_shape_.rows(); }
  /// Classical modes: the outputs of the mass-normalised modes, row-major n_outputs × n_modes
  /// (y = S q), and the same divided by ω² (the modes' share of the static response, S Ω⁻²).
  const RowMatrix& output_rows() const { return out_rows_; }
  const RowMatrix& output_static_rows() const { return out_static_rows_; }
  /// Weights W (n_outputs × n_channels) such that W p is the kept coordinates' share of the
  /// static response (S Ω⁻² for classical modes, Re(S_c u) for complex ones), p the load channels.
  Matrix static_channel_weights() const;

  /// Complex modes (complex_modes()): one coordinate per conjugate pair or real mode, ẏ_k = λ_k y_k
  /// + u_k with u_k = p[c] + i p[c + 1] for a pair (p[c] alone for a real one), c = channel[k],
  /// p the load channels. Outputs of the coordinates: deflection Re Σ_k disp_jk y_k, acceleration
  /// Re Σ_k acc_jk (λ_k y_k + u_k); the rows are weighted (2 for a pair, which stands for its
  /// conjugate too). The static correction comes on top (static_channel_weights()).
  struct ComplexForm {
    std::vector<std::complex<double>> lambda;
    std::vector<Index> channel;
    std::vector<bool> pair;
    Eigen::MatrixXcd disp, acc;  ///< n_outputs × n_coordinates, weighted
  };
  ComplexForm complex_form() const;

  /// The mass-normalised real modes, n_dofs × n_modes (Φᵀ M Φ = I), as the reduction uses them.
  const Matrix& shapes() const { return shapes_; }

  /// Built for the coupled vehicle kernels (the constructor with contact DOFs).
  bool coupled() const { return coupled_; }
  /// The reduced matrices the coupled kernels integrate (coupled() only): M = I, C = Φᵀ C Φ in
  /// full (symmetrised against rounding: classical damping leaves it diagonal), K = Ω².
  struct CoupledMatrices {
    SparseMatrix M, C, K;
  };
  const CoupledMatrices& coupled_matrices() const { return coupled_matrices_; }
  /// Coupled: the index of DOF d among the contact DOFs (its row in contact_residual() and
  /// contact_output_residual() with the static correction), or -1 when d is not one (or out of
  /// range, or the reduction is not coupled).
  Index contact_slot(Index d) const {
    return d >= 0 && static_cast<std::size_t>(d) < contact_slot_.size() ? contact_slot_[static_cast<std::size_t>(d)] : -1;
  }
  /// R = K⁻¹ − Φ Ω⁻² Φᵀ between the contact DOFs (n_contact², symmetric) and from them to each
  /// output (n_contact × n_outputs: rows of flexibility_rows() less the kept modes' share); empty
  /// without the static correction.
  const Matrix& contact_residual() const { return contact_residual_; }
  const Matrix& contact_output_residual() const { return contact_output_residual_; }

 private:
  ModalReduction(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K, const Matrix& shapes,
                 const Vector& omega, const std::vector<Functional>& outputs, bool static_correction,
                 const std::vector<Index>* contact_dofs);
  // Parts of the constructor: the damped (complex) basis from the modal damping matrix Cm, and
  // the static correction's flexibility rows K⁻¹ cⱼᵀ of the outputs.
  void build_complex_basis(const Matrix& phi, const Matrix& Cm, const Vector& omega);
  void build_static_correction(const SparseMatrix& K, const std::vector<Functional>& outputs,
                               const std::vector<Index>* contact_dofs);
  Summary integrate_complex(ModalForce& force, const TimeGrid& grid, const ModalOptions& opt,
                            const OutputObserver& observe) const;
  RowMatrix load_rows_;  // n × n_channels
  Vector omega_, zeta_;
  bool complex_ = false;
  // Complex modes: kept coordinates (one per conjugate pair, plus real ones).
  using CVector = Eigen::VectorXcd;
  using CMatrix = Eigen::MatrixXcd;
  CVector lambda_;       // eigenvalues
  Vector weight_;        // 2 for a conjugate pair, 1 for a real coordinate
  std::vector<Index> channel_;  // first load channel of each coordinate (re, then im if complex)
  CMatrix c_disp_, c_acc_, c_static_;  // n_out × n_kept output rows
  Matrix out_shape_, out_static_;  // n_out × m: outputs of the modes, and the same / ω²
  RowMatrix out_rows_, out_static_rows_;  // the same, row-major for the step loop
  RowMatrix out_flex_rows_;  // n × n_out: K⁻¹ cⱼᵀ (empty without static correction)
  bool static_correction_ = false;
  double max_coupling_ = 0.0;
  Index n_dofs_ = 0;
  Matrix shapes_;  // n × m, mass-normalised
  // Coupled vehicle kernels only.
  bool coupled_ = false;
  CoupledMatrices coupled_matrices_;
  std::vector<Index> contact_slot_;  // per DOF: row in the contact residuals, or -1
  Matrix contact_residual_, contact_output_residual_;
};

/// The contacts of `full` (a path of the structure's DOFs; it and `r` must outlive the result)
/// in the modal coordinates of `r` (built for the coupled kernels): each rail point's weights on
/// the modes and, with r's static correction, the dropped modes' flexibility between the
/// `n_wheels` wheels (ContactPath::residual_flexibility; InputError when a wheel touches a DOF
/// that is not one of r's contact DOFs).
std::unique_ptr<ContactPath> modal_contacts(const ContactPath& full, const ModalReduction& r, std::size_t n_wheels);

/// A Ritz basis that carries non-proportional damping past a truncated set of modes.
/// With discrete dashpots (a track's pads and ballast) the low complex modes of (M, C, K) are
/// not in the span of the low undamped modes Φ: to first order in C, complex mode j gains
/// iωⱼ R C φⱼ with R = K⁻¹ − Φ Ω⁻² Φᵀ, the flexibility of the dropped modes. Appends `blocks`
/// Krylov blocks (R C)ᵏ Φ, k = 1..blocks (M-orthonormalised; a vector whose remainder after
/// orthogonalisation is below 1e-8 of ‖K⁻¹ C b‖_M is dropped), then solves the Rayleigh–Ritz problem on the
/// whole basis: the modes Φ come back unchanged (R C Φ is M- and K-orthogonal to them) followed
/// by the enrichment's Ritz pairs. Returns the shapes (n × m', mass-normalised) and writes their
/// ω [rad/s] to omega_out. With blocks = 0, or classical damping (R C Φ = 0), returns Φ.
/// With max_omega [rad/s] > 0 (0: no limit) the vectors are seeded by as many of the lowest modes
/// as keep every Ritz pair at or below it: sampled every dt, a pair above the Nyquist frequency
/// π/dt aliases into the band of a filter, and dropping pairs from the enrichment unbalances it
/// (measured on Old Guadiana, 180 Hz basis at dt = 1 ms: pairs to 1.3 kHz, 23 % off when kept,
/// 3 % when dropped; seeding fewer modes instead: see docs/accuracy.md). shapes:
/// mass-normalised undamped modes with frequencies omega. Throws SolverError when K cannot be
/// factored.
Matrix damping_enriched_basis(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                              const Matrix& shapes, const Vector& omega, int blocks, Vector* omega_out,
                              double max_omega = 0.0);

/// Exact one-step coefficients of ẏ = λ y + u for u linear over the step (a complex coordinate):
/// y₁ = E y₀ + α u₀ + β u₁, returned as {E, α, β}.
std::array<std::complex<double>, 3> complex_step_coefficients(std::complex<double> lambda, double dt);

/// Exact one-step coefficients of q̈ + 2ζω q̇ + ω² q = p(t), p linear over the step:
/// q₁ = a[0] q₀ + a[1] q̇₀ + a[2] p₀ + a[3] p₁ and q̇₁ = a[4] q₀ + a[5] q̇₀ + a[6] p₀ + a[7] p₁.
std::array<double, 8> exact_step_coefficients(double omega, double zeta, double dt);

}  // namespace viaduct::solve
