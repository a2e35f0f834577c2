#include "viaduct/study/speed.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <tuple>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "series.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/signal/iir.hpp"
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
  if (!(A.maxCoeff() > 0.0)) throw InputError("no train found: the channel is constant");
  // Detection: each line against the spectrum's median over the band its harmonic was searched in.
  double log_ratio = 0.0;
  for (int k = 1; k <= n_harmonics; ++k) {
    const Index i0 = std::min(static_cast<Index>(std::floor(k * v_min / d / df)), A.size() - 1);
    const Index i1 = std::min(static_cast<Index>(std::ceil(k * v_max / d / df)) + 1, A.size());
    std::vector<double> band(A.data() + i0, A.data() + std::max(i0 + 1, i1));
    std::nth_element(band.begin(), band.begin() + static_cast<std::ptrdiff_t>(band.size() / 2), band.end());
    log_ratio += std::log((amp(k * v / d) + floor) / (band[band.size() / 2] + floor));
  }
  e.detection = std::exp(log_ratio / n_harmonics);
  if (e.detection < kMinSpectralDetection)
    throw InputError("no train found between " + format_number(v_min * 3.6, 4) + " and " + format_number(v_max * 3.6, 4) +
                     " km/h: the best speed's " + std::to_string(n_harmonics) + " lines stand " + format_number(e.detection, 3) +
                     " times above the spectrum's median (a train's: at least " + format_number(kMinSpectralDetection, 3) + ")");
  return e;
}

SpeedEstimate speed_from_peaks(const Vector& x, double fs_hz, double d, double min_interval_s, double v_min, double v_max) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_positive(d, "characteristic distance d [m]");
  require_positive(min_interval_s, "minimum interval between axle peaks [s]");
  if (!(v_min >= 0.0) || !(v_max > v_min)) throw InputError("speed range: need 0 <= v_min < v_max");
  if (x.size() < 16 || !x.allFinite()) throw InputError("axle passages: need at least 16 finite samples");
  signal::PeakOptions o;
  o.min_distance = std::max<Index>(1, static_cast<Index>(std::ceil(min_interval_s * fs_hz)));
  // Axle passages are the prominent peaks; a free-vibration tail adds many small ones that
  // would otherwise set the median interval.
  auto all = signal::find_peaks(x, o);
  double top = 0.0;
  for (const auto& p : all) top = std::max(top, p.prominence);
  std::vector<signal::Peak> peaks;
  double dropped = 0.0;  // the largest prominence left out
  for (const auto& p : all) {
    if (p.prominence >= 0.1 * top) peaks.push_back(p);
    else dropped = std::max(dropped, p.prominence);
  }
  // The noise RMS from the first differences (robust: the median of their magnitudes; white
  // noise of RMS s has differences of RMS s·√2, whose median magnitude is 0.6745 of that).
  std::vector<double> diff(static_cast<std::size_t>(x.size() - 1));
  for (Index i = 1; i < x.size(); ++i) diff[static_cast<std::size_t>(i - 1)] = std::abs(x[i] - x[i - 1]);
  std::nth_element(diff.begin(), diff.begin() + static_cast<std::ptrdiff_t>(diff.size() / 2), diff.end());
  const double noise = diff[diff.size() / 2] / (0.6745 * std::sqrt(2.0));
  if (!(top > 0.0)) throw InputError("no train found: the channel has no peak (constant)");
  const double detection = noise > 0.0 ? top / noise : std::numeric_limits<double>::infinity();
  if (detection < kMinPeakDetection)
    throw InputError("no train found: the largest peak stands " + format_number(detection, 3) + " noise RMS out of the record "
                     "(axle passages: at least " + format_number(kMinPeakDetection, 3) + ")");
  if (peaks.size() < 3) throw InputError("axle passages: fewer than 3 peaks found");
  // The axles stand apart from the ripple: the kept peaks' median prominence well above every
  // peak left out (noise has prominences of every size).
  std::vector<double> kept;
  for (const auto& p : peaks) kept.push_back(p.prominence);
  std::nth_element(kept.begin(), kept.begin() + static_cast<std::ptrdiff_t>(kept.size() / 2), kept.end());
  if (kept[kept.size() / 2] < kMinPeakSeparation * dropped)
    throw InputError("no train found: the peaks' median prominence is " + format_number(kept[kept.size() / 2] / dropped, 3) +
                     " times the largest of the peaks left out (axles stand apart from the ripple: at least " +
                     format_number(kMinPeakSeparation, 3) + ")");
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
  // A train's axles (or bogies) pass at one spacing: most intervals are regular. Noise, or a
  // record's own vibration beating, gives intervals all over.
  if (2 * n < static_cast<int>(dt.size()))
    throw InputError("no train found: only " + std::to_string(n) + " of the " + std::to_string(dt.size()) +
                     " intervals between the record's peaks lie within 15 % of their median (a train's axles: most of them)");
  const double mean = sum / n;
  const double sd = std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)));
  SpeedEstimate e;
  e.speed = d / mean;
  e.uncertainty = e.speed * (sd / std::sqrt(static_cast<double>(n))) / mean;
  e.frequency_hz = 1.0 / mean;
  e.n_used = n;
  e.detection = detection;
  if (e.speed < v_min || e.speed > v_max)
    throw InputError("no train found between " + format_number(v_min * 3.6, 4) + " and " + format_number(v_max * 3.6, 4) +
                     " km/h: the peaks' median spacing " + format_number(mean, 4) + " s gives " + format_number(e.speed * 3.6, 5) +
                     " km/h for d = " + format_number(d, 4) + " m");
  return e;
}

namespace {

// The record (filtered) against templates at trial speeds.
class Signature {
 public:
  Signature(const Vector& record, double fs, const std::function<Vector(double)>& f, double fs_t, const SignatureOptions& o)
      : fs_(fs), fs_t_(fs_t), f_(f), o_(o) {
    y_ = o.filter.enabled ? signal::sosfiltfilt(signal::cheby1(o.filter.cheby, fs), record) : record;
    yc_ = y_.array() - y_.mean();
  }
  const Vector& y() const { return y_; }
  double shortest_s() const { return shortest_s_; }
  double pad_s() const { return pad_s_; }
  Index evaluations() const { return n_; }

  // The filtered template at speed v, at the template's rate, from t = −pad (the quiet before the
  // train, zeros: filtered as the record's quiet lead-in is, without the filter's edge effects).
  Vector filtered(double v) {
    ++n_;
    const Vector m = f_(v);
    shortest_s_ = std::min(shortest_s_, static_cast<double>(m.size() - 1) / fs_t_);
    if (m.size() < 16 || !m.allFinite()) throw InputError("speed match: the template at " + format_number(v * 3.6, 6) + " km/h is not 16 finite samples");
    return filter_padded(m);
  }
  Vector filter_padded(const Vector& m) const {
    const auto n_pad = static_cast<Index>(std::llround(pad_s_ * fs_t_));
    Vector p = Vector::Zero(m.size() + n_pad);
    p.tail(m.size()) = m;
    return o_.filter.enabled ? signal::sosfiltfilt(signal::cheby1(o_.filter.cheby, fs_t_), p) : p;
  }
  // The template aligned on the record's grid, its t = 0 at record sample `lag`.
  Vector aligned(const Vector& m, double lag) const {
    Vector a(y_.size());
    const double pad = static_cast<double>(std::llround(pad_s_ * fs_t_)) / fs_t_;
    for (Index j = 0; j < a.size(); ++j) a[j] = detail::sample_at(m, fs_t_, (static_cast<double>(j) - lag) / fs_ + pad);
    return a;
  }
  // Best lag (record sample of the template's t = 0) and the correlation there.
  std::pair<double, double> best(const Vector& m) const {
    const auto n_r = static_cast<Index>(std::floor(static_cast<double>(m.size() - 1) / fs_t_ * fs_)) + 1;
    Vector m_r(n_r);
    for (Index j = 0; j < n_r; ++j) m_r[j] = detail::sample_at(m, fs_t_, static_cast<double>(j) / fs_);
    const auto max_lag = static_cast<Index>(std::ceil(o_.max_shift_s * fs_));
    const double pad = static_cast<double>(std::llround(pad_s_ * fs_t_)) / fs_t_;
    const double lag = signal::best_lag(m_r, yc_, max_lag) + pad * fs_;
    return {lag, detail::pearson(y_, aligned(m, lag))};
  }
  double score(double v) { return best(filtered(v)).second; }

 private:
  double fs_, fs_t_;
  const std::function<Vector(double)>& f_;
  const SignatureOptions& o_;
  Vector y_, yc_;
  Index n_ = 0;
  double pad_s_ = 1.0;  // [s] longer than the filter's memory (a 1 Hz band edge: a few tenths of a second)
  double shortest_s_ = std::numeric_limits<double>::infinity();  // [s] the shortest template so far
};

// Rows of the least-squares fit: record samples whose template time lies in [−pad/2, T − 0.25 s]
// (T: the shortest template, at the highest speed searched; its end and the record's ends carry
// the filter's edge effects, which differ between record and template), 0.25 s inside the record.
std::vector<Index> fit_rows(Index n, double fs, double lag, double pad_s, double shortest_s) {
  std::vector<Index> rows;
  const auto edge = static_cast<Index>(0.25 * fs);
  for (Index j = edge; j + edge < n; ++j) {
    const double t = (static_cast<double>(j) - lag) / fs;
    if (t >= -pad_s / 2 && t <= shortest_s - 0.25) rows.push_back(j);
  }
  return rows;
}

Matrix rows_of(const Matrix& X, const std::vector<Index>& rows) {
  Matrix out(static_cast<Index>(rows.size()), X.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Index>(k)) = X.row(rows[k]);
  return out;
}

// Golden-section search for the maximum of f on [a, b] to a width `width`.
double golden_max(const std::function<double(double)>& f, double a, double b, double width) {
  const double r = (std::sqrt(5.0) - 1) / 2;
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = f(c), fd = f(d);
  for (int it = 0; it < 200 && b - a > width; ++it) {
    if (fc >= fd) {
      b = d, d = c, fd = fc;
      c = b - r * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + r * (b - a), fd = f(d);
    }
  }
  return fc >= fd ? c : d;
}

// Independent samples of a residual of `n` samples at fs after the filter (its band B: N × 2B/fs).
double effective_samples(Index n, double fs, const FilterSpec& f) {
  double band = fs / 2;
  if (f.enabled) {
    const auto& c = f.cheby;
    band = c.band == signal::BandType::lowpass ? c.high_hz : c.band == signal::BandType::highpass ? fs / 2 - c.low_hz : c.high_hz - c.low_hz;
  }
  return static_cast<double>(n) * std::min(1.0, 2 * band / fs);
}

}  // namespace

SignatureMatch match_signature(const Vector& record, double fs_hz, double t0_s, const std::function<Vector(double)>& template_at,
                               double fs_template, const SignatureOptions& o) {
  require_positive(fs_hz, "record sampling rate [Hz]");
  require_positive(fs_template, "template sampling rate [Hz]");
  require_positive(o.v_min, "lowest speed [m/s]");
  require_positive(o.grid_step, "grid step");
  require_positive(o.max_shift_s, "max_shift_s [s]");
  require_finite(t0_s, "record start [s]");
  if (!(o.v_max > o.v_min) || !std::isfinite(o.v_max)) throw InputError("speed range: need v_max > v_min");
  if (record.size() < 16 || !record.allFinite()) throw InputError("speed match: need at least 16 finite samples");
  Signature sig(record, fs_hz, template_at, fs_template, o);
  // 1. log-spaced grid
  std::vector<double> vs;
  for (double v = o.v_min; v < o.v_max * (1 + 1e-9); v *= 1 + o.grid_step) vs.push_back(v);
  if (vs.back() < o.v_max) vs.push_back(o.v_max);
  std::vector<double> sc(vs.size());
  for (std::size_t i = 0; i < vs.size(); ++i) sc[i] = sig.score(vs[i]);
  const auto ib = static_cast<std::size_t>(std::max_element(sc.begin(), sc.end()) - sc.begin());
  // 2. golden section between the neighbours of the best grid point
  const double a = vs[ib > 0 ? ib - 1 : 0], b = vs[std::min(ib + 1, vs.size() - 1)];
  const double v_best = a < b ? golden_max([&](double x) { return sig.score(x); }, a, b, 1e-6 * b) : vs[ib];
  // 3. least squares: y ≈ c + A·m(t − τ; v), Gauss-Newton in (c, A, v, τ) from the correlation's
  // optimum (whose lag, a parabola through the cross-correlation's peak, is biased by up to a
  // fraction of a sample, which the speed would otherwise absorb); Jacobian by central differences.
  const Vector& y = sig.y();
  double v = v_best, lag = 0.0, corr = 0.0, A = 0.0;
  Matrix X;
  Vector e;
  for (int it = 0; it < 8; ++it) {
    const Vector m = sig.filtered(v);
    if (it == 0) std::tie(lag, corr) = sig.best(m);
    const std::vector<Index> rows = fit_rows(y.size(), fs_hz, lag, sig.pad_s(), sig.shortest_s());
    if (rows.size() < 16) throw InputError("speed match: the record and the template overlap by fewer than 16 samples away from their ends");
    const Vector a0 = sig.aligned(m, lag);
    const double dv = 1e-4 * v;
    Matrix Xf(y.size(), 5);
    Xf.col(0).setOnes();
    Xf.col(1) = a0;
    Xf.col(2) = (sig.aligned(sig.filtered(v + dv), lag) - sig.aligned(sig.filtered(v - dv), lag)) / (2 * dv);
    Xf.col(3) = (sig.aligned(m, lag + 1.0) - sig.aligned(m, lag - 1.0)) * (fs_hz / 2);
    Xf.col(4) = y;
    const Matrix W = rows_of(Xf, rows);
    const Vector yw = W.col(4);
    const Eigen::Vector2d ca = W.leftCols(2).colPivHouseholderQr().solve(yw);
    A = ca[1];
    X = W.leftCols(4);
    X.col(2) *= A;
    X.col(3) *= A;
    e = yw - W.leftCols(2) * ca;
    corr = detail::pearson(yw, W.col(1));
    const Eigen::Vector4d step = X.colPivHouseholderQr().solve(e);
    if (std::abs(step[2]) < 1e-7 * v && std::abs(step[3]) * fs_hz < 1e-4) break;
    v += step[2];
    lag += step[3] * fs_hz;
  }
  SignatureMatch r;
  r.speed = v;
  r.shift_s = t0_s + lag / fs_hz;
  r.amplitude = A;
  r.correlation = corr;
  const auto n = X.rows();
  r.n_effective = effective_samples(n, fs_hz, o.filter);
  const double sigma2 = e.squaredNorm() / static_cast<double>(n - 4) * static_cast<double>(n) / r.n_effective;
  const Eigen::Matrix4d XtX = X.transpose() * X;
  const Eigen::Matrix4d cov = sigma2 * XtX.inverse();
  r.speed_se = std::sqrt(std::max(0.0, cov(2, 2)));
  r.shift_se = std::sqrt(std::max(0.0, cov(3, 3)));
  r.n_evaluations = sig.evaluations();
  return r;
}

Delay delay_between(const Vector& a, const Vector& b, double fs_hz, const FilterSpec& filter, double max_delay_s) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_positive(max_delay_s, "largest delay [s]");
  if (a.size() != b.size() || a.size() < 16 || !a.allFinite() || !b.allFinite())
    throw InputError("delay: need two channels of the same length, at least 16 finite samples");
  const Vector fa = filter.enabled ? signal::sosfiltfilt(signal::cheby1(filter.cheby, fs_hz), a) : a;
  const Vector y = filter.enabled ? signal::sosfiltfilt(signal::cheby1(filter.cheby, fs_hz), b) : b;
  const Index n = y.size();
  // Fractional delays by a phase shift (band-limited): a linear interpolation of the noisy first
  // channel would average its noise by an amount that depends on the fraction and bias the lag
  // towards half samples.
  Index nfft = 1;
  while (nfft < 4 * n) nfft *= 2;
  Vector pa = Vector::Zero(nfft);
  pa.head(n) = fa;
  const signal::ComplexVector A = signal::rfft(pa);
  auto shifted = [&](double lag) {
    signal::ComplexVector S = A;
    for (Index k = 0; k < S.size(); ++k)
      S[k] *= std::polar(1.0, -2 * 3.14159265358979323846 * static_cast<double>(k) * lag / static_cast<double>(nfft));
    return Vector(signal::irfft(S, nfft).head(n));
  };
  double lag = signal::best_lag(fa, Vector(y.array() - y.mean()), static_cast<Index>(std::ceil(max_delay_s * fs_hz)));
  // The lag minimising the residual of b ≈ c + g·a(t − delay) (c, g fitted at each lag), over a
  // window fixed from the first lag in which the delayed first channel is all its own samples (a
  // window that moved with the lag would hold fewer of its noise samples the longer the delay).
  // A search in one variable: the first channel's noise makes a Jacobian by differences useless.
  const auto l0 = static_cast<Index>(std::llround(lag));
  const Index j0 = std::max<Index>(0, l0) + 4, j1 = std::min<Index>(n, n + l0) - 4;
  if (j1 - j0 < 16) throw InputError("delay: the two channels overlap by fewer than 16 samples at a delay of " + format_number(lag / fs_hz, 6) + " s");
  const Index nw = j1 - j0;
  const Vector yw = y.segment(j0, nw);
  auto rss = [&](double l) {
    Matrix X(nw, 2);
    X.col(0).setOnes();
    X.col(1) = shifted(l).segment(j0, nw);
    const Eigen::Vector2d cg = X.colPivHouseholderQr().solve(yw);
    return (yw - X * cg).squaredNorm();
  };
  lag = golden_max([&](double l) { return -rss(l); }, lag - 1.5, lag + 1.5, 1e-4);
  const double h = 0.05;  // [samples]
  const double r0 = rss(lag), curvature = (rss(lag + h) - 2 * r0 + rss(lag - h)) / (h * h);  // per sample²
  const double n_eff = effective_samples(nw, fs_hz, filter);
  const double sigma2 = r0 / static_cast<double>(nw - 3) * static_cast<double>(nw) / n_eff;
  Delay d;
  d.delay_s = lag / fs_hz;
  d.delay_se = curvature > 0 ? std::sqrt(2 * sigma2 / curvature) / fs_hz : std::numeric_limits<double>::infinity();
  d.correlation = detail::pearson(yw, shifted(lag).segment(j0, nw));
  return d;
}

FilterSpec signature_filter(const FilterSpec& scenario_filter, ResponseKind kind) {
  FilterSpec f = filter_for(scenario_filter, kind);
  if (quasi_static_kind(kind)) f.enabled = true;
  return f;
}

SignatureMatch match_train_signature(const PreparedModel& m, const RunSettings& settings, const load::Train& train, std::size_t station,
                                     ResponseKind kind, const Vector& record, double fs_hz, double t0_s, const FilterSpec& scenario_filter,
                                     double v_min, double v_max, double grid_step) {
  if (station >= m.stations.size()) throw InputError("match_train_signature: station index out of range");
  require_positive(fs_hz, "sampling rate [Hz]");
  RunSettings rs = settings;
  rs.filter.enabled = false;  // the match filters record and template alike
  SignatureOptions so;
  so.v_min = v_min;
  so.v_max = v_max;
  so.grid_step = grid_step;
  so.filter = signature_filter(scenario_filter, kind);
  so.max_shift_s = static_cast<double>(record.size()) / fs_hz + 60.0;
  const std::function<Vector(double)> at = [&](double v) { return station_response(simulate(m, train, v, rs), station, kind); };
  SignatureMatch sm = match_signature(record, fs_hz, t0_s, at, 1.0 / rs.dt, so);
  if (!(sm.correlation >= kMinSignatureCorrelation))
    throw InputError("no train found between " + format_number(v_min * 3.6, 4) + " and " + format_number(v_max * 3.6, 4) +
                     " km/h: the record's best match to " + train.name + "'s signature correlates " + format_number(sm.correlation, 3) +
                     " (a passage of it: at least " + format_number(kMinSignatureCorrelation, 3) + ")");
  return sm;
}

namespace {

// The train's axles merged into groups (axles closer than merge_m): offsets at the groups'
// load-weighted means, and the shortest distance between groups.
std::vector<double> axle_groups(const load::Train& train, double merge_m, std::vector<double>* extent = nullptr) {
  std::vector<double> d;
  double sum_w = 0, sum_wx = 0, first = 0;
  for (std::size_t k = 0; k < train.n_axles(); ++k) {
    if (k > 0 && train.offset[k] - train.offset[k - 1] >= merge_m && sum_w > 0) {
      d.push_back(sum_wx / sum_w);
      if (extent) extent->push_back(train.offset[k - 1] - first);
      sum_w = sum_wx = 0;
    }
    if (sum_w == 0) first = train.offset[k];
    sum_w += train.load[k];
    sum_wx += train.load[k] * train.offset[k];
  }
  if (sum_w > 0) d.push_back(sum_wx / sum_w);
  if (extent && sum_w > 0) extent->push_back(train.offset.back() - first);
  return d;
}

struct Pairing {
  std::size_t n = 0;
  double ss = 0.0;  // [s²] sum of squared time residuals
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (group, peak)
};

// Each group's nearest peak within tol of entry + d / v, every peak used once (nearest wins).
Pairing pair_groups(const std::vector<double>& d, const std::vector<double>& peaks, double entry, double v, double tol, bool keep) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> cand;
  for (std::size_t g = 0; g < d.size(); ++g) {
    const double t = entry + d[g] / v;
    auto it = std::lower_bound(peaks.begin(), peaks.end(), t - tol);
    for (; it != peaks.end() && *it <= t + tol; ++it) cand.emplace_back(std::abs(*it - t), g, static_cast<std::size_t>(it - peaks.begin()));
  }
  std::sort(cand.begin(), cand.end());
  Pairing p;
  std::vector<char> g_used(d.size(), 0), p_used(peaks.size(), 0);
  for (const auto& [e, g, j] : cand) {
    if (g_used[g] || p_used[j]) continue;
    g_used[g] = p_used[j] = 1;
    ++p.n;
    p.ss += e * e;
    if (keep) p.pairs.emplace_back(g, j);
  }
  return p;
}

}  // namespace

AxleMatch match_axles(const Vector& x, double fs_hz, double t0_s, const load::Train& train, double speed, double speed_se, double entry_s,
                      double entry_se, const FilterSpec& filter, double min_prominence) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_positive(speed, "speed [m/s]");
  require_finite(entry_s, "entry time [s]");
  require_finite(t0_s, "record start [s]");
  if (!(speed_se >= 0) || !(entry_se >= 0)) throw InputError("match_axles: standard errors must be >= 0");
  if (!(min_prominence > 0 && min_prominence < 1)) throw InputError("match_axles: min_prominence must be in (0, 1)");
  if (train.n_axles() == 0) throw InputError("match_axles: a train without axles");
  if (x.size() < 3 || !x.allFinite()) throw InputError("match_axles: at least 3 finite samples are needed");
  AxleMatch m;
  double min_gap = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < train.n_axles(); ++k) {
    AxlePassage a;
    a.axle = k;
    a.offset_m = train.offset[k];
    a.load_n = train.load[k];
    a.t_s = entry_s + a.offset_m / speed;
    a.t_se = std::hypot(entry_se, a.offset_m / speed / speed * speed_se);
    if (k > 0 && train.offset[k] > train.offset[k - 1]) min_gap = std::min(min_gap, (train.offset[k] - train.offset[k - 1]) / speed);
    m.axles.push_back(a);
  }
  // A tenth of the shortest time between axles: an axle peak of a short influence line falls on
  // the axle's time to a sample or two; a wider window would pair the humps of a long one with
  // axles by chance.
  m.tolerance_s = std::max(std::isfinite(min_gap) ? 0.1 * min_gap : 0.1 * x.size() / fs_hz, 3.0 / fs_hz);
  const Vector y = filter.enabled ? signal::sosfiltfilt(signal::cheby1(filter.cheby, fs_hz), x) : x;
  std::vector<signal::Peak> peaks = signal::find_peaks(y, {}, signal::Interpolation::parabolic);
  double top = 0;
  for (const auto& p : peaks) top = std::max(top, p.prominence);
  peaks.erase(std::remove_if(peaks.begin(), peaks.end(), [&](const signal::Peak& p) { return p.prominence < min_prominence * top; }),
              peaks.end());
  // Every (axle, peak) pair within the tolerance, nearest first; each axle and peak used once.
  std::vector<double> times;
  for (const auto& p : peaks) times.push_back(t0_s + p.position / fs_hz);
  const Pairing pr = pair_groups(train.offset, times, entry_s, speed, m.tolerance_s, true);
  for (const auto& [k, j] : pr.pairs) {
    m.axles[k].seen = true;
    m.axles[k].peak_t_s = times[j];
    m.axles[k].peak_value = peaks[j].value;
  }
  m.n_seen = pr.n;
  m.rms_residual_s = pr.n ? std::sqrt(pr.ss / static_cast<double>(pr.n)) : 0.0;
  return m;
}


TrainTiming speed_from_train(const Vector& x, double fs_hz, double t0_s, const load::Train& train, const TrainTimingOptions& o) {
  require_positive(fs_hz, "sampling rate [Hz]");
  require_finite(t0_s, "record start [s]");
  if (!(o.v_min > 0 && o.v_max > o.v_min && std::isfinite(o.v_max))) throw InputError("speed range: need 0 < v_min < v_max");
  if (!(o.min_prominence > 0 && o.min_prominence < 1)) throw InputError("min_prominence must be in (0, 1)");
  if (!(o.merge_m >= 0) || !std::isfinite(o.merge_m)) throw InputError("merge distance must be >= 0 [m]");
  if (train.n_axles() < 3) throw InputError("the train's geometry: at least 3 axles are needed");
  if (x.size() < 16 || !x.allFinite()) throw InputError("at least 16 finite samples are needed");
  Vector y = o.filter.enabled ? signal::sosfiltfilt(signal::cheby1(o.filter.cheby, fs_hz), x) : x;
  std::vector<double> sorted(y.data(), y.data() + y.size());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  y.array() -= sorted[sorted.size() / 2];
  if (-y.minCoeff() > y.maxCoeff()) y = -y;  // the load's sign: the largest excursion
  std::vector<signal::Peak> pk = signal::find_peaks(y, {}, signal::Interpolation::parabolic);
  double top = 0;
  for (const auto& p : pk) top = std::max(top, p.prominence);
  std::vector<double> peaks;
  for (const auto& p : pk)
    if (p.prominence >= o.min_prominence * top) peaks.push_back(t0_s + p.position / fs_hz);
  TrainTiming best;
  double best_share = -1, best_ss = 0;
  std::vector<double> merges = o.merge_m > 0 ? std::vector<double>{o.merge_m} : std::vector<double>{1e-9, 3.5, 8.0};
  for (const double merge : merges) {
    std::vector<double> extent;
    const std::vector<double> d = axle_groups(train, merge, &extent);
    if (d.size() < 3) continue;
    double min_gap = std::numeric_limits<double>::infinity();
    for (std::size_t g = 1; g < d.size(); ++g) min_gap = std::min(min_gap, d[g] - d[g - 1]);
    const double length = d.back() - d.front();
    // Log grid: over the train's length the step drifts by a third of the tolerance at most.
    const double step = std::max(1e-5, (min_gap / 6.0) / length / 3.0);
    Pairing top_p;
    double top_v = 0, top_e = 0;
    for (double v = o.v_min; v <= o.v_max * (1 + 1e-12); v *= 1 + step) {
      const double tol = std::max(2.0 / fs_hz, min_gap / v / 6.0);
      // Anchors: one of the first 3 groups on one of the first 8 peaks (the train's head is
      // among the first; a few noise peaks before it are allowed for).
      for (std::size_t g0 = 0; g0 < std::min<std::size_t>(3, d.size()); ++g0)
        for (std::size_t j0 = 0; j0 < std::min<std::size_t>(8, peaks.size()); ++j0) {
          const double entry = peaks[j0] - d[g0] / v;
          const Pairing p = pair_groups(d, peaks, entry, v, tol, false);
          if (p.n > top_p.n || (p.n == top_p.n && p.ss < top_p.ss)) top_p = p, top_v = v, top_e = entry;
        }
    }
    if (top_p.n < 3) continue;
    // Least squares of t = entry + d·s (s = 1/v) on the pairs, re-paired until stable.
    double v = top_v, entry = top_e, se_s = 0, se_e = 0, rms = 0;
    Pairing p;
    for (int it = 0; it < 5; ++it) {
      p = pair_groups(d, peaks, entry, v, std::max(2.0 / fs_hz, min_gap / v / 6.0), true);
      if (p.n < 3) break;
      Eigen::MatrixXd A(static_cast<Index>(p.n), 2);
      Vector b(static_cast<Index>(p.n));
      for (std::size_t k = 0; k < p.n; ++k) {
        A(static_cast<Index>(k), 0) = 1.0;
        A(static_cast<Index>(k), 1) = d[p.pairs[k].first];
        b[static_cast<Index>(k)] = peaks[p.pairs[k].second];
      }
      const Eigen::Vector2d sol0 = (A.transpose() * A).ldlt().solve(A.transpose() * b);
      const double rss = (A * sol0 - b).squaredNorm();
      rms = std::sqrt(rss / static_cast<double>(p.n));
      // Each peak time's variance: the residual's (at least that of a time read to a sample,
      // 1/fs/√12), plus, for a group of several axles, where within it the merged peak falls
      // (uniform over the group's extent: a partly merged group does not peak at its centre).
      const double s2 = std::max(p.n > 2 ? rss / static_cast<double>(p.n - 2) : 0.0, 1.0 / (12.0 * fs_hz * fs_hz));
      Vector w(static_cast<Index>(p.n));
      for (std::size_t k = 0; k < p.n; ++k) {
        const double e = extent[p.pairs[k].first] / v;
        w[static_cast<Index>(k)] = 1.0 / (s2 + e * e / 12.0);
      }
      const Eigen::Matrix2d AtWA = A.transpose() * w.asDiagonal() * A;
      const Eigen::Vector2d sol = AtWA.ldlt().solve(A.transpose() * w.asDiagonal() * b);
      entry = sol[0];
      v = 1.0 / sol[1];
      const Eigen::Matrix2d cov = AtWA.inverse();
      se_e = std::sqrt(cov(0, 0));
      se_s = std::sqrt(cov(1, 1));
    }
    if (p.n < 3 || !(v > 0)) continue;
    // Not by chance: most peaks inside the train's passage are its groups', and the groups
    // matched are well beyond what peaks of that density would give (a peak within the
    // tolerance of a time with probability q: the share must exceed q by 4 standard deviations).
    const double t_a = entry + d.front() / v, t_b = entry + d.back() / v, tol = std::max(2.0 / fs_hz, min_gap / v / 6.0);
    const auto in_span = static_cast<double>(std::count_if(peaks.begin(), peaks.end(), [&](double t) { return t >= t_a - tol && t <= t_b + tol; }));
    const double q = std::min(1.0, in_span / std::max(t_b - t_a, 1.0 / fs_hz) * 2.0 * tol);
    const double share = static_cast<double>(p.n) / static_cast<double>(d.size());
    if (static_cast<double>(p.n) < 0.5 * in_span || share < q + 4.0 * std::sqrt(q * (1.0 - q) / static_cast<double>(d.size()))) continue;
    // The grouping the record matches best; equally well: the finer (more groups, more timing).
    const bool same = std::abs(share - best_share) <= 1e-12;
    if (share > best_share + 1e-12 || (same && p.n > best.n_matched) || (same && p.n == best.n_matched && p.ss < best_ss)) {
      best_share = share, best_ss = p.ss;
      best.speed = v, best.speed_se = se_s * v * v, best.entry_s = entry, best.entry_se = se_e;
      best.merge_m = merge < 1e-6 ? 0.0 : merge, best.n_groups = d.size(), best.n_matched = p.n, best.n_peaks = peaks.size();
      best.rms_residual_s = rms;
    }
  }
  if (best_share < 0.5 || best.n_matched < 3)
    throw InputError("no train found: the channel's " + std::to_string(peaks.size()) + " peaks match " +
                     (best_share < 0 ? std::string("fewer than 3") : std::to_string(best.n_matched) + " of the " + std::to_string(best.n_groups)) +
                     " axle groups of " + train.name + " at no speed between " + format_number(o.v_min * 3.6, 4) + " and " +
                     format_number(o.v_max * 3.6, 4) + " km/h (a channel that merges the train's axles and bogies cannot be timed this way: "
                     "use --model)");
  return best;
}

SignatureCheck check_train_signature(const SignatureMatch& m, const load::Train& train, ResponseKind kind, const Vector& record,
                                     double fs_hz, double t0_s, const FilterSpec& scenario_filter, double v_min, double v_max) {
  SignatureCheck c;
  c.speed_se = m.speed_se;
  if (quasi_static_kind(kind)) {
    TrainTimingOptions to;
    to.v_min = v_min, to.v_max = v_max;
    to.filter = signature_filter(scenario_filter, kind);
    try {
      const TrainTiming t = speed_from_train(record, fs_hz, t0_s, train, to);
      c.timing_checked = true;
      c.timing_speed = t.speed, c.timing_speed_se = t.speed_se;
      c.timing_entry_s = t.entry_s, c.timing_entry_se = t.entry_se;
    } catch (const InputError&) {  // the channel merges the axles: no timing without the model
    }
  }
  const double diff = std::abs(c.timing_speed - m.speed);
  if (c.timing_checked && diff > 3 * std::hypot(m.speed_se, c.timing_speed_se))
    c.flags.push_back("the model's signature gives " + format_number(m.speed * 3.6, 5) + " km/h, the axles' timing alone " +
                      format_number(c.timing_speed * 3.6, 5) + " km/h +- " + format_number(3 * c.timing_speed_se * 3.6, 3) +
                      ": the model's shape does not match the record (span, supports, track?)");
  if (m.correlation < kFlagSignatureCorrelation)
    c.flags.push_back("the model's signature matches the record poorly (correlation " + format_number(m.correlation, 3) +
                      "): the speed may be biased beyond its uncertainty");
  if (m.amplitude < 0.5 || m.amplitude > 2.0)
    c.flags.push_back("the record is " + format_number(m.amplitude, 3) + " x the model: check the model (and the channel's unit) "
                      "before trusting its timing");
  // A model the checks doubt gives a standard error that may not cover its error (an 18 m model
  // of a 15 m span: 199.6 +- 0.27 km/h, truth 200): the uncertainty then covers the model-free
  // timing's interval too.
  if (!c.flags.empty() && c.timing_checked) {
    const double se = std::max(c.speed_se, (diff + 3 * c.timing_speed_se) / 3);
    if (se > c.speed_se)
      c.flags.push_back("the uncertainty is widened to +- " + format_number(3 * se * 3.6, 3) + " km/h to cover the axles' timing alone (" +
                        format_number(c.timing_speed * 3.6, 5) + " km/h +- " + format_number(3 * c.timing_speed_se * 3.6, 3) + ")");
    c.speed_se = se;
  }
  return c;
}

}  // namespace viaduct::study
