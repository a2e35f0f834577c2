#include "viaduct/load/irregularity.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::load {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct SpectrumParams {
  const char* name;
  bool fra;
  double a;  // [m·rad] (FRA: k·A_v with k = 0.25, A_v converted from cm²·rad/m)
};

constexpr SpectrumParams kSpectra[] = {
    {"fra1", true, 0.25 * 1.2107e-4},  {"fra2", true, 0.25 * 1.0181e-4}, {"fra3", true, 0.25 * 0.6816e-4},
    {"fra4", true, 0.25 * 0.5376e-4},  {"fra5", true, 0.25 * 0.2095e-4}, {"fra6", true, 0.25 * 0.0339e-4},
    {"german-low", false, 4.032e-7}, {"german-high", false, 1.080e-6},
};
constexpr double kFraOmegaC = 0.8245;     // [rad/m]
constexpr double kGermanOmegaC = 0.8246;  // [rad/m]
constexpr double kGermanOmegaR = 0.0206;  // [rad/m]

const SpectrumParams& params(IrregularitySpectrum s) { return kSpectra[static_cast<int>(s)]; }

// The antiderivative of S at Ω.
double psd_integral(IrregularitySpectrum s, double w) {
  const SpectrumParams& p = params(s);
  if (p.fra)  // S = a·(1/Ω² − 1/(Ω² + Ωc²))
    return p.a * (-1.0 / w - std::atan(w / kFraOmegaC) / kFraOmegaC);
  const double c2 = kGermanOmegaC * kGermanOmegaC, r2 = kGermanOmegaR * kGermanOmegaR;
  // S = a·Ωc²/(Ωc² − Ωr²)·(1/(Ω² + Ωr²) − 1/(Ω² + Ωc²))
  return p.a * c2 / (c2 - r2) * (std::atan(w / kGermanOmegaR) / kGermanOmegaR - std::atan(w / kGermanOmegaC) / kGermanOmegaC);
}

}  // namespace

IrregularitySpectrum irregularity_spectrum(const std::string& name) {
  for (int i = 0; i < 8; ++i)
    if (name == kSpectra[i].name) return static_cast<IrregularitySpectrum>(i);
  throw InputError("unknown irregularity spectrum '" + name + "' (known: fra1 ... fra6 (FRA classes, 6 the best track), german-low, german-high)");
}

const char* spectrum_name(IrregularitySpectrum s) { return params(s).name; }

double irregularity_psd(IrregularitySpectrum s, double omega) {
  if (!(omega > 0) || !std::isfinite(omega)) throw InputError("irregularity_psd: the spatial frequency must be > 0 [rad/m]");
  const SpectrumParams& p = params(s);
  const double w2 = omega * omega;
  if (p.fra) return p.a * kFraOmegaC * kFraOmegaC / (w2 * (w2 + kFraOmegaC * kFraOmegaC));
  return p.a * kGermanOmegaC * kGermanOmegaC / ((w2 + kGermanOmegaR * kGermanOmegaR) * (w2 + kGermanOmegaC * kGermanOmegaC));
}

double irregularity_variance(IrregularitySpectrum s, double lambda_min, double lambda_max) {
  if (!(lambda_min > 0) || !(lambda_max > lambda_min) || !std::isfinite(lambda_max))
    throw InputError("irregularity_variance: need 0 < lambda_min < lambda_max");
  return psd_integral(s, 2 * kPi / lambda_min) - psd_integral(s, 2 * kPi / lambda_max);
}

bool ProfileSpec::is_valid(std::string* why) const {
  OptionsCheck c("ProfileSpec", why);
  return c.require(dx > 0, "dx", dx, "dx > 0") && c.require(length > 0, "length", length, "length > 0") &&
         c.require(length / dx <= 1e8, "length", length, "length / dx <= 1e8 samples") &&
         c.require(lambda_min >= 4 * dx, "lambda_min", lambda_min, "lambda_min >= 4 dx (four samples a wave at least)") &&
         c.require(lambda_max > lambda_min, "lambda_max", lambda_max, "lambda_max > lambda_min") &&
         c.require(lambda_max <= length, "lambda_max", lambda_max, "lambda_max <= length (the profile holds its longest wave)") &&
         c.require(std::isfinite(x0), "x0", x0, "x0 finite");
}

namespace {
// The cubic of RailProfile::at() around x: the sample i before x, the fraction t in [0, 1] and the
// central-difference slopes m0, m1 at samples i and i + 1 (one-sided at the ends), per sample step.
struct ProfileCubic {
  Index i = 0;
  double t = 0.0, m0 = 0.0, m1 = 0.0;
};
ProfileCubic profile_cubic(const RailProfile& p, double x) {
  const double s = (x - p.x0) / p.dx;
  const auto n = p.z.size();
  if (!(s >= -1e-9) || s > static_cast<double>(n - 1) + 1e-9 || n < 2)
    throw InputError("rail profile: x = " + format_number(x) + " m is outside the profile [" + format_number(p.x0) + ", " +
                     format_number(p.end()) + "] m");
  ProfileCubic c;
  c.i = std::min<Index>(static_cast<Index>(std::floor(std::max(s, 0.0))), n - 2);
  c.t = std::clamp(s - static_cast<double>(c.i), 0.0, 1.0);
  const Vector& z = p.z;
  auto slope = [&](Index k) { return k == 0 ? z[1] - z[0] : k == n - 1 ? z[n - 1] - z[n - 2] : 0.5 * (z[k + 1] - z[k - 1]); };
  c.m0 = slope(c.i), c.m1 = slope(c.i + 1);
  return c;
}
}  // namespace

double RailProfile::at(double x) const {
  // Cubic Hermite with central-difference slopes (one-sided at the ends), per sample step.
  const ProfileCubic c = profile_cubic(*this, x);
  const double t = c.t, t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * z[c.i] + (t3 - 2 * t2 + t) * c.m0 + (-2 * t3 + 3 * t2) * z[c.i + 1] + (t3 - t2) * c.m1;
}

void RailProfile::slopes(double x, double& dz, double& d2z) const {
  const ProfileCubic c = profile_cubic(*this, x);
  const double t = c.t, t2 = t * t;
  const Index i = c.i;
  // d/dt and d²/dt² of at()'s cubic, then per metre (t = (x − x0)/dx − i).
  const double d1 = (6 * t2 - 6 * t) * z[i] + (3 * t2 - 4 * t + 1) * c.m0 + (-6 * t2 + 6 * t) * z[i + 1] + (3 * t2 - 2 * t) * c.m1;
  const double d2 = (12 * t - 6) * z[i] + (6 * t - 4) * c.m0 + (-12 * t + 6) * z[i + 1] + (6 * t - 2) * c.m1;
  dz = d1 / dx;
  d2z = d2 / (dx * dx);
}

RailProfile random_profile(const ProfileSpec& spec) {
  std::string why;
  if (!spec.is_valid(&why)) throw InputError("rail irregularity: " + why);
  const auto m = static_cast<Index>(std::ceil(spec.length / spec.dx - 1e-9)) + 1;  // samples
  Index n = 1;
  while (n < m) n *= 2;  // the period, in samples
  const double dw = 2 * kPi / (static_cast<double>(n) * spec.dx);
  const double w_lo = 2 * kPi / spec.lambda_max, w_hi = 2 * kPi / spec.lambda_min;
  RailProfile p;
  p.x0 = spec.x0;
  p.dx = spec.dx;
  p.z = Vector::Zero(m);
  // One phase per harmonic k = 1 .. n/2 in order, whatever the band: two bands from one seed
  // share their common harmonics.
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> phase(0.0, 2 * kPi);
  for (Index k = 1; k <= n / 2; ++k) {
    const double phi = phase(rng);
    // Harmonic k carries the band's variance over its cell [Ωk − ΔΩ/2, Ωk + ΔΩ/2] (clipped to
    // the band): the cells tile the band, so the variance is the band's integral exactly.
    const double w = static_cast<double>(k) * dw;
    const double lo = std::max(w - 0.5 * dw, w_lo), hi = std::min(w + 0.5 * dw, w_hi);
    if (!(hi > lo)) continue;
    const double a = std::sqrt(2 * (psd_integral(spec.spectrum, hi) - psd_integral(spec.spectrum, lo)));
    // Σ over samples by rotation: c_j = a·e^{i(φ + k·2π·j/n)}, renewed every 1024 samples
    // against the rounding of the product.
    const std::complex<double> step = std::polar(1.0, 2 * kPi * static_cast<double>(k) / static_cast<double>(n));
    std::complex<double> c;
    for (Index j = 0; j < m; ++j) {
      if (j % 1024 == 0)
        c = std::polar(a, phi + 2 * kPi * static_cast<double>((k * j) % n) / static_cast<double>(n));
      p.z[j] += c.real();
      c *= step;
    }
  }
  return p;
}

}  // namespace viaduct::load
