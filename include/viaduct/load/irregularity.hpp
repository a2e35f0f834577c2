#pragma once
/// \file Vertical rail irregularities (issue #21 part 3): random profiles from a one-sided
/// spatial power spectral density in a wavelength band, reproducible from a seed, and measured
/// profiles. A profile is what every wheel of a vehicle sees at its position; the vehicle models
/// of issue #21 read it (moving forces, which have no wheel, do not).

#include <cstdint>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::load {

/// The spectra of a track's vertical profile (level) that studies use.
enum class IrregularitySpectrum { fra1, fra2, fra3, fra4, fra5, fra6, german_low, german_high };

/// "fra1" ... "fra6", "german-low", "german-high"; InputError listing the names otherwise.
IrregularitySpectrum irregularity_spectrum(const std::string& name);
const char* spectrum_name(IrregularitySpectrum s);

/// One-sided PSD S(Ω) [m²/(rad/m)] of the vertical profile at spatial circular frequency
/// Ω = 2π/λ [rad/m] > 0, so that the variance is ∫ S dΩ over the band (to confirm against the
/// sources, as Zhai, Vehicle–Track Coupled Dynamics, tabulates them):
/// - US FRA classes 1 (worst) to 6 (best): S = k·A_v·Ω_c² / (Ω²(Ω² + Ω_c²)), k = 0.25,
///   Ω_c = 0.8245 rad/m, A_v = 1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339 cm²·rad/m;
/// - German high-speed spectra, low and high disturbance: S = A_v·Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²)),
///   Ω_c = 0.8246 rad/m, Ω_r = 0.0206 rad/m, A_v = 4.032e-7 and 1.080e-6 m·rad.
/// InputError for Ω not finite and > 0.
double irregularity_psd(IrregularitySpectrum s, double omega);

/// ∫ S dΩ from 2π/λ_max to 2π/λ_min in closed form [m²]: the variance of a profile of that band.
double irregularity_variance(IrregularitySpectrum s, double lambda_min, double lambda_max);

/// A random profile's recipe.
struct ProfileSpec {
  IrregularitySpectrum spectrum = IrregularitySpectrum::fra6;
  double lambda_min = 1.0;    ///< [m] shortest wavelength kept, >= 4 dx
  double lambda_max = 80.0;   ///< [m] longest, > lambda_min, <= length
  double length = 500.0;      ///< [m] > 0; the profile covers [x0, x0 + length]
  double x0 = 0.0;            ///< [m] start along the load path (before the first wheel's entry)
  double dx = 0.05;           ///< [m] sampling step, > 0
  std::uint64_t seed = 1;     ///< same seed, same profile (any platform: std::mt19937_64)
  bool is_valid(std::string* why) const;
};

/// A vertical profile sampled at x0 + k·dx [m], k = 0..n−1 (positive: the rail above its
/// nominal level).
struct RailProfile {
  double x0 = 0.0;  ///< [m]
  double dx = 0.05; ///< [m] > 0
  Vector z;         ///< [m]
  double end() const { return x0 + dx * static_cast<double>(z.size() - 1); }  ///< [m]
  /// The profile at x [m] (cubic Hermite between samples, slopes by central differences: smooth
  /// enough for a wheel's acceleration); InputError outside [x0, end()].
  double at(double x) const;
  /// Its first and second derivatives d/dx [-] and d²/dx² [1/m] at x, of the same cubics (the
  /// slope is continuous, the curvature jumps at the samples); InputError outside [x0, end()].
  void slopes(double x, double& dz, double& d2z) const;
};

/// Harmonic superposition on the period P = n·dx ≥ length (n a power of two): z(x) =
/// Σₖ aₖ·cos(Ωₖ(x − x0) + φₖ), Ωₖ = k·ΔΩ, ΔΩ = 2π/P, aₖ = √(2·∫S dΩ) over harmonic k's cell
/// [Ωₖ − ΔΩ/2, Ωₖ + ΔΩ/2] clipped to the band (√(2·S(Ωₖ)·ΔΩ) inside it, to O(ΔΩ²)), phases φₖ
/// uniform in [0, 2π) drawn from the seed, one per harmonic in order. Over a full period its
/// variance is irregularity_variance() exactly. InputError for an invalid spec.
RailProfile random_profile(const ProfileSpec& spec);

}  // namespace viaduct::load
