#pragma once
/// \file Modal parameters from FRFs: peak picking with half-power damping, single-mode circle
/// fit, multi-mode least-squares complex-frequency (LSCF) poles with a stabilization diagram,
/// least-squares frequency-domain (LSFD) residues for mode shapes, and the modal assurance
/// criterion.
///
/// Viscous damping throughout: a mode is the pole pair λ = −ζω ± iω√(1−ζ²); frequencies are
/// undamped natural frequencies f = |λ|/2π. Peak picking and the circle fit work on mobility
/// (velocity/force), where an isolated viscous mode peaks exactly at f and its half-power points
/// satisfy f₂ − f₁ = 2ζf; any FRF is converted first (FrfQuantity).

#include <limits>
#include <string>
#include <vector>

#include "viaduct/ident/frf.hpp"

namespace viaduct::ident {

struct IdentifiedMode {
  double frequency_hz = 0.0;   ///< [Hz] undamped natural frequency
  double damping_ratio = 0.0;  ///< [-] of critical; NaN when the method could not tell
  /// Shape across the FRF's responses (receptance residues), scaled so that the largest entry
  /// is 1: real for classically damped modes. Empty when not estimated.
  ComplexVector shape;
  Index response = -1;         ///< channel used by single-channel methods (-1: all)
  std::string note;            ///< why damping is NaN, or a warning; empty when all went well
};

// ---------------------------------------------------------------------------------------------
// Peak picking

struct PeakPickingOptions {
  double f_min_hz = 0.0;                                       ///< [Hz] band searched
  double f_max_hz = std::numeric_limits<double>::infinity();   ///< [Hz]
  double min_relative_prominence = 0.05;  ///< [-] peaks of the indicator below this fraction of its maximum are ignored, [0, 1)
  std::size_t max_modes = 0;              ///< keep the most prominent ones (0: all)
  bool is_valid(std::string* why) const;
};

/// Peaks of the mode indicator Σ_o |Y_o|/max|Y_o| (Y: mobility); at each, every channel that
/// peaks there gives a natural frequency (parabola through three lines) and half-power damping
/// (|Y| = peak/√2, linear interpolation; NaN when a crossing lies beyond the neighbouring
/// minimum, i.e. the modes overlap); the channel with the median damping is reported, with a
/// note when the channels disagree by more than 30 % (closely spaced modes add on some sensors
/// and cancel on others). The shape is the receptance at that line across the channels. Resolution-limited: a bin width of Δf biases f by up to
/// Δf/2 and damping by (Δf/f)/ζ relatively.
std::vector<IdentifiedMode> peak_picking(const Frf& frf, const PeakPickingOptions& o = {});

// ---------------------------------------------------------------------------------------------
// Circle fit

struct CircleFitOptions {
  /// [-] points within f·(1 ± half_band·ζ_guess) of the guess are fitted (2: ±2 half-power
  /// bandwidths, about 250° of the circle); widened to min_points when there are fewer.
  double half_band = 2.0;
  Index min_points = 5;  ///< >= 4
  bool is_valid(std::string* why) const;
};

/// Fits a circle to the mobility of channel `response` near a mode (guess from peak picking),
/// then the angle law θ(ω) = θ₀ − 2·atan((ω² − ωₙ²)/(2ζωₙω)) of a viscous mode (Gauss–Newton in
/// θ₀, ωₙ, ζ). Exact for an isolated viscous mode, insensitive to a constant offset from other
/// modes. InputError when fewer than min_points lie on the FRF or the fit does not converge.
IdentifiedMode circle_fit(const Frf& frf, Index response, double f_guess_hz, double zeta_guess,
                          const CircleFitOptions& o = {});

// ---------------------------------------------------------------------------------------------
// LSCF with stabilization diagram

struct LscfOptions {
  double f_min_hz = 0.0;                                      ///< [Hz] band fitted (clipped to the FRF)
  double f_max_hz = std::numeric_limits<double>::infinity();  ///< [Hz]
  int max_order = 40;        ///< [-] largest denominator order (poles), even, 4..200
  double tol_frequency = 0.01;  ///< [-] relative change of f against the previous order for "stable"
  double tol_damping = 0.05;    ///< [-] relative change of ζ for "stable"
  double max_damping = 0.2;     ///< [-] poles with ζ outside (0, max_damping] are not physical
  double cluster_tol = 0.005;   ///< [-] stable poles closer than this (relative f) form one mode
  /// [-] a cluster is a mode when it holds stable poles from at least this fraction of the orders
  double min_cluster_fraction = 0.3;
  /// Refine the selected poles by nonlinear least squares on the FRFs themselves (see
  /// refine_poles): removes the bias of the linearised LSCF equations at high damping and noise.
  bool refine = true;
  /// [-] with refine: each mode is also tried as two poles; the split is kept when the residual
  /// sum of squares falls by more than this fraction (0: no test), in [0, 1)
  double split_gain = 0.2;
  /// [-] ... and by more than this share of the FRFs' weighted energy (1e-4: −40 dB), >= 0
  double split_min_share = 1e-4;
  bool is_valid(std::string* why) const;
};

enum class PoleStatus { new_pole, stable_frequency, stable };

struct StabilizationPole {
  int order = 0;
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
  PoleStatus status = PoleStatus::new_pole;
};

struct LscfResult {
  std::vector<StabilizationPole> poles;  ///< every physical pole of every order
  std::vector<int> orders;               ///< orders computed
  std::vector<IdentifiedMode> modes;     ///< selected from the diagram, refined (LscfOptions::refine), shapes by LSFD
  std::vector<IdentifiedMode> diagram_modes;  ///< the same before refinement (cluster medians)
  double f_min_hz = 0.0, f_max_hz = 0.0; ///< band actually fitted
};

/// Common-denominator LSCF on the z-domain basis zₖ = e^{iωₖTs}, Ts = 1/(2 f_max), each response
/// weighted by the inverse of its rms magnitude; denominator orders 2, 4, … max_order; poles
/// compared order to order; stable poles clustered into modes (median f and ζ of the cluster;
/// a cluster with k poles of one order is split into k modes, so closely spaced modes stay apart);
/// refined by refine_poles() (LscfOptions::refine) and tested for a hidden second mode
/// (LscfOptions::split_gain); shapes from an LSFD fit with those poles plus lower and upper
/// residuals.
/// InputError when the band holds fewer than max_order + 2 frequencies.
LscfResult lscf(const Frf& frf, const LscfOptions& o = {});

// ---------------------------------------------------------------------------------------------
// The whole fit (viaduct modal-fit)

struct ModalFitOptions {
  double f_min_hz = 0.0;                 ///< [Hz] band fitted
  double f_max_hz = 1e9;                 ///< [Hz]
  double min_relative_prominence = 0.05; ///< peak picking (PeakPickingOptions)
  int max_order = 40;                    ///< LSCF (LscfOptions)
  double cluster_tol = 0.005;            ///< LSCF
  bool refine = true;                    ///< LSCF
};

struct ModalFitResult {
  std::vector<IdentifiedMode> peak_picking;
  std::vector<IdentifiedMode> circle_fit;  ///< one per peak with a finite damping whose fit succeeded
  LscfResult lscf;
  std::vector<std::string> warnings;       ///< "circle fit at F Hz: why" for each fit that failed
};

/// Peak picking on the band, a circle fit started from each peak, and LSCF with its
/// stabilization diagram: the three estimates viaduct modal-fit reports side by side.
ModalFitResult modal_fit(const Frf& frf, const ModalFitOptions& o);

/// Residues (receptance) of the poles of `modes` fitted to every response of `frf` over
/// [f_min, f_max], with lower (mass-like) and upper (stiffness-like) residuals; fills each
/// mode's shape (normalised as IdentifiedMode::shape says).
void fit_shapes(const Frf& frf, double f_min_hz, double f_max_hz, std::vector<IdentifiedMode>& modes);

/// Refines the poles of `modes` (frequency and damping) by Levenberg–Marquardt on the output
/// error of all responses over [f_min, f_max], each in its measured quantity and weighted by
/// 1/rms: variable projection, the residues and residual terms solved linearly for each trial
/// set of poles. The least-squares (maximum-likelihood for white noise of equal variance per
/// response) counterpart of LSCF's linearised equations. Updates frequency, damping and shapes;
/// returns the ratio of final to initial residual norm (<= 1).
double refine_poles(const Frf& frf, double f_min_hz, double f_max_hz, std::vector<IdentifiedMode>& modes);

/// Tries each mode as two poles (at f(1 ∓ max(ζ, 0.2 %)), refined with all the others by
/// refine_poles); keeps the pair when the residual sum of squares falls by more than
/// o.split_gain of itself and by more than o.split_min_share of the FRFs' weighted energy, and
/// both poles are physical (ζ in (0, o.max_damping]), in the band and apart. Returns the number
/// of modes split. Two modes closer than the stabilization diagram resolves (high damping,
/// noise) leave a misfit of the order of the FRF; a single mode gains from a second pole only
/// what it can fit of noise or small systematic errors.
std::size_t split_hidden_modes(const Frf& frf, double f_min_hz, double f_max_hz, std::vector<IdentifiedMode>& modes,
                               const LscfOptions& o = {});

/// Modal assurance criterion |aᴴb|²/((aᴴa)(bᴴb)) of every column of a against every column of b
/// (same number of rows). 1: the same shape; 0: orthogonal. Zero columns give 0.
Matrix mac(const ComplexMatrix& a, const ComplexMatrix& b);

}  // namespace viaduct::ident
