#include "viaduct/signal/resample.hpp"

#include <cmath>
#include <deque>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::signal {

namespace {
Vector antialias(const Vector& x, double fs, double edge_hz) {
  Cheby1Spec s;
  s.order = 8;
  s.ripple_db = 0.05;
  s.band = BandType::lowpass;
  s.high_hz = edge_hz;
  return sosfiltfilt(cheby1(s, fs), x);
}
void check(const Vector& x, const char* what) {
  if (x.size() == 0) throw InputError(std::string(what) + ": empty signal");
  if (!x.allFinite()) throw InputError(std::string(what) + ": NaN or infinite samples");
}
void check_window(Index w, Index n, const char* what) {
  if (w < 1 || w % 2 == 0) throw InputError(std::string(what) + ": window must be an odd number of samples >= 1");
  if (w > 2 * n) throw InputError(std::string(what) + ": window longer than twice the signal");
}
}  // namespace

Vector decimate(const Vector& x, int q) {
  check(x, "decimate");
  if (q < 2) throw InputError("decimate: factor must be >= 2, got " + std::to_string(q));
  if (q >= x.size())
    throw InputError("decimate: factor " + std::to_string(q) + " leaves fewer than two of the " + std::to_string(x.size()) + " samples");
  // Normalised edge 0.8/q of Nyquist, i.e. 0.8·(fs/2)/q with fs = 2.
  const Vector y = antialias(x, 2.0, 0.8 / q);
  Vector out((x.size() + q - 1) / q);
  for (Index i = 0; i < out.size(); ++i) out[i] = y[i * q];
  if (!out.allFinite()) throw SolverError("decimate: the anti-alias filter is not accurate at factor " + std::to_string(q));
  return out;
}

Vector resample(const Vector& x, double fs_in, double fs_out) {
  check(x, "resample");
  require_positive(fs_in, "input sampling rate [Hz]");
  require_positive(fs_out, "output sampling rate [Hz]");
  const Vector y = fs_out < fs_in ? antialias(x, fs_in, 0.8 * fs_out / 2) : x;
  const double duration = static_cast<double>(x.size() - 1) / fs_in;
  // Counted in floating point before it becomes a size: at least two samples, at most
  // kMaxResampled (2 GiB of doubles per channel).
  const double n_out = std::floor(duration * fs_out + 1e-9) + 1.0;
  if (!(n_out >= 2.0))
    throw InputError("resample: " + format_number(fs_out, 6) + " Hz leaves fewer than two samples over the record's " +
                     format_number(duration, 6) + " s");
  if (!(n_out <= kMaxResampled))
    throw InputError("resample: " + format_number(fs_out, 6) + " Hz would make " + format_number(n_out, 3) +
                     " samples per channel, more than the limit of " + format_number(kMaxResampled, 3));
  const auto n = static_cast<Index>(n_out);
  Vector out(n);
  for (Index j = 0; j < n; ++j) {
    const double s = static_cast<double>(j) / fs_out * fs_in;
    const auto i = std::min<Index>(static_cast<Index>(std::floor(s)), x.size() - 1);
    const double w = s - static_cast<double>(i);
    out[j] = (i + 1 < x.size()) ? (1 - w) * y[i] + w * y[i + 1] : y[i];
  }
  if (!out.allFinite())
    throw SolverError("resample: the anti-alias filter is not accurate at " + format_number(fs_out / fs_in, 3) + " times the rate");
  return out;
}

Vector running_rms(const Vector& x, Index window) {
  check(x, "running RMS");
  check_window(window, x.size(), "running RMS");
  if (const int e = overflow_exponent(x)) return std::ldexp(1.0, e) * running_rms(std::ldexp(1.0, -e) * x, window);
  const Index h = window / 2, n = x.size();
  Vector c(n + 1);  // prefix sums of x²
  c[0] = 0.0;
  for (Index i = 0; i < n; ++i) c[i + 1] = c[i] + x[i] * x[i];
  Vector out(n);
  for (Index i = 0; i < n; ++i) {
    const Index a = std::max<Index>(0, i - h), b = std::min<Index>(n, i + h + 1);
    out[i] = std::sqrt(std::max(0.0, (c[b] - c[a]) / static_cast<double>(b - a)));
  }
  return out;
}

Vector maxabs_envelope(const Vector& x, Index window) {
  check(x, "max-abs envelope");
  check_window(window, x.size(), "max-abs envelope");
  const Index h = window / 2, n = x.size();
  Vector out(n);
  std::deque<Index> q;  // indices of decreasing |x| (monotone queue): O(n)
  Index next = 0;
  for (Index i = 0; i < n; ++i) {
    const Index b = std::min<Index>(n - 1, i + h);
    for (; next <= b; ++next) {
      while (!q.empty() && std::abs(x[q.back()]) <= std::abs(x[next])) q.pop_back();
      q.push_back(next);
    }
    while (q.front() < i - h) q.pop_front();
    out[i] = std::abs(x[q.front()]);
  }
  return out;
}

Eigen::VectorXcd analytic_signal(const Vector& x) {
  check(x, "analytic signal");
  if (const int e = overflow_exponent(x)) return std::ldexp(1.0, e) * analytic_signal(std::ldexp(1.0, -e) * x);
  const Index n = x.size();
  const ComplexVector X = rfft(x);
  Eigen::VectorXcd Z = Eigen::VectorXcd::Zero(n);
  Z[0] = X[0];
  for (Index k = 1; k < X.size(); ++k) Z[k] = (n % 2 == 0 && k == n / 2) ? X[k] : 2.0 * X[k];
  return ifft(Z);
}

Vector hilbert_envelope(const Vector& x) { return analytic_signal(x).cwiseAbs(); }

}  // namespace viaduct::signal
