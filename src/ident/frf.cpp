#include "viaduct/ident/frf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::ident {

namespace {

void check_signal(const Vector& x, const char* what) {
  if (x.size() == 0) throw InputError(std::string(what) + " is empty");
  if (!x.allFinite()) throw InputError(std::string(what) + " holds NaN or infinite samples");
}

void check_force_nonzero(const Vector& f) {
  const double peak = f.cwiseAbs().maxCoeff();
  if (!(peak > 0.0)) throw InputError("the force channel is zero: no FRF can be formed");
  const double mean = f.mean();
  if ((f.array() - mean).abs().maxCoeff() <= 1e-12 * peak)
    throw InputError("the force channel is constant: no dynamic force, no FRF");
}

}  // namespace

int derivative_order(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::receptance: return 0;
    case FrfQuantity::mobility: return 1;
    case FrfQuantity::accelerance: return 2;
  }
  return 0;
}

FrfQuantity quantity_of_unit(const std::string& unit) {
  if (unit == "m") return FrfQuantity::receptance;
  if (unit == "mps") return FrfQuantity::mobility;
  if (unit == "mps2") return FrfQuantity::accelerance;
  throw InputError("response unit '" + unit + "' is not a displacement (m), velocity (mps) or acceleration (mps2)");
}

std::string unit_of_quantity(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::receptance: return "m";
    case FrfQuantity::mobility: return "mps";
    case FrfQuantity::accelerance: return "mps2";
  }
  return "m";
}

void Frf::check(const std::string& what) const {
  const Index n = frequency_hz.size();
  if (n < 2) throw InputError(what + ": an FRF needs at least 2 frequencies");
  if (h.rows() != n) throw InputError(what + ": FRF rows do not match the frequency axis");
  if (h.cols() < 1) throw InputError(what + ": no response");
  if (static_cast<Index>(responses.size()) != h.cols() || static_cast<Index>(quantity.size()) != h.cols())
    throw InputError(what + ": response names or quantities do not match the FRF columns");
  if (coherence.size() != 0 && (coherence.rows() != n || coherence.cols() != h.cols()))
    throw InputError(what + ": coherence size does not match the FRF");
  if (!frequency_hz.allFinite() || !h.allFinite()) throw InputError(what + ": NaN or infinite values");
  for (Index k = 1; k < n; ++k)
    if (!(frequency_hz[k] > frequency_hz[k - 1])) throw InputError(what + ": frequencies must increase strictly");
}

ComplexVector convert(const Vector& frequency_hz, const ComplexVector& h, FrfQuantity from, FrfQuantity to) {
  const int k = derivative_order(to) - derivative_order(from);
  ComplexVector out = h;
  if (k == 0) return out;
  for (Index j = 0; j < h.size(); ++j) {
    const Complex iw(0.0, 2.0 * M_PI * frequency_hz[j]);
    if (k < 0 && !(frequency_hz[j] > 0.0)) throw InputError("FRF conversion needs frequencies > 0");
    out[j] *= std::pow(iw, k);
  }
  return out;
}

WelchFrf welch_frf(const Vector& force, const Matrix& responses, double fs_hz, const signal::WelchOptions& o) {
  check_signal(force, "force");
  require_positive(fs_hz, "sampling rate [Hz]");
  if (responses.cols() < 1) throw InputError("no response channel");
  if (responses.rows() != force.size())
    throw InputError("force and responses differ in length (" + std::to_string(force.size()) + " and " +
                     std::to_string(responses.rows()) + " samples)");
  if (!responses.allFinite()) throw InputError("a response holds NaN or infinite samples");
  check_force_nonzero(force);
  const signal::Psd sff = signal::welch(force, fs_hz, o);
  WelchFrf r;
  r.frequency_hz = sff.frequency_hz;
  r.n_segments = sff.n_segments;
  const Index nf = sff.frequency_hz.size();
  r.h1.resize(nf, responses.cols());
  r.h2.resize(nf, responses.cols());
  r.coherence.resize(nf, responses.cols());
  const double floor_ff = 1e-14 * sff.density.maxCoeff();
  for (Index c = 0; c < responses.cols(); ++c) {
    const Vector y = responses.col(c);
    const signal::Psd saa = signal::welch(y, fs_hz, o);
    const signal::Csd sfa = signal::csd(force, y, fs_hz, o);
    const double floor_aa = 1e-14 * std::max(saa.density.maxCoeff(), 1e-300);
    for (Index k = 0; k < nf; ++k) {
      const double ff = sff.density[k], aa = saa.density[k];
      const Complex fa = sfa.density[k];
      const bool ok_f = ff > floor_ff, ok_a = aa > floor_aa;
      r.h1(k, c) = ok_f ? fa / ff : Complex(0.0);
      r.h2(k, c) = ok_a && std::abs(fa) > 0.0 ? aa / std::conj(fa) : Complex(0.0);
      r.coherence(k, c) = ok_f && ok_a ? std::min(1.0, std::norm(fa) / (ff * aa)) : 0.0;
    }
  }
  return r;
}

// ---------------------------------------------------------------------------------------------

std::vector<SineStep> regular_schedule(double f_start_hz, double f_end_hz, Index n_steps, double dwell_s, double t0_s) {
  require_positive(f_start_hz, "first step frequency [Hz]");
  require_positive(f_end_hz, "last step frequency [Hz]");
  require_positive(dwell_s, "dwell [s]");
  if (n_steps < 1) throw InputError("a stepped-sine schedule needs at least one step");
  if (n_steps == 1 && f_end_hz != f_start_hz)
    throw InputError("one step cannot span two frequencies (give f_end = f_start or more steps)");
  std::vector<SineStep> s;
  for (Index k = 0; k < n_steps; ++k) {
    const double f = n_steps == 1 ? f_start_hz
                                  : f_start_hz + (f_end_hz - f_start_hz) * static_cast<double>(k) / static_cast<double>(n_steps - 1);
    s.push_back({t0_s + dwell_s * static_cast<double>(k), t0_s + dwell_s * static_cast<double>(k + 1), f});
  }
  return s;
}

bool StepDetectionOptions::is_valid(std::string* why) const {
  OptionsCheck c("StepDetectionOptions", why);
  return c.require(min_cycles >= 2.0, "min_cycles", min_cycles, "min_cycles >= 2") &&
         c.require(tolerance > 0.0, "tolerance", tolerance, "tolerance > 0") &&
         c.require(smooth_cycles >= 1 && smooth_cycles % 2 == 1, "smooth_cycles", smooth_cycles,
                   "smooth_cycles odd and >= 1") &&
         c.require(hysteresis > 0.0 && hysteresis < 1.0, "hysteresis", hysteresis, "hysteresis in (0, 1)");
}

std::vector<SineStep> detect_steps(const Vector& force, double fs_hz, double t0_s, const StepDetectionOptions& o) {
  std::string why;
  if (!o.is_valid(&why)) throw InputError("step detection: " + why);
  check_signal(force, "force");
  require_positive(fs_hz, "sampling rate [Hz]");
  check_force_nonzero(force);
  const Vector x = force.array() - force.mean();
  const double h = o.hysteresis * x.cwiseAbs().maxCoeff();
  // Upward zero crossings, each after the force has been below −h (noise cannot double-count).
  std::vector<double> tc;
  bool armed = false;
  for (Index j = 0; j + 1 < x.size(); ++j) {
    if (x[j] < -h) armed = true;
    if (armed && x[j] < 0.0 && x[j + 1] >= 0.0) {
      tc.push_back(t0_s + (static_cast<double>(j) + x[j] / (x[j] - x[j + 1])) / fs_hz);
      armed = false;
    }
  }
  if (tc.size() < 3) throw InputError("step detection: the force has fewer than 2 cycles");
  const std::size_t nc = tc.size() - 1;
  std::vector<double> fc(nc), g(nc);
  for (std::size_t k = 0; k < nc; ++k) fc[k] = 1.0 / (tc[k + 1] - tc[k]);
  const std::size_t half = static_cast<std::size_t>(o.smooth_cycles / 2);
  for (std::size_t k = 0; k < nc; ++k) {
    const std::size_t a = k >= half ? k - half : 0, b = std::min(nc, k + half + 1);
    std::vector<double> w(fc.begin() + static_cast<std::ptrdiff_t>(a), fc.begin() + static_cast<std::ptrdiff_t>(b));
    std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2), w.end());
    g[k] = w[w.size() / 2];
  }
  std::vector<SineStep> steps;
  std::size_t first = 0;
  // The running median and the persistence test place an edge up to half the median window
  // plus two cycles late: each step ends that many cycles early, so that no cycle of the next
  // step is ever fitted (its start is discarded by the settling anyway).
  const std::size_t margin = half + 2;
  auto close = [&](std::size_t end) {  // cycles [first, end)
    end = end > first + margin ? end - margin : first;
    if (static_cast<double>(end - first) < o.min_cycles) return;
    std::vector<double> w(fc.begin() + static_cast<std::ptrdiff_t>(first), fc.begin() + static_cast<std::ptrdiff_t>(end));
    std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2), w.end());
    steps.push_back({tc[first], tc[end], w[w.size() / 2]});
  };
  // A step ends where the smoothed frequency leaves the step's mean so far by more than the
  // tolerance for three cycles running (a true change persists; noise does not).
  double sum = g[0];
  std::size_t count = 1;
  auto off = [&](std::size_t k, double ref) { return std::abs(g[k] - ref) > o.tolerance * ref; };
  for (std::size_t k = 1; k < nc; ++k) {
    const double ref = sum / static_cast<double>(count);
    if (off(k, ref) && (k + 1 >= nc || off(k + 1, ref)) && (k + 2 >= nc || off(k + 2, ref))) {
      close(k);
      first = k;
      sum = 0.0;
      count = 0;
    }
    sum += g[k];
    ++count;
  }
  close(nc);
  if (steps.empty())
    throw InputError("step detection: no steady sine of at least " + std::to_string(o.min_cycles) +
                     " cycles in the force channel: give the schedule with --steps");
  return steps;
}

bool SteppedSineOptions::is_valid(std::string* why) const {
  OptionsCheck c("SteppedSineOptions", why);
  return c.require(settle_cycles >= 0.0, "settle_cycles", settle_cycles, "settle_cycles >= 0") &&
         c.require(settle_s >= 0.0, "settle_s", settle_s, "settle_s >= 0") &&
         c.require(min_cycles >= 2.0, "min_cycles", min_cycles, "min_cycles >= 2") &&
         c.require(n_harmonics >= 1 && n_harmonics <= 20, "n_harmonics", n_harmonics, "n_harmonics in 1..20");
}

Complex fit_sine(const Vector& t, const Vector& x, double frequency_hz, int n_harmonics, double* distortion) {
  const Index n = t.size();
  const int nh = std::max(1, n_harmonics);
  const Index n_par = 1 + 2 * nh;
  if (n < n_par + 2) throw InputError("too few samples for a sine fit");
  const double w = 2.0 * M_PI * frequency_hz;
  Matrix A(n, n_par);
  for (Index j = 0; j < n; ++j) {
    A(j, 0) = 1.0;
    for (int h = 1; h <= nh; ++h) {
      A(j, 2 * h - 1) = std::cos(h * w * t[j]);
      A(j, 2 * h) = std::sin(h * w * t[j]);
    }
  }
  const Vector p = A.colPivHouseholderQr().solve(x);
  const double a = p[1], b = p[2];
  if (distortion) {
    // Everything but offset and fundamental, relative to the fundamental (rms ratio).
    Vector fund(n);
    for (Index j = 0; j < n; ++j) fund[j] = p[0] + a * A(j, 1) + b * A(j, 2);
    const double rest = (x - fund).squaredNorm() / static_cast<double>(n);
    const double fund_ms = 0.5 * (a * a + b * b);
    *distortion = fund_ms > 0.0 ? std::sqrt(rest / fund_ms) : std::numeric_limits<double>::infinity();
  }
  return Complex(a, -b);
}

double refine_sine_frequency(const Vector& t, const Vector& x, double frequency_hz, int n_harmonics) {
  const Index n = t.size();
  const int nh = std::max(1, n_harmonics);
  const Index nl = 1 + 2 * nh;  // offset, then cos/sin of each harmonic
  double w = 2.0 * M_PI * frequency_hz;
  const double tm = 0.5 * (t[0] + t[n - 1]);
  const double span = t[n - 1] - t[0];
  for (int it = 0; it < 8; ++it) {
    Matrix J(n, nl + 1);
    for (Index j = 0; j < n; ++j) {
      const double tj = t[j] - tm;
      J(j, 0) = 1.0;
      for (int h = 1; h <= nh; ++h) {
        J(j, 2 * h - 1) = std::cos(h * w * tj);
        J(j, 2 * h) = std::sin(h * w * tj);
      }
    }
    const Vector p = J.leftCols(nl).colPivHouseholderQr().solve(x);
    for (Index j = 0; j < n; ++j) {
      const double tj = t[j] - tm;
      double d = 0.0;
      for (int h = 1; h <= nh; ++h) d += h * tj * (-p[2 * h - 1] * std::sin(h * w * tj) + p[2 * h] * std::cos(h * w * tj));
      J(j, nl) = d;
    }
    const Vector r = x - J.leftCols(nl) * p;
    const Vector d = J.colPivHouseholderQr().solve(r);
    // Keep the step within a quarter cycle over the record (the Gauss–Newton basin).
    const double max_dw = 0.5 * M_PI / std::max(span, 1e-12);
    const double dw = std::clamp(d[nl], -max_dw, max_dw);
    w += dw;
    if (std::abs(dw) < 1e-12 * w) break;
  }
  return w / (2.0 * M_PI);
}

std::vector<SteppedSinePoint> stepped_sine(const Vector& force, const Matrix& responses, double fs_hz, double t0_s,
                                           const std::vector<SineStep>& schedule, const SteppedSineOptions& o) {
  std::string why;
  if (!o.is_valid(&why)) throw InputError("stepped sine: " + why);
  check_signal(force, "force");
  require_positive(fs_hz, "sampling rate [Hz]");
  if (responses.cols() < 1) throw InputError("no response channel");
  if (responses.rows() != force.size()) throw InputError("force and responses differ in length");
  if (!responses.allFinite()) throw InputError("a response holds NaN or infinite samples");
  if (schedule.empty()) throw InputError("stepped sine: the schedule has no step");
  check_force_nonzero(force);
  const Index n = force.size();
  const double t_last = t0_s + static_cast<double>(n - 1) / fs_hz;
  std::vector<SteppedSinePoint> out;
  for (std::size_t s = 0; s < schedule.size(); ++s) {
    const SineStep& st = schedule[s];
    const std::string tag = "step " + std::to_string(s + 1) + " (" + std::to_string(st.frequency_hz) + " Hz)";
    if (!(st.frequency_hz > 0.0) || !(st.t_end_s > st.t_start_s))
      throw InputError(tag + ": needs frequency > 0 and t_end > t_start");
    if (st.frequency_hz >= 0.5 * fs_hz)
      throw InputError(tag + ": drive frequency at or above the Nyquist frequency " + std::to_string(0.5 * fs_hz) + " Hz");
    if (st.t_start_s < t0_s - 0.5 / fs_hz || st.t_end_s > t_last + 1.5 / fs_hz)
      throw InputError(tag + ": dwell [" + std::to_string(st.t_start_s) + ", " + std::to_string(st.t_end_s) +
                       "] s lies outside the record [" + std::to_string(t0_s) + ", " + std::to_string(t_last) + "] s");
    const double settle = std::max(o.settle_s, o.settle_cycles / st.frequency_hz);
    const double t_from = st.t_start_s + settle;
    const Index j0 = std::max<Index>(0, static_cast<Index>(std::ceil((t_from - t0_s) * fs_hz - 1e-9)));
    const Index j1 = std::min<Index>(n - 1, static_cast<Index>(std::floor((st.t_end_s - t0_s) * fs_hz + 1e-9)) - 1);
    const double n_cycles = static_cast<double>(j1 - j0 + 1) / fs_hz * st.frequency_hz;
    if (j1 <= j0 || n_cycles < o.min_cycles)
      throw InputError(tag + ": " + std::to_string(std::max(0.0, n_cycles)) + " cycles left after settling (" +
                       std::to_string(settle) + " s), at least " + std::to_string(o.min_cycles) +
                       " needed: lengthen the dwell or shorten settle_cycles");
    // Harmonics above Nyquist are left out of the fit.
    const int nh = std::max(1, std::min(o.n_harmonics, static_cast<int>(std::floor(0.5 * fs_hz / st.frequency_hz * 0.999))));
    const Index m = j1 - j0 + 1;
    Vector t(m);
    for (Index j = 0; j < m; ++j) t[j] = static_cast<double>(j0 + j) / fs_hz;  // relative to t0
    const Vector f_seg = force.segment(j0, m);
    SteppedSinePoint p;
    p.frequency_hz = o.refine_frequency ? refine_sine_frequency(t, f_seg, st.frequency_hz, nh) : st.frequency_hz;
    if (std::abs(p.frequency_hz - st.frequency_hz) > 0.05 * st.frequency_hz)
      throw InputError(tag + ": the force's frequency (" + std::to_string(p.frequency_hz) +
                       " Hz) is not the scheduled one: check the schedule against the record");
    p.t_from_s = t0_s + t[0];
    p.t_to_s = t0_s + t[m - 1];
    p.n_cycles = n_cycles;
    p.force = fit_sine(t, f_seg, p.frequency_hz, nh, &p.force_distortion);
    if (!(std::abs(p.force) > 1e-12 * force.cwiseAbs().maxCoeff()) || !(p.force_distortion < 1.0))
      throw InputError(tag + ": the force is not a sine at the scheduled frequency (distortion " +
                       std::to_string(p.force_distortion) + "): check the schedule against the record");
    const Index nr = responses.cols();
    p.response.resize(nr);
    p.h.resize(nr);
    p.response_distortion.resize(nr);
    p.settle_change.resize(nr);
    const Index half = m / 2;
    const Complex fa = fit_sine(t.head(half), f_seg.head(half), p.frequency_hz, 1);
    const Complex fb = fit_sine(t.tail(m - half), f_seg.tail(m - half), p.frequency_hz, 1);
    for (Index c = 0; c < nr; ++c) {
      const Vector y = responses.col(c).segment(j0, m);
      double d = 0.0;
      p.response[c] = fit_sine(t, y, p.frequency_hz, nh, &d);
      p.response_distortion[c] = d;
      p.h[c] = p.response[c] / p.force;
      const Complex ha = fit_sine(t.head(half), y.head(half), p.frequency_hz, 1) / fa;
      const Complex hb = fit_sine(t.tail(m - half), y.tail(m - half), p.frequency_hz, 1) / fb;
      const double mag = std::abs(p.h[c]);
      p.settle_change[c] = mag > 0.0 ? std::abs(ha - hb) / mag : 0.0;
    }
    out.push_back(std::move(p));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

bool SweptSineOptions::is_valid(double fs_hz, std::string* why) const {
  OptionsCheck c("SweptSineOptions", why);
  return c.require(f_min_hz > 0.0, "f_min_hz", f_min_hz, "f_min_hz > 0") &&
         c.require(f_max_hz > f_min_hz, "f_max_hz", f_max_hz, "f_max_hz > f_min_hz") &&
         c.require(f_max_hz < 0.5 * fs_hz, "f_max_hz", f_max_hz,
                   "f_max_hz below the Nyquist frequency " + format_number(0.5 * fs_hz, 6) + " Hz") &&
         c.require(min_force_ratio >= 0.0 && min_force_ratio < 1.0, "min_force_ratio", min_force_ratio,
                   "min_force_ratio in [0, 1)");
}

Frf swept_sine(const Vector& force, const Matrix& responses, double fs_hz, const SweptSineOptions& o) {
  std::string why;
  require_positive(fs_hz, "sampling rate [Hz]");
  if (!o.is_valid(fs_hz, &why)) throw InputError("swept sine: " + why);
  check_signal(force, "force");
  if (responses.cols() < 1) throw InputError("no response channel");
  if (responses.rows() != force.size()) throw InputError("force and responses differ in length");
  if (!responses.allFinite()) throw InputError("a response holds NaN or infinite samples");
  check_force_nonzero(force);
  const Index n = force.size();
  Index nfft = 1;
  while (nfft < 2 * n) nfft *= 2;
  auto padded = [&](const Vector& x) {
    Vector p = Vector::Zero(nfft);
    p.head(n) = x;
    return p;
  };
  const ComplexVector F = signal::rfft(padded(force));
  const Vector freq = signal::rfft_frequencies(nfft, fs_hz);
  std::vector<Index> band;
  for (Index k = 0; k < freq.size(); ++k)
    if (freq[k] >= o.f_min_hz && freq[k] <= o.f_max_hz) band.push_back(k);
  if (band.size() < 2) throw InputError("swept sine: fewer than 2 frequency bins in the band; lengthen the record");
  std::vector<double> mags;
  for (Index k : band) mags.push_back(std::abs(F[k]));
  std::nth_element(mags.begin(), mags.begin() + static_cast<std::ptrdiff_t>(mags.size() / 2), mags.end());
  const double limit = o.min_force_ratio * mags[mags.size() / 2];
  std::vector<Index> kept;
  for (Index k : band)
    if (std::abs(F[k]) > limit && std::abs(F[k]) > 0.0) kept.push_back(k);
  if (kept.size() < 2) throw InputError("swept sine: the force does not excite the band");
  Frf r;
  r.frequency_hz.resize(static_cast<Index>(kept.size()));
  r.h.resize(static_cast<Index>(kept.size()), responses.cols());
  for (std::size_t j = 0; j < kept.size(); ++j) r.frequency_hz[static_cast<Index>(j)] = freq[kept[j]];
  for (Index c = 0; c < responses.cols(); ++c) {
    const ComplexVector Y = signal::rfft(padded(responses.col(c)));
    for (std::size_t j = 0; j < kept.size(); ++j) {
      const Index k = kept[j];
      r.h(static_cast<Index>(j), c) = std::conj(F[k]) * Y[k] / std::norm(F[k]);
    }
  }
  return r;
}

}  // namespace viaduct::ident
