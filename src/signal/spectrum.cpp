#include "viaduct/signal/spectrum.hpp"

#include <algorithm>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::signal {

Vector rfft_frequencies(Index n, double fs_hz) {
  Vector f(n / 2 + 1);
  for (Index k = 0; k < f.size(); ++k) f[k] = static_cast<double>(k) * fs_hz / static_cast<double>(n);
  return f;
}

int overflow_exponent(const Vector& x) {
  const double peak = x.size() ? x.cwiseAbs().maxCoeff() : 0.0;
  // At least -1022: 2^1022 is the largest power of two a subnormal peak can be scaled by in one
  // factor (2^1074 is not a double).
  return (peak > 1e100 || (peak > 0.0 && peak < 1e-100)) && std::isfinite(peak) ? std::max(std::ilogb(peak), -1022) : 0;
}

Window window_of(const std::string& name, const std::string& key) {
  if (name == "hann") return Window::hann;
  if (name == "rectangular" || name == "boxcar") return Window::rectangular;
  throw InputError(key + " must be hann or rectangular, got '" + name + "'");
}

Detrend detrend_of(const std::string& name, const std::string& key) {
  if (name == "constant") return Detrend::constant;
  if (name == "linear") return Detrend::linear;
  if (name == "none") return Detrend::none;
  throw InputError(key + " must be constant, linear or none, got '" + name + "'");
}

Vector make_window(Window w, Index n) {
  if (n < 1) throw InputError("window length must be >= 1");
  Vector v(n);
  for (Index k = 0; k < n; ++k)
    v[k] = w == Window::rectangular ? 1.0 : 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(k) / static_cast<double>(n));
  return v;
}

namespace {

void check_record(const Vector& x, double fs_hz, const char* what) {
  require_positive(fs_hz, "sampling rate [Hz]");
  if (x.size() == 0) throw InputError(std::string(what) + ": empty record");
  if (!x.allFinite()) throw InputError(std::string(what) + ": the record holds NaN or infinite samples");
}

// Removes the mean or the least-squares line in place.
void remove_trend(Vector& s, Detrend d) {
  if (d == Detrend::none) return;
  const Index n = s.size();
  if (d == Detrend::constant) {
    s.array() -= s.mean();
    return;
  }
  // linear: fit a + b (j - jm)
  const double jm = 0.5 * static_cast<double>(n - 1);
  double sxx = 0.0, sxy = 0.0;
  const double mean = s.mean();
  for (Index j = 0; j < n; ++j) {
    const double dj = static_cast<double>(j) - jm;
    sxx += dj * dj;
    sxy += dj * (s[j] - mean);
  }
  const double b = sxx > 0.0 ? sxy / sxx : 0.0;
  for (Index j = 0; j < n; ++j) s[j] -= mean + b * (static_cast<double>(j) - jm);
}

// Averaged scaled cross products conj(X) Y over Welch segments (x == y allowed).
Csd welch_cross(const Vector& x, const Vector& y, double fs_hz, const WelchOptions& o) {
  std::string why;
  if (!o.is_valid(x.size(), &why)) throw InputError("Welch: " + why);
  const Index nseg = o.nperseg;
  const Index nover = o.noverlap < 0 ? nseg / 2 : o.noverlap;
  const Index step = nseg - nover;
  const Index n_segments = (x.size() - nover) / step;
  const Vector w = make_window(o.window, nseg);
  const double scale = 1.0 / (fs_hz * w.squaredNorm());
  const bool same = &x == &y;
  Csd out;
  out.frequency_hz = rfft_frequencies(nseg, fs_hz);
  out.density = ComplexVector::Zero(nseg / 2 + 1);
  Vector sx(nseg), sy(nseg);
  for (Index s = 0; s < n_segments; ++s) {
    sx = x.segment(s * step, nseg);
    remove_trend(sx, o.detrend);
    const ComplexVector X = rfft(sx.cwiseProduct(w));
    if (same) {
      out.density += X.cwiseAbs2().cast<std::complex<double>>();
    } else {
      sy = y.segment(s * step, nseg);
      remove_trend(sy, o.detrend);
      const ComplexVector Y = rfft(sy.cwiseProduct(w));
      out.density += X.conjugate().cwiseProduct(Y);
    }
  }
  out.density *= scale / static_cast<double>(n_segments);
  // One-sided: double every bin but DC and (even nperseg) Nyquist.
  const Index last = nseg % 2 == 0 ? out.density.size() - 1 : out.density.size();
  for (Index k = 1; k < last; ++k) out.density[k] *= 2.0;
  out.n_segments = n_segments;
  return out;
}

}  // namespace

bool WelchOptions::is_valid(Index n_samples, std::string* why) const {
  OptionsCheck c("WelchOptions", why);
  return c.require(nperseg >= 2, "nperseg", static_cast<double>(nperseg), "nperseg >= 2") &&
         c.require(nperseg <= n_samples, "nperseg", static_cast<double>(nperseg),
                   "nperseg <= the record's " + std::to_string(n_samples) + " samples") &&
         c.require(noverlap < nperseg && noverlap >= -1, "noverlap", static_cast<double>(noverlap),
                   "noverlap in [0, nperseg) (-1: nperseg/2)");
}

AmplitudeSpectrum amplitude_spectrum(const Vector& x, double fs_hz, Window w) {
  check_record(x, fs_hz, "amplitude spectrum");
  // One sample has no spectrum (and a one-point Hann window sums to 0: NaN amplitudes).
  if (x.size() < 2) throw InputError("amplitude spectrum: at least 2 samples are needed, got " + std::to_string(x.size()));
  const Vector win = make_window(w, x.size());
  const ComplexVector X = rfft(x.cwiseProduct(win));
  AmplitudeSpectrum a;
  a.frequency_hz = rfft_frequencies(x.size(), fs_hz);
  a.amplitude = X.cwiseAbs() * (2.0 / win.sum());
  a.amplitude[0] *= 0.5;
  if (x.size() % 2 == 0) a.amplitude[a.amplitude.size() - 1] *= 0.5;
  return a;
}

Psd welch(const Vector& x, double fs_hz, const WelchOptions& o) {
  check_record(x, fs_hz, "Welch PSD");
  if (const int e = overflow_exponent(x)) {
    Psd p = welch(std::ldexp(1.0, -e) * x, fs_hz, o);
    p.density *= std::ldexp(1.0, e);
    p.density *= std::ldexp(1.0, e);
    if (!p.density.allFinite())
      throw InputError("Welch PSD: the density of samples up to " + format_number(x.cwiseAbs().maxCoeff(), 3) +
                       " overflows a double: give the record in a larger unit");
    return p;
  }
  const Csd c = welch_cross(x, x, fs_hz, o);
  return Psd{c.frequency_hz, c.density.real(), c.n_segments};
}

Csd csd(const Vector& x, const Vector& y, double fs_hz, const WelchOptions& o) {
  check_record(x, fs_hz, "cross spectral density");
  check_record(y, fs_hz, "cross spectral density");
  if (x.size() != y.size())
    throw InputError("cross spectral density: records differ in length (" + std::to_string(x.size()) + " and " +
                     std::to_string(y.size()) + " samples)");
  const int ex = overflow_exponent(x), ey = overflow_exponent(y);
  if (ex == 0 && ey == 0) return welch_cross(x, y, fs_hz, o);
  Csd c = welch_cross(std::ldexp(1.0, -ex) * x, std::ldexp(1.0, -ey) * y, fs_hz, o);
  c.density *= std::ldexp(1.0, ex);
  c.density *= std::ldexp(1.0, ey);
  if (!c.density.allFinite())
    throw InputError("cross spectral density: it overflows a double for these samples: give the records in larger units");
  return c;
}

}  // namespace viaduct::signal
