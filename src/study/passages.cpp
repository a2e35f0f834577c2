#include "viaduct/study/passages.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/speed.hpp"

namespace viaduct::study {

bool PassageOptions::is_valid(std::string* why) const {
  OptionsCheck c("PassageOptions", why);
  return c.require(v_min > 0.0 && std::isfinite(v_min), "v_min", v_min, "v_min > 0") &&
         c.require(v_max > v_min && std::isfinite(v_max), "v_max", v_max, "v_max > v_min") &&
         c.require(grid_step > 0.0 && grid_step <= 0.2, "grid_step", grid_step, "0 < grid_step <= 0.2") &&
         c.require(speed_band >= 0.0 && std::isfinite(speed_band), "speed_band", speed_band, "speed_band >= 0") &&
         c.require(noise_band > 0.0 && std::isfinite(noise_band), "noise_band", noise_band, "noise_band > 0") &&
         c.require(threads >= 1, "threads", threads, "threads >= 1");
}

double filtered_peak(const Vector& x, double fs_hz, const FilterSpec& f) {
  if (x.size() == 0) return 0.0;
  if (!f.enabled) return x.cwiseAbs().maxCoeff();
  return signal::max_abs_between_samples(signal::sosfiltfilt(signal::cheby1(f.cheby, fs_hz), x));
}

namespace {

// A (station, response) pair some passage maps a channel to.
struct Need {
  std::size_t station;
  ResponseKind kind;
  bool operator==(const Need& o) const { return station == o.station && kind == o.kind; }
};

// The model's filtered peak of every need for `train` at `v`; the run itself into *keep.
std::vector<double> model_peaks(const PreparedModel& m, const RunSettings& rs, const FilterSpec& filter, const load::Train& train,
                                double v, const std::vector<Need>& needs, RunResult* keep = nullptr) {
  RunResult r = simulate(m, train, v, rs);
  const double fs = 1.0 / rs.dt;
  std::vector<double> out;
  for (const Need& n : needs) out.push_back(filtered_peak(station_response(r, n.station, n.kind), fs, filter_for(filter, n.kind)));
  if (keep) *keep = std::move(r);
  return out;
}

// The filtered record against the aligned model at the passage's speed: least-squares amplitude
// over their overlap, then the residual's RMS and the correlation.
void residual_of(const PassageChannel& ch, const Passage& p, const Vector& model, double fs_model, const FilterSpec& f,
                 double shift_s, ChannelVerdict& v) {
  ComparisonOptions co;
  co.filter = f;
  co.max_shift_s = static_cast<double>(ch.x.size()) / p.fs_hz + static_cast<double>(model.size()) / fs_model;
  co.shift_s = shift_s;  // the identification's, when there is one: an offset cannot pull the alignment
  const ChannelComparison cc = compare_channel(ch.x, p.fs_hz, p.t0_s, model, fs_model, co);
  Index i0 = 0, i1 = cc.model.size() - 1;
  while (i0 < i1 && cc.model[i0] == 0.0) ++i0;
  while (i1 > i0 && cc.model[i1] == 0.0) --i1;
  const Vector r = cc.record.segment(i0, i1 - i0 + 1), mo = cc.model.segment(i0, i1 - i0 + 1);
  // The noise once the model is taken out, and whatever structure the model does not have (an
  // offset, a step, a drift): counted as noise it would widen the band that judges the peak.
  const ResidualStructure rs = residual_structure(r, mo, p.fs_hz);
  v.noise_rms = rs.noise_rms;
  v.residual = rs.kind;
  v.residual_size = rs.size;
  v.correlation = cc.correlation;
  v.unit_warning = unit_slip_warning(cc.peak_ratio, cc.rms_ratio, cc.correlation, ch.name);
}

// A deflection or strain channel's zero: the record before the train's entry (where the aligned
// model's response rises above 1 % of its peak) is its level; removed when asked, else reported
// when it is an offset.
void zero_passage_channel(PassageChannel& ch, const Passage& p, const Vector& model, double fs_model, const FilterSpec& f,
                          double shift_s, const ZeroSpec& zero, ChannelVerdict& v) {
  double entry = std::numeric_limits<double>::quiet_NaN();
  if (zero.mode != ZeroSpec::Mode::window) {
    ComparisonOptions co;
    co.filter = f;
    co.max_shift_s = static_cast<double>(ch.x.size()) / p.fs_hz + static_cast<double>(model.size()) / fs_model;
    co.shift_s = shift_s;
    entry = compare_channel(ch.x, p.fs_hz, p.t0_s, model, fs_model, co).shift_s + response_onset_s(model, fs_model);
  }
  const ZeroOutcome z = apply_zero(zero, ch.x, p.fs_hz, p.t0_s, entry, ch.name, response_unit(ch.kind), "passage " + p.name);
  v.zero_removed = z.removed;
  v.zero_level_seen = z.level_seen;
  v.offset_warning = z.warning;
}

void check_passage(const Passage& p, std::size_t n_trains, std::size_t n_stations) {
  if (p.train >= n_trains) throw InputError("passage " + p.name + ": train index out of range");
  require_positive(p.fs_hz, "passage " + p.name + ": sampling rate [Hz]");
  require_finite(p.t0_s, "passage " + p.name + ": start time [s]");
  if (p.channels.empty()) throw InputError("passage " + p.name + ": no channels");
  if (!(p.speed >= 0.0) || !std::isfinite(p.speed)) throw InputError("passage " + p.name + ": speed must be >= 0 (0: identify)");
  for (const auto& ch : p.channels) {
    if (ch.station >= n_stations) throw InputError("passage " + p.name + ": channel " + ch.name + " maps to a station out of range");
    if (ch.x.size() < 16) throw InputError("passage " + p.name + ": channel " + ch.name + " has fewer than 16 samples");
    if (!ch.x.allFinite()) throw InputError("passage " + p.name + ": channel " + ch.name + " has non-finite samples");
  }
}

// One passage: speed, the model at it and its uncertainty's ends, each channel's verdict.
PassageResult run_passage(const PreparedModel& m, const RunSettings& rs, const FilterSpec& filter, const load::Train& train,
                          const Passage& p, const PassageOptions& o) {
  PassageResult res;
  res.name = p.name;
  res.train = train.name;
  const double fs_model = 1.0 / rs.dt;
  const PassageChannel& first = p.channels.front();
  double shift_s = std::numeric_limits<double>::quiet_NaN();  // the model's t = 0 in record time, when identified
  if (p.speed > 0.0) {
    res.speed = p.speed;
  } else {
    const SignatureMatch sm = match_train_signature(m, rs, train, first.station, first.kind, first.x, p.fs_hz, p.t0_s, filter, o.v_min,
                                                    o.v_max, o.grid_step);
    const SignatureCheck check = check_train_signature(sm, train, first.kind, first.x, p.fs_hz, p.t0_s, filter, o.v_min, o.v_max);
    res.speed = sm.speed;
    res.speed_se = check.speed_se;
    res.speed_flags = check.flags;
    res.identified = true;
    res.signature_correlation = sm.correlation;
    shift_s = sm.shift_s;
  }
  std::vector<Need> needs;
  for (const auto& ch : p.channels) needs.push_back({ch.station, ch.kind});
  RunResult at_v;
  const std::vector<double> pred = model_peaks(m, rs, filter, train, res.speed, needs, &at_v);
  std::vector<double> lo = pred, hi = pred;
  const double band = o.speed_band * res.speed_se;
  for (double k : {-1.0, -0.5, 0.5, 1.0}) {
    const double u = res.speed + k * band;
    if (band == 0.0 || !(u > 0.0)) continue;
    const std::vector<double> q = model_peaks(m, rs, filter, train, u, needs);
    for (std::size_t i = 0; i < q.size(); ++i) lo[i] = std::min(lo[i], q[i]), hi[i] = std::max(hi[i], q[i]);
  }
  for (std::size_t i = 0; i < p.channels.size(); ++i) {
    PassageChannel ch = p.channels[i];
    ChannelVerdict v;
    if (quasi_static_kind(ch.kind)) zero_passage_channel(ch, p, station_response(at_v, ch.station, ch.kind), fs_model,
                                                                    filter_for(filter, ch.kind), shift_s, o.zero, v);
    v.channel = ch.name;
    v.station = m.stations[ch.station].name;
    v.kind = ch.kind;
    const FilterSpec f = filter_for(filter, ch.kind);
    v.measured = filtered_peak(ch.x, p.fs_hz, f);
    v.predicted = pred[i];
    v.predicted_low = lo[i];
    v.predicted_high = hi[i];
    v.ratio = pred[i] > 0 ? v.measured / pred[i] : std::numeric_limits<double>::quiet_NaN();
    residual_of(ch, p, station_response(at_v, ch.station, ch.kind), fs_model, f, shift_s, v);
    // A structured residual leaves the peak unjudged: not within (the flag says why).
    if (!v.offset_warning.empty() && v.residual == "white") {  // an offset before the entry: the peak is not judged
      v.residual = "offset";
      v.residual_size = v.zero_level_seen;
    }
    v.within = v.residual == "white" && v.unit_warning.empty() && v.measured >= lo[i] - o.noise_band * v.noise_rms &&
               v.measured <= hi[i] + o.noise_band * v.noise_rms;
    res.channels.push_back(v);
  }
  return res;
}

}  // namespace

PassageStudy run_passages(const PreparedModel& m, const RunSettings& settings, const FilterSpec& filter,
                          const std::vector<load::Train>& trains, const std::vector<double>& speeds,
                          const std::vector<Passage>& passages, const PassageOptions& options) {
  std::string why;
  if (!options.is_valid(&why)) throw InputError("passages: " + why);
  if (speeds.empty()) throw InputError("passages: no speeds for the model's envelope");
  for (double v : speeds) require_positive(v, "passages: envelope speed [m/s]");
  RunSettings rs = settings;
  rs.filter.enabled = false;  // every response is filtered here, record and model alike
  // The trains used and the (station, response) pairs mapped, in order of appearance.
  std::vector<std::size_t> used;
  std::vector<Need> needs;
  for (const auto& p : passages) {
    if (p.train < trains.size() && std::find(used.begin(), used.end(), p.train) == used.end()) used.push_back(p.train);
    for (const auto& ch : p.channels)
      if (ch.station < m.stations.size() && std::find(needs.begin(), needs.end(), Need{ch.station, ch.kind}) == needs.end())
        needs.push_back({ch.station, ch.kind});
  }
  std::vector<double> sorted = speeds;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n_cases = used.size() * sorted.size(), total = n_cases + passages.size();
  std::vector<std::vector<double>> case_peaks(n_cases);
  std::vector<std::string> case_failure(n_cases);
  std::atomic<std::size_t> done{0};
  auto tick = [&] {
    const std::size_t d = ++done;
    if (options.progress) options.progress(d, total);
  };
  parallel_for(n_cases, options.threads, [&](std::size_t i, int) {
    try {
      case_peaks[i] = model_peaks(m, rs, filter, trains[used[i / sorted.size()]], sorted[i % sorted.size()], needs);
    } catch (const std::exception& e) {
      case_peaks[i].clear();  // the curve goes without this speed, and says so
      case_failure[i] = e.what();
    }
    tick();
  });
  PassageStudy out;
  for (std::size_t t = 0; t < used.size(); ++t)
    for (std::size_t n = 0; n < needs.size(); ++n) {
      EnvelopeCurve c;
      c.train = trains[used[t]].name;
      c.station = m.stations[needs[n].station].name;
      c.kind = needs[n].kind;
      for (std::size_t s = 0; s < sorted.size(); ++s) {
        const auto& cp = case_peaks[t * sorted.size() + s];
        if (cp.empty()) {
          if (n == 0)
            out.envelope_failures.push_back(c.train + " at " + std::to_string(sorted[s] * 3.6) + " km/h: " + case_failure[t * sorted.size() + s]);
          continue;
        }
        c.speeds.push_back(sorted[s]);
        c.peaks.push_back(cp[n]);
      }
      out.curves.push_back(std::move(c));
    }
  out.passages.resize(passages.size());
  parallel_for(passages.size(), options.threads, [&](std::size_t i, int) {
    const Passage& p = passages[i];
    try {
      check_passage(p, trains.size(), m.stations.size());
      out.passages[i] = run_passage(m, rs, filter, trains[p.train], p, options);
    } catch (const std::exception& e) {
      PassageResult& r = out.passages[i];
      r = PassageResult{};
      r.name = p.name;
      r.train = p.train < trains.size() ? trains[p.train].name : "";
      r.failure = e.what();
      r.input_error = dynamic_cast<const InputError*>(&e) != nullptr;
    }
    tick();
  });
  return out;
}

}  // namespace viaduct::study
