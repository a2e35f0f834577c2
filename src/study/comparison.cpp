#include "viaduct/study/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include <Eigen/Dense>

#include "series.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::study {

namespace {

double main_peak_hz(const Vector& f, const Vector& amp, double f_max) {
  Index n = 0;
  while (n < f.size() && f[n] <= f_max) ++n;
  if (n < 3) return 0.0;
  signal::PeakOptions o;
  o.max_peaks = 1;
  const auto p = signal::find_peaks(amp.head(n), o);
  if (p.empty()) return 0.0;
  return p.front().position * (f[1] - f[0]);
}

std::string cmp_num(double v) { return format_number(v, 4); }

// The record must hold the model's whole response once aligned (|model| >= 5 % of its peak, in
// record samples [a, b]) and must move while it does.
void require_coverage(const Vector& record, double fs_record, double t0_record, const Vector& mod, double fs_model,
                      double lag, const ComparisonOptions& o) {
  const double peak = mod.cwiseAbs().maxCoeff();
  if (!(peak > 0.0)) return;
  Index j0 = 0, j1 = mod.size() - 1;
  while (j0 < j1 && std::abs(mod[j0]) < 0.05 * peak) ++j0;
  while (j1 > j0 && std::abs(mod[j1]) < 0.05 * peak) --j1;
  const double a = static_cast<double>(j0) / fs_model * fs_record + lag, b = static_cast<double>(j1) / fs_model * fs_record + lag;
  const auto n = static_cast<double>(record.size());
  auto at = [&](double i) { return cmp_num(t0_record + i / fs_record); };
  // (two samples of slack: a record cut at the response's last sample, resampled, may end a sample short)
  if (a < -2.0 || b > n + 1.0)
    throw InputError("the record covers t = " + at(0) + " to " + at(n - 1) + " s, but the passage's response (the model above 5 % "
                     "of its peak, aligned) runs from t = " + at(a) + " to " + at(b) +
                     " s: the record lost part of the passage, and a comparison over what is left would be wrong");
  // A stuck channel: one value repeated while the model's response runs.
  const Index lo = std::max<Index>(0, static_cast<Index>(std::floor(a))), hi = std::min<Index>(record.size() - 1, static_cast<Index>(std::ceil(b)));
  const Index need = std::max<Index>(16, static_cast<Index>(std::ceil(o.stuck_s * fs_record)));
  Index run = 1;
  for (Index i = lo + 1; i <= hi; ++i) {
    run = record[i] == record[i - 1] ? run + 1 : 1;
    if (run >= need)
      throw InputError("the record holds " + cmp_num(record[i]) + " unchanged from t = " + at(static_cast<double>(i - run + 1)) +
                       " s for " + std::to_string(run) + " samples or more while the passage's response runs (t = " + at(a) +
                       " to " + at(b) + " s): a stuck channel, not a measurement");
  }
}

}  // namespace

ResidualStructure residual_structure(const Vector& record, const Vector& model, double fs_hz) {
  const Index n = record.size();
  if (model.size() != n || n < 16) throw InputError("residual_structure: record and model of one size, at least 16 samples");
  require_positive(fs_hz, "residual_structure: sampling rate [Hz]");
  const double nn = static_cast<double>(n);
  // Least squares on the normal equations of a few regressors (the model, and the structure's).
  auto rss_of = [&](const std::vector<const Vector*>& x, Vector* beta) {
    const auto p = static_cast<Index>(x.size());
    Matrix A(p, p);
    Vector y(p);
    for (Index i = 0; i < p; ++i) {
      y[i] = x[static_cast<std::size_t>(i)]->dot(record);
      for (Index j = 0; j < p; ++j) A(i, j) = x[static_cast<std::size_t>(i)]->dot(*x[static_cast<std::size_t>(j)]);
    }
    const Vector b = A.completeOrthogonalDecomposition().solve(y);
    if (beta) *beta = b;
    return std::max(0.0, record.squaredNorm() - b.dot(y));
  };
  const Vector one = Vector::Ones(n);
  Vector ramp(n);
  for (Index i = 0; i < n; ++i) ramp[i] = static_cast<double>(i) / (nn - 1.0) - 0.5;
  const double rss0 = rss_of({&model}, nullptr);
  Vector b1, b3;
  const double rss1 = rss_of({&model, &one}, &b1);
  const double rss3 = rss_of({&model, &one, &ramp}, &b3);
  // The step: every position k, with suffix sums (the 3 x 3 normal equations in O(1) each).
  const double smm = model.squaredNorm(), sm = model.sum(), smr = model.dot(record), sr = record.sum(), srr = record.squaredNorm();
  double best_rss = rss1, best_c = 0.0;
  Index best_k = -1;
  double tm = 0.0, tr = 0.0;  // suffix sums of the model and the record from k on
  std::vector<double> sm_k(static_cast<std::size_t>(n) + 1, 0.0), sr_k(static_cast<std::size_t>(n) + 1, 0.0);
  for (Index i = n - 1; i >= 0; --i) {
    tm += model[i], tr += record[i];
    sm_k[static_cast<std::size_t>(i)] = tm, sr_k[static_cast<std::size_t>(i)] = tr;
  }
  for (Index k = n / 20; k <= n - n / 20; ++k) {
    const double nk = nn - static_cast<double>(k), mk = sm_k[static_cast<std::size_t>(k)], rk = sr_k[static_cast<std::size_t>(k)];
    Eigen::Matrix3d A;
    A << smm, sm, mk, sm, nn, nk, mk, nk, nk;
    const Eigen::Vector3d y(smr, sr, rk);
    const Eigen::Vector3d b = A.colPivHouseholderQr().solve(y);
    const double rss = std::max(0.0, srr - b.dot(y));
    if (rss < best_rss) best_rss = rss, best_c = b[2], best_k = k;
  }
  ResidualStructure out;
  out.noise_rms = std::sqrt(rss0 / nn);
  // A structure counts when it halves what the model leaves and stands 6 noise RMS above what it leaves.
  auto counts = [&](double rss, double size) { return rss < 0.5 * rss0 && std::abs(size) > 6.0 * std::sqrt(rss / nn); };
  const bool step = best_k >= 0 && counts(best_rss, best_c), drift = counts(rss3, b3[2]);
  if (step && (!drift || best_rss <= rss3)) {
    out.kind = "step", out.size = best_c, out.at_s = static_cast<double>(best_k) / fs_hz, out.noise_rms = std::sqrt(best_rss / nn);
  } else if (drift) {
    out.kind = "drift", out.size = b3[2], out.noise_rms = std::sqrt(rss3 / nn);
  } else if (counts(rss1, b1[1])) {
    out.kind = "offset", out.size = b1[1], out.noise_rms = std::sqrt(rss1 / nn);
  }
  return out;
}

ChannelComparison compare_channel(const Vector& record, double fs_record, double t0_record, const Vector& model,
                                  double fs_model, const ComparisonOptions& o) {
  require_positive(fs_record, "record sampling rate [Hz]");
  require_positive(fs_model, "model sampling rate [Hz]");
  require_positive(o.max_shift_s, "max_shift_s [s]");
  require_finite(t0_record, "record start time [s]");
  if (!record.allFinite() || !model.allFinite()) throw InputError("comparison: non-finite samples");
  if (record.size() < 16 || model.size() < 16) throw InputError("comparison: signals shorter than 16 samples");
  ChannelComparison c;
  // 1. the same filter on both
  Vector rec = record, mod = model;
  if (o.filter.enabled) {
    rec = signal::sosfiltfilt(signal::cheby1(o.filter.cheby, fs_record), record);
    mod = signal::sosfiltfilt(signal::cheby1(o.filter.cheby, fs_model), model);
  }
  // 2. model onto the record's rate, then 3. align by cross-correlation
  const double n_resampled = std::floor(static_cast<double>(model.size() - 1) / fs_model * fs_record) + 1;
  if (!(n_resampled <= 5e7))  // 400 MB of samples, and as many again for the alignment: a wrong rate
    throw InputError("comparison: the model's " + cmp_num(static_cast<double>(model.size() - 1) / fs_model) +
                     " s at the record's rate, " + cmp_num(fs_record) + " Hz, would be " + cmp_num(n_resampled) +
                     " samples: check the record's sampling rate");
  const auto n_m = static_cast<Index>(n_resampled);
  Vector mod_r(n_m);
  for (Index j = 0; j < n_m; ++j) mod_r[j] = detail::sample_at(mod, fs_model, static_cast<double>(j) / fs_record);
  const auto max_lag = static_cast<Index>(std::ceil(o.max_shift_s * fs_record));
  const double lag = std::isfinite(o.shift_s) ? (o.shift_s - t0_record) * fs_record : signal::best_lag(mod_r, rec, max_lag);
  c.shift_s = t0_record + lag / fs_record;
  require_coverage(record, fs_record, t0_record, mod, fs_model, lag, o);
  // 4. aligned model on the record grid; overlap where the model exists
  const Index n = record.size();
  c.t.resize(n);
  c.record = rec;
  c.model.resize(n);
  std::vector<Index> overlap;
  const double t_model_end = static_cast<double>(model.size() - 1) / fs_model;
  for (Index j = 0; j < n; ++j) {
    c.t[j] = t0_record + static_cast<double>(j) / fs_record;
    const double tm = (static_cast<double>(j) - lag) / fs_record;
    c.model[j] = detail::sample_at(mod, fs_model, tm);
    if (tm >= 0.0 && tm <= t_model_end) overlap.push_back(j);
  }
  if (overlap.size() < 16) throw InputError("comparison: record and aligned model overlap by fewer than 16 samples");
  Vector ro(static_cast<Index>(overlap.size())), mo(static_cast<Index>(overlap.size()));
  for (std::size_t k = 0; k < overlap.size(); ++k) {
    ro[static_cast<Index>(k)] = rec[overlap[k]];
    mo[static_cast<Index>(k)] = c.model[overlap[k]];
  }
  c.peak_record = ro.cwiseAbs().maxCoeff();
  c.peak_model = mo.cwiseAbs().maxCoeff();
  c.peak_ratio = c.peak_record > 0 ? c.peak_model / c.peak_record : 0.0;
  const double rms_r = std::sqrt(ro.squaredNorm() / static_cast<double>(ro.size()));
  const double rms_m = std::sqrt(mo.squaredNorm() / static_cast<double>(mo.size()));
  c.rms_ratio = rms_r > 0 ? rms_m / rms_r : 0.0;
  c.correlation = detail::pearson(ro, mo);
  // 5. spectra of the aligned signals over the record window
  const auto ar = signal::amplitude_spectrum(c.record, fs_record, signal::Window::hann);
  const auto am = signal::amplitude_spectrum(c.model, fs_record, signal::Window::hann);
  c.frequency_hz = ar.frequency_hz;
  c.record_amplitude = ar.amplitude;
  c.model_amplitude = am.amplitude;
  double f_max = o.spectrum_max_hz > 0 ? o.spectrum_max_hz : fs_record / 2;
  if (o.spectrum_max_hz <= 0 && o.filter.enabled && o.filter.cheby.band != signal::BandType::highpass)
    f_max = o.filter.cheby.high_hz;
  c.f_peak_record_hz = main_peak_hz(ar.frequency_hz, ar.amplitude, f_max);
  c.f_peak_model_hz = main_peak_hz(am.frequency_hz, am.amplitude, f_max);
  Index nf = 0;
  while (nf < ar.frequency_hz.size() && ar.frequency_hz[nf] <= f_max) ++nf;
  c.spectral_correlation = detail::pearson(ar.amplitude.head(nf), am.amplitude.head(nf));
  return c;
}


ZeroSpec parse_zero(const std::string& text, const std::string& who) {
  ZeroSpec z;
  if (text == "keep" || text.empty()) return z;
  if (text == "pre-entry") {
    z.mode = ZeroSpec::Mode::pre_entry;
    return z;
  }
  const auto colon = text.find(':');
  char* end = nullptr;
  if (colon != std::string::npos) {
    const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
    z.start_s = std::strtod(a.c_str(), &end);
    const bool ok_a = !a.empty() && end == a.c_str() + a.size();
    z.end_s = std::strtod(b.c_str(), &end);
    const bool ok_b = !b.empty() && end == b.c_str() + b.size();
    if (ok_a && ok_b && std::isfinite(z.start_s) && std::isfinite(z.end_s) && z.end_s > z.start_s) {
      z.mode = ZeroSpec::Mode::window;
      return z;
    }
  }
  throw InputError(who + ": '" + text + "' is not pre-entry, keep or START:END (seconds of record time, START < END)");
}

Level level_between(const Vector& x, double fs_hz, double t0_s, double from_s, double to_s, const std::string& channel,
                    const std::string& who) {
  Level l;
  const double k0 = std::max(0.0, std::ceil((from_s - t0_s) * fs_hz - 1e-9));
  const double k1 = std::min(static_cast<double>(x.size() - 1), std::floor((to_s - t0_s) * fs_hz + 1e-9));
  l.from_s = t0_s + k0 / fs_hz;
  l.to_s = t0_s + k1 / fs_hz;
  l.n = k1 >= k0 ? static_cast<Index>(k1 - k0) + 1 : 0;
  if (l.n < 10)
    throw InputError(who + ": channel " + channel + " holds " + std::to_string(l.n) + " samples between t = " + cmp_num(from_s) + " and " +
                     cmp_num(to_s) + " s, too few for its zero (10 at least): give a window of the record where the bridge is "
                     "unloaded, --zero START:END");
  const auto seg = x.segment(static_cast<Index>(k0), l.n);
  if (!seg.allFinite()) throw InputError(who + ": channel " + channel + " misses samples between t = " + cmp_num(l.from_s) + " and " + cmp_num(l.to_s) + " s, the span of its zero");
  l.mean = seg.mean();
  l.noise = std::sqrt((seg.array() - l.mean).square().sum() / static_cast<double>(std::max<Index>(1, l.n - 1)));
  return l;
}

std::string offset_warning(const Level& pre, double peak, const std::string& channel, const std::string& unit) {
  const double a = std::abs(pre.mean);
  if (!(a > 2.0 * pre.noise) || !(a > 0.01 * peak)) return "";
  return "channel " + channel + ": its mean before the train's entry (t = " + cmp_num(pre.from_s) + " to " + cmp_num(pre.to_s) + " s) is " +
         cmp_num(pre.mean) + " " + unit + ", beyond its noise (" + cmp_num(pre.noise) + " " + unit + ") and " +
         cmp_num(100.0 * a / std::max(peak, 1e-300)) + " % of its peak: a zero offset? --zero pre-entry removes it";
}

std::string unit_slip_warning(double peak_ratio, double rms_ratio, double correlation, const std::string& channel,
                              double band) {
  struct Factor {
    double f;
    const char* what;
  };
  static const Factor factors[] = {{9.80665, "between g and m/s²"},
                                   {1e3, "between mm and m, kN and N, or mm/s² and m/s²"},
                                   {1e6, "between µε and ε"}};
  if (!(correlation >= 0.8) || !(peak_ratio > 0.0) || !(rms_ratio > 0.0) || !(band > 1.0)) return "";
  const double tol = std::log(band);
  for (const Factor& u : factors)
    for (const double sign : {1.0, -1.0}) {
      const double f = std::pow(u.f, sign);
      if (std::abs(std::log(peak_ratio / f)) < tol && std::abs(std::log(rms_ratio / f)) < tol)
        return "channel " + channel + ": the record reads " + cmp_num(sign > 0 ? peak_ratio : 1.0 / peak_ratio) + " times " +
               (sign > 0 ? "smaller" : "larger") + " than the model at the peak (" +
               cmp_num(sign > 0 ? rms_ratio : 1.0 / rms_ratio) + " by RMS) with the same shape (correlation " +
               cmp_num(correlation) + "): close to " + cmp_num(u.f) + ", the factor " + u.what +
               ". A unit slip? Check the unit the channel's name gives (its suffix, e.g. _g or _mm; --unit for a name "
               "without one)";
    }
  return "";
}

double response_onset_s(const Vector& model, double fs_model) {
  if (model.size() == 0) return 0.0;
  const double peak = model.cwiseAbs().maxCoeff();
  Index j = 0;
  while (j < model.size() && std::abs(model[j]) <= 0.01 * peak) ++j;
  return peak > 0.0 ? static_cast<double>(j) / fs_model : 0.0;
}

ZeroOutcome apply_zero(const ZeroSpec& z, Vector& x, double fs_hz, double t0_s, double entry_s, const std::string& channel,
                       const std::string& unit, const std::string& who) {
  ZeroOutcome out;
  if (z.mode == ZeroSpec::Mode::keep) {
    try {
      const Level pre = level_between(x, fs_hz, t0_s, t0_s, entry_s, channel, who);
      out.level_seen = pre.mean;
      out.warning = offset_warning(pre, x.cwiseAbs().maxCoeff(), channel, unit);
    } catch (const InputError&) {  // too little record before the entry to tell
    }
    return out;
  }
  if (z.mode == ZeroSpec::Mode::pre_entry && !std::isfinite(entry_s))
    throw InputError(who + ": --zero pre-entry needs the train's entry time; give --zero START:END");
  const Level l = z.mode == ZeroSpec::Mode::window ? level_between(x, fs_hz, t0_s, z.start_s, z.end_s, channel, who)
                                                   : level_between(x, fs_hz, t0_s, t0_s, entry_s, channel, who);
  x.array() -= l.mean;
  out.removed = l.mean;
  return out;
}

}  // namespace viaduct::study
