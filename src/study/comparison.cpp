#include "viaduct/study/comparison.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace

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
  const auto n_m = static_cast<Index>(std::floor(static_cast<double>(model.size() - 1) / fs_model * fs_record)) + 1;
  Vector mod_r(n_m);
  for (Index j = 0; j < n_m; ++j) mod_r[j] = detail::sample_at(mod, fs_model, static_cast<double>(j) / fs_record);
  const auto max_lag = static_cast<Index>(std::ceil(o.max_shift_s * fs_record));
  const double lag = signal::best_lag(mod_r, rec, max_lag);
  c.shift_s = t0_record + lag / fs_record;
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

}  // namespace viaduct::study
