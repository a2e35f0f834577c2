#include "viaduct/ident/decay.hpp"

#include <algorithm>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/resample.hpp"

namespace viaduct::ident {

namespace {

struct Line {
  double slope = 0.0, intercept = 0.0;  ///< y ≈ intercept + slope·(x − x_mean)
  double x_mean = 0.0;
  double at(double x) const { return intercept + slope * (x - x_mean); }
};

// Weighted least-squares line (weights w >= 0; empty w: all 1).
Line fit_line(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& w = {}) {
  Line l;
  const std::size_t n = x.size();
  if (n < 2) return l;
  auto wt = [&](std::size_t i) { return w.empty() ? 1.0 : w[i]; };
  double sw = 0.0, mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i) sw += wt(i), mx += wt(i) * x[i], my += wt(i) * y[i];
  if (!(sw > 0.0)) return l;
  mx /= sw;
  my /= sw;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += wt(i) * (x[i] - mx) * (x[i] - mx);
    sxy += wt(i) * (x[i] - mx) * (y[i] - my);
  }
  l.x_mean = mx;
  l.intercept = my;
  l.slope = sxx > 0.0 ? sxy / sxx : 0.0;
  return l;
}

struct TimedPeak {
  double t = 0.0;
  double value = 0.0;  ///< |x| at the peak
};

std::vector<TimedPeak> peaks_of(const Vector& y, double fs, double t0, double f_hz, bool positive) {
  signal::PeakOptions po;
  po.min_distance = std::max<Index>(1, static_cast<Index>(0.6 * fs / f_hz));
  po.min_height = 0.0;
  const Vector s = positive ? Vector(y) : Vector(-y);
  std::vector<TimedPeak> out;
  for (const auto& p : signal::find_peaks(s, po, signal::Interpolation::parabolic))
    if (p.value > 0.0) out.push_back({t0 + p.position / fs, p.value});
  return out;
}

}  // namespace

bool DecayOptions::is_valid(double fs_hz, std::string* why) const {
  OptionsCheck c("DecayOptions", why);
  return c.require(frequency_hz > 0.0, "frequency_hz", frequency_hz, "frequency_hz (the mode to isolate) > 0") &&
         c.require(band_ratio > 0.0 && band_ratio < 0.9, "band_ratio", band_ratio, "band_ratio in (0, 0.9)") &&
         c.require(filter_order >= 0 && filter_order <= 8, "filter_order", filter_order, "filter_order in 0..8") &&
         c.require(ripple_db > 0.0, "ripple_db", ripple_db, "ripple_db > 0") &&
         c.require(filter_order == 0 || frequency_hz * (1.0 + band_ratio) < 0.5 * fs_hz, "band_ratio", band_ratio,
                   "the band-pass's upper edge frequency_hz (1 + band_ratio) = " +
                       format_number(frequency_hz * (1.0 + band_ratio), 6) + " Hz below the Nyquist frequency " +
                       format_number(0.5 * fs_hz, 6) + " Hz") &&
         c.require(noise_factor >= 1.0, "noise_factor", noise_factor, "noise_factor >= 1") &&
         c.require(skip_cycles >= 0.0, "skip_cycles", skip_cycles, "skip_cycles >= 0") &&
         c.require(min_cycles >= 2.0, "min_cycles", min_cycles, "min_cycles >= 2") &&
         c.require(window_cycles >= 1.0, "window_cycles", window_cycles, "window_cycles >= 1") &&
         c.require(rise_tolerance > 0.0, "rise_tolerance", rise_tolerance, "rise_tolerance > 0");
}

double passage_end_time(double entry_s, double train_length_m, double bridge_length_m, double speed_mps) {
  require_finite(entry_s, "train entry time [s]");
  require_positive(train_length_m, "train length [m]");
  require_positive(bridge_length_m, "bridge length [m]");
  require_positive(speed_mps, "train speed [m/s]");
  return entry_s + (train_length_m + bridge_length_m) / speed_mps;
}

namespace {

// The band-passed record with its Hilbert envelope and unwrapped phase, and the sample/time maps.
struct DecaySignal {
  double fs = 0.0, t0 = 0.0;
  Index n = 0;
  Vector y, env, phase;
  Vector raw;  // the record less its mean, before the band-pass
  double time_of(Index j) const { return t0 + static_cast<double>(j) / fs; }
  Index index_of(double t) const { return std::clamp<Index>(static_cast<Index>(std::llround((t - t0) * fs)), 0, n - 1); }
};

DecaySignal band_passed(const Vector& x, double fs_hz, double t0_s, const DecayOptions& o) {
  DecaySignal s;
  s.fs = fs_hz;
  s.t0 = t0_s;
  s.n = x.size();
  s.y = x.array() - x.mean();
  s.raw = s.y;
  if (o.filter_order > 0) {
    signal::Cheby1Spec spec;
    spec.order = o.filter_order;
    spec.ripple_db = o.ripple_db;
    spec.band = signal::BandType::bandpass;
    spec.low_hz = o.frequency_hz * (1.0 - o.band_ratio);
    spec.high_hz = o.frequency_hz * (1.0 + o.band_ratio);
    s.y = signal::sosfiltfilt(signal::cheby1(spec, fs_hz), s.y);
  }
  const Eigen::VectorXcd z = signal::analytic_signal(s.y);
  s.env = z.cwiseAbs();
  s.phase.resize(s.n);
  for (Index j = 0; j < s.n; ++j) {
    s.phase[j] = std::arg(z[j]);
    if (j > 0) {
      while (s.phase[j] - s.phase[j - 1] > M_PI) s.phase[j] -= 2.0 * M_PI;
      while (s.phase[j] - s.phase[j - 1] < -M_PI) s.phase[j] += 2.0 * M_PI;
    }
  }
  return s;
}

// The noise floor: the envelope's median over the record's last 5 % (short of the filter's edge),
// unless the mode still rings there. A record that ends before the decay reaches the noise has an
// envelope falling smoothly at its end — the log a straight line, falling by more than 5 % and
// by more than ten times the line's rms residual over the last 15 % — where band-passed noise
// has a log-envelope scattered by about 0.5 (Rayleigh); taking that ringing for noise left no
// decay at all (a viaduct run with 3 s of free vibration at 1 % damping ends at 40 % of its
// amplitude after the train). The floor is then the in-band share of what the band-pass removed
// there, taken as white: its rms × √(band / (fs/2 − band)), times 1.18 (the median of a Rayleigh
// envelope) — about 0 for a simulation, the noise for a record.
double noise_floor(const DecaySignal& s, Index edge, const DecayOptions& o) {
  const Index n = s.n;
  const Index stop = std::max<Index>(n - edge, static_cast<Index>(0.95 * static_cast<double>(n)));
  const Index from = static_cast<Index>(0.85 * static_cast<double>(n));
  if (stop - from >= 8) {
    const Index m = stop - from;
    std::vector<double> t, l;
    for (Index j = from; j < stop; ++j) {
      t.push_back(static_cast<double>(j - from) / s.fs);
      l.push_back(std::log(std::max(s.env[j], 1e-300)));
    }
    const Line line = fit_line(t, l);
    double ss = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) ss += (l[i] - line.at(t[i])) * (l[i] - line.at(t[i]));
    const double md = static_cast<double>(m);
    const double fall = -line.slope * static_cast<double>(m - 1) / s.fs, resid = std::sqrt(ss / md);
    if (fall > 0.05 && fall > 10.0 * resid) {  // still ringing
      double ss_out = 0.0;
      for (Index j = from; j < stop; ++j) ss_out += (s.raw[j] - s.y[j]) * (s.raw[j] - s.y[j]);
      const double band = o.filter_order > 0 ? 2.0 * o.band_ratio * o.frequency_hz : 0.0;
      const double rest = std::max(0.5 * s.fs - band, band);
      return 1.1774 * std::sqrt(ss_out / md) * std::sqrt(band / rest);
    }
  }
  std::vector<double> tail;
  for (Index j = static_cast<Index>(0.94 * static_cast<double>(n)); j < stop; ++j) tail.push_back(s.env[j]);
  if (tail.empty()) return 0.0;
  std::nth_element(tail.begin(), tail.begin() + static_cast<std::ptrdiff_t>(tail.size() / 2), tail.end());
  return tail[tail.size() / 2];
}

// The free decay is where the half-cycle peaks fall as one exponential: ln(peak) a straight line
// in time. From the last peaks above the noise back to `from` (the peak after the last rise), the
// line through the later peaks must predict each earlier one within max(5 %, 3 × its rms
// residual) + 2·noise/peak; the first it does not predict is still forced (a train on the bridge
// can make the peaks fall for a while without a rise, which the rise test alone misses). 5 %: the
// band-pass's edge bends the last peaks' logs by up to 3 % (1.5 % damping, 5 Hz, measured), the
// forcing's end moves them by 8 to 25 % (HSLM-A1 leaving a 15 m span).
// Returns the index of the first peak of the decay.
constexpr double kExponentialTolerance = 0.05;

std::size_t exponential_start(const std::vector<TimedPeak>& half, std::size_t from, double noise, double t_end,
                              const DecayOptions& o) {
  std::size_t last = from;
  for (std::size_t k = from; k < half.size() && half[k].t <= t_end && half[k].value >= o.noise_factor * noise; ++k) last = k;
  if (last < from + 6) return from;
  double n = 0, st = 0, sl = 0, stt = 0, stl = 0, sll = 0;
  auto add = [&](const TimedPeak& p) {
    const double t = p.t - half[last].t, l = std::log(p.value);
    n += 1, st += t, sl += l, stt += t * t, stl += t * l, sll += l * l;
  };
  for (std::size_t k = last - 5; k <= last; ++k) add(half[k]);
  for (std::size_t k = last - 6;; --k) {
    const double den = n * stt - st * st;
    const double b = (n * stl - st * sl) / den, a = (sl - b * st) / n;
    const double sse = std::max(0.0, sll - a * sl - b * stl);
    const double rms = std::sqrt(sse / n);
    const double dev = std::log(half[k].value) - (a + b * (half[k].t - half[last].t));
    if (std::abs(dev) > std::max(kExponentialTolerance, 3.0 * rms) + 2.0 * noise / half[k].value) return k + 1;
    add(half[k]);
    if (k == from) return from;
  }
}

// Start (given, or the first half-cycle peak after the largest from which the peaks only fall)
// and end (given, or where the envelope sinks into the noise) of the free decay.
void decay_window(const DecaySignal& s, const std::vector<TimedPeak>& half, double noise, Index edge, const DecayOptions& o,
                  DecayResult& r) {
  const double t_last = s.time_of(s.n - 1);
  const double t_usable_end = s.time_of(s.n - 1 - edge);
  if (std::isfinite(o.start_s)) {
    if (o.start_s < s.t0 || o.start_s >= t_last)
      throw InputError("decay: DecayOptions::start_s = " + format_number(o.start_s, 6) + " s lies outside the record [" +
                       format_number(s.t0, 6) + ", " + format_number(t_last, 6) + "] s");
    r.start_s = o.start_s;
  } else {
    r.start_detected = true;
    std::size_t kmax = 0;
    for (std::size_t k = 1; k < half.size(); ++k)
      if (half[k].t <= t_usable_end && half[k].value > half[kmax].value) kmax = k;
    std::size_t ks = kmax;
    for (std::size_t k = kmax + 1; k < half.size() && half[k].t <= t_usable_end; ++k) {
      if (half[k].value < o.noise_factor * noise) break;  // into the noise: rises mean nothing
      // A rise beyond tolerance and noise ends the decay found so far.
      if (half[k].value > half[k - 1].value * (1.0 + o.rise_tolerance) + 2.0 * noise) ks = k;
    }
    r.start_s = half[exponential_start(half, ks, noise, t_usable_end, o)].t;
  }
  if (std::isfinite(o.end_s)) {
    if (o.end_s <= r.start_s || o.end_s > t_last + 0.5 / s.fs)
      throw InputError("decay: DecayOptions::end_s = " + format_number(o.end_s, 6) + " s must lie after the start (" +
                       format_number(r.start_s, 6) + " s) and within the record (to " + format_number(t_last, 6) + " s)");
    r.end_s = std::min(o.end_s, t_usable_end);
  } else {
    r.end_s = t_usable_end;
    for (Index j = s.index_of(r.start_s); j < s.n - edge; ++j)
      if (s.env[j] < o.noise_factor * noise) {
        r.end_s = s.time_of(j);
        break;
      }
  }
}

// Damped angular frequency from the upward zero crossings in [a, b]. Each crossing's timing
// error is about noise/(amplitude·ω): weights amplitude².
double damped_frequency(const DecaySignal& s, double a, double b) {
  std::vector<double> kx, tx, wx;
  for (Index j = s.index_of(a); j < s.index_of(b); ++j)
    if (s.y[j] < 0.0 && s.y[j + 1] >= 0.0) {
      const double frac = s.y[j] / (s.y[j] - s.y[j + 1]);
      kx.push_back(static_cast<double>(kx.size()));
      tx.push_back(s.time_of(j) + frac / s.fs);
      wx.push_back(s.env[j] * s.env[j]);
    }
  if (kx.size() < 3) throw InputError("decay: fewer than 3 zero crossings in the decay");
  return 2.0 * M_PI / fit_line(kx, tx, wx).slope;
}

// Envelope fit of the half-cycle peaks in [a, b] (ln(peak) has an error of about noise/peak:
// weights peak²) and logarithmic decrement of the positive peaks.
void peak_estimates(const std::vector<TimedPeak>& half, const std::vector<TimedPeak>& pos, double a, double b, double wd,
                    DecayResult& r) {
  std::vector<double> tp, lp, wp;
  for (const auto& p : half)
    if (p.t >= a && p.t <= b) tp.push_back(p.t), lp.push_back(std::log(p.value)), wp.push_back(p.value * p.value);
  std::vector<TimedPeak> pw;
  for (const auto& p : pos)
    if (p.t >= a && p.t <= b) pw.push_back(p);
  if (pw.size() < 3 || tp.size() < 4) throw InputError("decay: fewer than 3 cycle peaks in the decay");
  const Line env_line = fit_line(tp, lp, wp);
  const double sigma_env = -env_line.slope;
  double ss = 0.0;
  for (std::size_t k = 0; k < tp.size(); ++k) ss += std::pow(lp[k] - env_line.at(tp[k]), 2);
  r.envelope_residual = std::sqrt(ss / static_cast<double>(tp.size()));
  const double wn = std::sqrt(wd * wd + sigma_env * sigma_env);
  r.frequency_hz = wn / (2.0 * M_PI);
  r.zeta_envelope_fit = sigma_env / wn;
  // Over the cycles down to e^{-2} of the first peak: more cycles average the noise, a last peak
  // near the noise floor adds it back (error ≈ (ε/p₀ + ε/p_N)/N).
  std::size_t last = 1;
  while (last + 1 < pw.size() && pw[last + 1].value >= pw.front().value * std::exp(-2.0)) ++last;
  last = std::max<std::size_t>(last, std::min<std::size_t>(2, pw.size() - 1));
  const double delta = std::log(pw.front().value / pw[last].value) / static_cast<double>(last);
  r.zeta_log_decrement = delta / std::sqrt(4.0 * M_PI * M_PI + delta * delta);
}

// Decay rate, damped angular frequency and mid-window amplitude of the Hilbert envelope and
// phase over [ta, tb]; both have errors of about noise/envelope: weights envelope².
void hilbert_fit(const DecaySignal& s, double ta, double tb, double* sigma, double* w_d, double* amp_mid) {
  std::vector<double> t, le, ph, w;
  for (Index j = s.index_of(ta); j <= s.index_of(tb); ++j)
    if (s.env[j] > 0.0) t.push_back(s.time_of(j)), le.push_back(std::log(s.env[j])), ph.push_back(s.phase[j]), w.push_back(s.env[j] * s.env[j]);
  const Line l = fit_line(t, le, w);
  *sigma = -l.slope;
  *w_d = std::abs(fit_line(t, ph, w).slope);
  if (amp_mid) *amp_mid = std::exp(l.at(0.5 * (ta + tb)));
}

// Along the decay: windows of window_cycles, one cycle apart, and the linear laws of damping and
// frequency against amplitude.
void amplitude_dependence(const DecaySignal& s, double a, double b, double wd, const DecayOptions& o, DecayResult& r) {
  const double W = o.window_cycles * 2.0 * M_PI / wd;
  const double step = 2.0 * M_PI / wd;
  // Counted in floating point before any window is made: one per cycle of the decay.
  const double n_windows = (b - a - W) / step + 1.0;
  if (!(n_windows < 1e7)) throw InputError("decay: the damped period is not resolved (" + std::to_string(n_windows) + " windows)");
  std::vector<double> amps, zetas, freqs;
  for (double ta = a; ta + W <= b + 1e-12; ta += step) {
    double sg = 0.0, w = 0.0, amp = 0.0;
    hilbert_fit(s, ta, ta + W, &sg, &w, &amp);
    const double wnw = std::sqrt(w * w + sg * sg);
    AmplitudePoint p;
    p.t_s = ta + 0.5 * W;
    p.amplitude = amp;
    p.frequency_hz = wnw / (2.0 * M_PI);
    p.damping_ratio = sg / wnw;
    r.by_amplitude.push_back(p);
    amps.push_back(amp);
    zetas.push_back(p.damping_ratio);
    freqs.push_back(p.frequency_hz);
  }
  if (amps.size() >= 2) {
    const Line lz = fit_line(amps, zetas), lf = fit_line(amps, freqs);
    r.law_zeta_slope = lz.slope;
    r.law_zeta0 = lz.at(0.0);
    r.law_f_slope_hz = lf.slope;
    r.law_f0_hz = lf.at(0.0);
  }
}

}  // namespace

namespace {
// A step in the raw record inside the decay window [a, b] (record time): the band-pass turns it into
// a transient at the mode's frequency that passes for the decay (issue #36: a step inside a decay
// of 2.71 % gave 0.89 %). Over whole periods of the mode the decay averages out: the record's mean
// per period is its baseline. A step leaves the baseline at another level for good; forcing left in
// the window or other modes make it wander and come back. So: the split of the periods' means
// into a before and an after (three periods each at least) whose means differ most for their
// spread — the MAD about its median of the noisier side: a step leaves both sides flat, forcing
// that ends leaves one wandering — counted as a step when the difference is 8 times that spread
// and 2 % of the mode's amplitude.
void require_no_step(const Vector& x, double fs_hz, double t0_s, double f0, double a, double b, double amplitude) {
  const auto P = std::max<Index>(2, static_cast<Index>(std::llround(fs_hz / f0)));
  const Index i0 = std::max<Index>(0, static_cast<Index>(std::floor((a - t0_s) * fs_hz)));
  const Index i1 = std::min<Index>(x.size(), static_cast<Index>(std::ceil((b - t0_s) * fs_hz)));
  const Index n = (i1 - i0) / P;  // whole periods
  if (n < 6) return;
  std::vector<double> m(static_cast<std::size_t>(n));
  for (Index k = 0; k < n; ++k) m[static_cast<std::size_t>(k)] = x.segment(i0 + k * P, P).mean();
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  double best = 0.0, spread = 0.0, best_score = 0.0;
  Index at = -1;
  for (Index j = 3; j + 3 <= n; ++j) {
    const std::vector<double> lo(m.begin(), m.begin() + j), hi(m.begin() + j, m.end());
    double ml = 0.0, mh = 0.0;
    for (const double v : lo) ml += v / static_cast<double>(lo.size());
    for (const double v : hi) mh += v / static_cast<double>(hi.size());
    std::vector<double> dl, dh;
    for (const double v : lo) dl.push_back(std::abs(v - median(lo)));
    for (const double v : hi) dh.push_back(std::abs(v - median(hi)));
    // The noisier side's spread: a step leaves both sides flat, forcing that ends leaves one wandering.
    const double sp = std::max(median(dl), median(dh)), jump = std::abs(mh - ml);
    const double score = jump / std::max(sp, 1e-300 * std::max(1.0, jump));
    if (score > best_score) best_score = score, best = jump, spread = sp, at = j;
  }
  if (at < 0 || !(best > 8.0 * spread && best > 0.02 * amplitude)) return;
  const double t = t0_s + static_cast<double>(i0 + at * P) / fs_hz;
  throw InputError("decay: the record's baseline steps by " + format_number(best, 3) + " near t = " + format_number(t, 5) +
                   " s, inside the decay analysed (" + format_number(a, 5) + " to " + format_number(b, 5) + " s; " +
                   format_number(best / amplitude * 100.0, 3) +
                   " % of the mode's amplitude there, " + format_number(best / std::max(spread, 1e-300), 3) +
                   " x the baseline's spread): a zero shift or a glitch of the logger, whose band-passed transient would pass "
                   "for the decay; cut the record before it or give --end-s");
}
}  // namespace

DecayResult analyse_decay(const Vector& x, double fs_hz, double t0_s, const DecayOptions& o) {
  require_positive(fs_hz, "sampling rate [Hz]");
  std::string why;
  if (!o.is_valid(fs_hz, &why)) throw InputError("decay: " + why);
  if (x.size() < 16) throw InputError("decay: the record is too short (" + std::to_string(x.size()) + " samples)");
  if (!x.allFinite()) throw InputError("decay: the record holds NaN or infinite samples");
  const double peak = x.cwiseAbs().maxCoeff();
  if (!(peak > 0.0)) throw InputError("decay: the record is zero throughout");
  // Squares of samples beyond 1e100 (and of those below 1e-100) would overflow (underflow): such a
  // record is analysed scaled by a power of two, exact, and its amplitudes scaled back.
  const int exponent = peak > 1e100 || peak < 1e-100 ? std::ilogb(peak) : 0;
  if (exponent != 0) {
    DecayResult r = analyse_decay(std::ldexp(1.0, -exponent) * x, fs_hz, t0_s, o);
    const double back = std::ldexp(1.0, exponent);
    r.amplitude_start *= back;
    r.amplitude_end *= back;
    for (auto& p : r.by_amplitude) p.amplitude *= back;
    r.law_zeta_slope /= back;
    r.law_f_slope_hz /= back;
    return r;
  }
  const double f0 = o.frequency_hz;
  const DecaySignal s = band_passed(x, fs_hz, t0_s, o);
  const double cycle = 1.0 / f0;
  const Index edge = std::min<Index>(s.n / 4, static_cast<Index>(std::ceil(2.0 * cycle * fs_hz)));
  const double noise = noise_floor(s, edge, o);
  const auto pos = peaks_of(s.y, fs_hz, t0_s, f0, true);
  const auto neg = peaks_of(s.y, fs_hz, t0_s, f0, false);
  std::vector<TimedPeak> half(pos);
  half.insert(half.end(), neg.begin(), neg.end());
  std::sort(half.begin(), half.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  if (half.size() < 4) throw InputError("decay: fewer than 2 cycles of the mode in the record");

  DecayResult r;
  decay_window(s, half, noise, edge, o, r);
  const double a = r.start_s + o.skip_cycles * cycle;
  const double b = r.end_s;
  r.n_cycles = std::max(0.0, (b - a) * f0);
  if (r.n_cycles < o.min_cycles) {
    auto n = [](double v) { return format_number(v, 4); };
    const std::string where = (r.start_detected ? "the decay detected at " : "the decay given at ") + n(r.start_s) + " s";
    if (a >= b)  // the window is empty: say why rather than "0 cycles between 3.75 s and 3.13 s"
      throw InputError("decay: too short a decay: " + where + ", after the " + n(o.skip_cycles) +
                       " cycles skipped for the filter's transient (to " + n(a) + " s), leaves nothing before " + n(b) +
                       " s (" + (std::isfinite(o.end_s) ? "--end-s" : "the record's end less two cycles of the filter's edge, or the noise") +
                       "): record longer after the passage, or give --start-s, --end-s or --skip-cycles");
    throw InputError("decay: too short a decay: the free vibration sinks into the noise" +
                     std::string(std::isfinite(o.end_s) ? " or reaches --end-s" : " or the record ends") + " after " + n(r.n_cycles) +
                     " cycles of " + n(f0) + " Hz (from " + n(a) + " s: " + where + " plus " + n(o.skip_cycles) +
                     " cycles skipped, to " + n(b) + " s), at least " + n(o.min_cycles) + " needed (--min-cycles)");
  }
  require_no_step(x, fs_hz, t0_s, f0, a, b, s.env[s.index_of(a)]);
  const double wd = damped_frequency(s, a, b);
  if (!(std::isfinite(wd) && wd > 0.0))
    throw InputError("decay: no oscillation of the mode in the decay window (the zero crossings give no period)");
  peak_estimates(half, pos, a, b, wd, r);
  double sh = 0.0, wdh = 0.0;
  hilbert_fit(s, a, b, &sh, &wdh, nullptr);
  const double wnh = std::sqrt(wdh * wdh + sh * sh);
  r.zeta_hilbert = sh / wnh;
  r.frequency_hilbert_hz = wnh / (2.0 * M_PI);
  r.amplitude_start = s.env[s.index_of(a)];
  r.amplitude_end = s.env[s.index_of(b)];
  amplitude_dependence(s, a, b, wd, o, r);
  return r;
}

Statistic statistic(const std::vector<double>& values) {
  Statistic s;
  for (double v : values)
    if (std::isfinite(v)) s.mean += v, ++s.n;
  if (s.n == 0) return s;
  s.mean /= static_cast<double>(s.n);
  double ss = 0.0;
  for (double v : values)
    if (std::isfinite(v)) ss += (v - s.mean) * (v - s.mean);
  s.std = s.n > 1 ? std::sqrt(ss / static_cast<double>(s.n - 1)) : 0.0;
  return s;
}

}  // namespace viaduct::ident
