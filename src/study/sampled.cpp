#include "viaduct/study/sampled.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "viaduct/core/error.hpp"

namespace viaduct::study {

SampledRunSummary run_samples(Index begin, Index end, const VariantMaker& make, const BatchSink& sink,
                              const SampledRunOptions& options) {
  if (options.batch < 1 || options.threads < 1 || begin < 0 || end < begin)
    throw InputError("SampledRunOptions: violated constraint batch >= 1, threads >= 1, 0 <= begin <= end");
  const auto t0 = std::chrono::steady_clock::now();
  SampledRunSummary sum;
  SweepOptions so;
  so.threads = options.threads;
  so.runner = options.runner;
  for (Index first = begin; first < end; first += options.batch) {
    const Index last = std::min(end, first + options.batch);
    std::vector<Variant> variants;
    for (Index s = first; s < last; ++s) {
      variants.push_back(make(s));
      variants.back().label = std::to_string(s);  // rows name their sample
    }
    const SweepResult r = run_sweep(variants, so);
    SampleBatch b;
    b.begin = first;
    b.end = last;
    b.n_cases = Index(r.summary.n_cases);
    b.n_steps = r.summary.n_steps_total;
    for (const EnvelopeRow& row : r.rows)
      b.peaks.push_back({std::stoll(row.variant), row.train, row.station, row.speed, row.max_abs_acc, row.max_abs_disp});
    for (const CaseFailure& f : r.failures)
      b.failures.push_back({std::stoll(f.variant), f.train, f.speed, f.message, f.input_error});
    sum.n_samples += last - first;
    sum.n_cases += b.n_cases;
    sum.n_failed += Index(r.failures.size());
    sum.n_steps_total += b.n_steps;
    sink(b);
    if (options.progress) options.progress(std::size_t(last - begin), std::size_t(end - begin));
  }
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

ResponseStats response_statistics(const std::vector<double>& by_sample, const SampleDesign& layout, double limit,
                                  const SampleStatsOptions& options) {
  ResponseStats out;
  std::vector<double> values;
  for (std::size_t s = 0; s < by_sample.size(); ++s)
    if (layout.independent(Index(s)) && !std::isnan(by_sample[s])) values.push_back(by_sample[s]);
  out.n = Index(values.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.percentiles.assign(options.percentiles.size(), nan);
  out.mean = out.sd = nan;
  if (!values.empty()) {
    double m = 0.0;
    for (double x : values) m += x;
    m /= double(values.size());
    double v = 0.0;
    for (double x : values) v += (x - m) * (x - m);
    out.mean = m;
    out.sd = values.size() > 1 ? std::sqrt(v / double(values.size() - 1)) : nan;
    std::sort(values.begin(), values.end());
    for (std::size_t i = 0; i < options.percentiles.size(); ++i)
      out.percentiles[i] = percentile_of_sorted(values, options.percentiles[i]);
    if (!std::isnan(limit)) out.exceed = exceedance(values, limit);
  }
  if (!layout.saltelli) return out;
  const Index g = layout.d + 2;
  std::vector<Index> complete;
  for (Index j = 0; j < layout.n_base && (j + 1) * g <= Index(by_sample.size()); ++j) {
    bool all = true;
    for (Index b = 0; b < g; ++b) all = all && !std::isnan(by_sample[std::size_t(j * g + b)]);
    if (all) complete.push_back(j);
  }
  out.n_base = Index(complete.size());
  if (out.n_base < 2) {
    out.sobol.assign(std::size_t(layout.d), SobolIndex{nan, nan, nan, nan, nan, nan});
    return out;
  }
  Vector fa(out.n_base), fb(out.n_base);
  Matrix fab(out.n_base, layout.d);
  for (Index k = 0; k < out.n_base; ++k) {
    const std::size_t base = std::size_t(complete[std::size_t(k)] * g);
    fa(k) = by_sample[base];
    fb(k) = by_sample[base + 1];
    for (Index i = 0; i < layout.d; ++i) fab(k, i) = by_sample[base + 2 + std::size_t(i)];
  }
  out.sobol = sobol_indices(fa, fb, fab, options.sobol);
  return out;
}

}  // namespace viaduct::study
