#include "viaduct/ident/frf_estimate.hpp"

#include <algorithm>

#include "viaduct/core/error.hpp"

namespace viaduct::ident {

FrfMethod frf_method(const std::string& name, const std::string& what) {
  if (name == "welch") return FrfMethod::welch;
  if (name == "stepped") return FrfMethod::stepped;
  if (name == "swept") return FrfMethod::swept;
  throw InputError(what + " must be welch, stepped or swept, got '" + name + "'");
}

namespace {

// Welch H1 (or H2) and coherence on the lines above 0 Hz inside [f_min, f_max].
void welch_estimate(const Vector& force, const Matrix& resp, double fs_hz, const FrfEstimateOptions& o, FrfEstimate& e) {
  const WelchFrf w = welch_frf(force, resp, fs_hz, o.welch);
  const double fmin = o.f_min_hz.value_or(0.0);
  const double fmax = o.f_max_hz.value_or(0.5 * fs_hz);
  std::vector<Index> keep;
  for (Index k = 0; k < w.frequency_hz.size(); ++k)
    if (w.frequency_hz[k] > 0.0 && w.frequency_hz[k] >= fmin && w.frequency_hz[k] <= fmax) keep.push_back(k);
  if (keep.size() < 2) throw InputError("fewer than 2 Welch lines in [--f-min, --f-max]");
  Frf& frf = e.frf;
  frf.frequency_hz.resize(static_cast<Index>(keep.size()));
  frf.h.resize(static_cast<Index>(keep.size()), resp.cols());
  frf.coherence.resize(static_cast<Index>(keep.size()), resp.cols());
  for (std::size_t j = 0; j < keep.size(); ++j) {
    frf.frequency_hz[static_cast<Index>(j)] = w.frequency_hz[keep[j]];
    frf.h.row(static_cast<Index>(j)) = (o.h2 ? w.h2 : w.h1).row(keep[j]);
    frf.coherence.row(static_cast<Index>(j)) = w.coherence.row(keep[j]);
  }
  e.n_segments = w.n_segments;
}

// One FRF point per dwell, sorted by frequency (schedules may go down or repeat).
void stepped_estimate(const Vector& force, const Matrix& resp, double fs_hz, double t0_s, const FrfEstimateOptions& o,
                      FrfEstimate& e) {
  e.steps = o.steps;
  if (e.steps.empty()) {
    e.steps = detect_steps(force, fs_hz, t0_s);
    e.steps_detected = true;
  }
  e.points = stepped_sine(force, resp, fs_hz, t0_s, e.steps, o.stepped);
  const Index n = static_cast<Index>(e.points.size());
  e.order.resize(e.points.size());
  for (std::size_t k = 0; k < e.order.size(); ++k) e.order[k] = k;
  std::stable_sort(e.order.begin(), e.order.end(),
                   [&](auto a, auto b) { return e.points[a].frequency_hz < e.points[b].frequency_hz; });
  e.frf.frequency_hz.resize(n);
  e.frf.h.resize(n, resp.cols());
  for (Index j = 0; j < n; ++j) {
    const auto& p = e.points[e.order[static_cast<std::size_t>(j)]];
    e.frf.frequency_hz[j] = p.frequency_hz;
    e.frf.h.row(j) = p.h.transpose();
  }
  for (const auto& p : e.points) {
    e.worst_settle_change = std::max(e.worst_settle_change, p.settle_change.maxCoeff());
    e.worst_distortion = std::max({e.worst_distortion, p.force_distortion, p.response_distortion.maxCoeff()});
  }
}

}  // namespace

FrfEstimate estimate_frf(const Vector& force, const Matrix& responses, double fs_hz, double t0_s,
                         const FrfEstimateOptions& o) {
  FrfEstimate e;
  switch (o.method) {
    case FrfMethod::welch:
      welch_estimate(force, responses, fs_hz, o, e);
      break;
    case FrfMethod::stepped:
      stepped_estimate(force, responses, fs_hz, t0_s, o, e);
      break;
    case FrfMethod::swept: {
      if (!o.f_min_hz || !o.f_max_hz) throw InputError("--method swept needs --f-min and --f-max (the swept band)");
      SweptSineOptions so;
      so.f_min_hz = *o.f_min_hz;
      so.f_max_hz = *o.f_max_hz;
      e.frf = swept_sine(force, responses, fs_hz, so);
      break;
    }
  }
  return e;
}

}  // namespace viaduct::ident
