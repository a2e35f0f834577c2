#include "viaduct/study/speed.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::study {

SpeedEstimate speed_from_spectrum(const Vector& x, double fs_hz, double d, double v_min, double v_max, int n_harmonics) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_positive(d, "characteristic distance d [m]");
  require_positive(v_min, "lowest speed [m/s]");
  if (!(v_max > v_min) || !std::isfinite(v_max)) throw InputError("speed range: need v_max > v_min");
  if (n_harmonics < 1) throw InputError("n_harmonics must be >= 1");
  if (n_harmonics * v_max / d >= fs_hz / 2)
    throw InputError("speed search: harmonic " + std::to_string(n_harmonics) + " of " + format_number(v_max / d, 6) +
                     " Hz exceeds the Nyquist frequency " + format_number(fs_hz / 2, 6) + " Hz");
  if (x.size() < 16 || !x.allFinite()) throw InputError("speed search: need at least 16 finite samples");
  // Hann window, zero-padded 8x (next power of two): the spectrum is sampled finely enough to
  // place each line's maximum well inside its main lobe.
  Index n_pad = 1;
  while (n_pad < 8 * x.size()) n_pad *= 2;
  Vector xp = Vector::Zero(n_pad);
  xp.head(x.size()) = (x.array() - x.mean()).matrix().cwiseProduct(signal::make_window(signal::Window::hann, x.size()));
  const Vector A = signal::rfft(xp).cwiseAbs();
  const double df = fs_hz / static_cast<double>(n_pad);
  const double df_record = fs_hz / static_cast<double>(x.size());
  auto amp = [&](double f) {
    const double s = f / df;
    const auto i = static_cast<Index>(std::floor(s));
    if (i + 1 >= A.size()) return 0.0;
    return A[i] + (s - static_cast<double>(i)) * (A[i + 1] - A[i]);
  };
  // Sum of logarithms (a product): every harmonic must be present, so one strong structural
  // resonance cannot win alone (a plain sum locks onto it).
  const double floor = 1e-12 * (A.maxCoeff() > 0 ? A.maxCoeff() : 1.0);
  auto score = [&](double v) {
    double sum = 0.0;
    for (int k = 1; k <= n_harmonics; ++k) sum += std::log(amp(k * v / d) + floor);
    return sum;
  };
  // Scan at a tenth of the finest resolution (one bin at the highest harmonic).
  const double dv = 0.1 * d * df / n_harmonics;
  const auto n = static_cast<Index>(std::ceil((v_max - v_min) / dv)) + 1;
  if (n > 50000000) throw InputError("speed search: range too wide for the record's resolution");
  Index best = 0;
  double best_s = -std::numeric_limits<double>::infinity();
  for (Index i = 0; i < n; ++i) {
    const double s = score(v_min + static_cast<double>(i) * dv);
    if (s > best_s) {
      best_s = s;
      best = i;
    }
  }
  double v = v_min + static_cast<double>(best) * dv;
  if (best > 0 && best + 1 < n) {
    const double a = score(v - dv), b = best_s, c = score(v + dv);
    const double den = a - 2 * b + c;
    if (den < 0) v += std::clamp(0.5 * (a - c) / den, -0.5, 0.5) * dv;
  }
  SpeedEstimate e;
  e.speed = v;
  e.frequency_hz = v / d;
  e.uncertainty = d * df_record / n_harmonics;
  e.n_used = n_harmonics;
  return e;
}

SpeedEstimate speed_from_peaks(const Vector& x, double fs_hz, double d, double min_interval_s) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_positive(d, "characteristic distance d [m]");
  require_positive(min_interval_s, "minimum interval between axle peaks [s]");
  signal::PeakOptions o;
  o.min_distance = std::max<Index>(1, static_cast<Index>(std::ceil(min_interval_s * fs_hz)));
  // Axle passages are the prominent peaks; a free-vibration tail adds many small ones that
  // would otherwise set the median interval.
  auto all = signal::find_peaks(x, o);
  double top = 0.0;
  for (const auto& p : all) top = std::max(top, p.prominence);
  std::vector<signal::Peak> peaks;
  for (const auto& p : all)
    if (p.prominence >= 0.1 * top) peaks.push_back(p);
  if (peaks.size() < 3) throw InputError("axle passages: fewer than 3 peaks found");
  std::vector<double> dt;
  for (std::size_t i = 1; i < peaks.size(); ++i) dt.push_back((peaks[i].position - peaks[i - 1].position) / fs_hz);
  std::vector<double> sorted = dt;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double med = sorted[sorted.size() / 2];
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (double t : dt)
    if (std::abs(t - med) <= 0.15 * med) {
      sum += t;
      sum2 += t * t;
      ++n;
    }
  if (n < 2) throw InputError("axle passages: fewer than 2 regular intervals between peaks");
  const double mean = sum / n;
  const double sd = std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)));
  SpeedEstimate e;
  e.speed = d / mean;
  e.uncertainty = e.speed * (sd / std::sqrt(static_cast<double>(n))) / mean;
  e.frequency_hz = 1.0 / mean;
  e.n_used = n;
  return e;
}

}  // namespace viaduct::study
