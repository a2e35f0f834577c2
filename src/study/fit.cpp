// Model updating by bounded nonlinear least squares (Ceres, Levenberg–Marquardt).
#include "viaduct/study/fit.hpp"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>

#include "series.hpp"
#include "viaduct/core/eigensolvers.hpp"

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

std::string num(double v, int digits = 6) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

bool bad_weight(double w) { return !(w >= 0.0) || !std::isfinite(w); }

// Catmull–Rom (C¹) interpolation of x sampled at fs from t = 0; 0 outside [0, T].
double sample_c1(const Vector& x, double fs, double t) {
  const double s = t * fs;
  const auto n = x.size();
  if (!(s >= 0.0) || s > static_cast<double>(n - 1)) return 0.0;
  auto i = static_cast<Index>(std::floor(s));
  if (i >= n - 1) return x[n - 1];
  const double u = s - static_cast<double>(i);
  const double p0 = x[i > 0 ? i - 1 : 0], p1 = x[i], p2 = x[i + 1], p3 = x[i + 2 < n ? i + 2 : n - 1];
  return p1 + 0.5 * u * (p2 - p0 + u * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + u * (3.0 * (p1 - p2) + p3 - p0)));
}

double halton(int k, int base) {
  double f = 1.0, r = 0.0;
  while (k > 0) {
    f /= base;
    r += f * (k % base);
    k /= base;
  }
  return r;
}

std::vector<double> initial_values(const FitProblem& p) {
  std::vector<double> v;
  for (const auto& q : p.params) v.push_back(q.initial);
  return v;
}

// Residual block: one objective on one channel (or one mode).
struct Block {
  std::string objective, record, channel;
  Index offset = 0, size = 0;
  double kappa = 1.0;  // variance inflation for serially correlated residuals (filtered time histories)
};

// One channel prepared for the objectives.
struct PreparedChannel {
  std::size_t station = 0;
  bool acceleration = true;
  bool velocity = false;  // a velocity channel (acceleration-like: band-filtered)
  std::string effect;  // a load effect's history (strain) instead of the station's motion
  double scale = 1.0;
  Vector y;          // filtered (accelerations) record
  double y_norm = 0, y_peak = 0, y_rms = 0;
  Vector env_y;      // windowed RMS envelope
  double env_norm = 0;
  std::vector<Index> lines;  // spectrum lines used
  Vector spec_y;
  double spec_norm = 0;
};

struct PreparedRecord {
  const FitRecord* in = nullptr;
  std::size_t train_index = 0;
  std::vector<PreparedChannel> channels;
  signal::Sos band;        // the record's band filter at its rate (filter enabled)
  signal::Sos anti_alias;  // low-pass of the model before it is sampled at the record's rate (empty: not needed)
  double free_vibration_s = 0.0;  // [s] simulated after the train (0: as long as the record, until known)
};

// What one simulation at trial values gives.
struct Simulated {
  double fs_model = 0.0;
  std::vector<std::vector<Vector>> signal;  // [record][channel], channel unit, filtered accelerations (alignment)
  std::vector<std::vector<Vector>> raw;     // the same before the band filter (anti-aliased for the record's rate)
  Vector modal_f;                           // [Hz] model modes in the pairing range
  Matrix modal_shapes;                      // sensors × modes
  Vector modal_zeta;                        // φᵀCφ / (2ω) of each mode
};

class Evaluator {
 public:
  Evaluator(const FitProblem& p, const FitOptions& o) : p_(p), o_(o) {
    n_params_ = p.params.size();
    const Scenario sc0 = p.scenario_at(initial_values(p_));
    filter_ = sc0.settings.filter;
    const bool records = o.weights.any_record_term();
    if (records) {
      prepare_records(sc0);
      // How long the model must ring: until the record ends, from the alignment at the start
      // (a first run as long as the record), with 1 s to spare for shifts during the fit.
      const Simulated s0 = simulate_at(initial_values(p_));
      const std::vector<double> shifts = align(s0);
      zero_records(s0, shifts);
      unit_checks(s0, shifts);
      for (std::size_t r = 0; r < records_.size(); ++r) {
        auto& pr = records_[r];
        const double duration = static_cast<double>(pr.channels.front().y.size()) / pr.in->fs_hz;
        const double t_model = static_cast<double>(s0.signal[r].front().size() - 1) / s0.fs_model;
        const double passage = t_model - std::max(sc0.settings.free_vibration_s, duration);
        pr.free_vibration_s = std::max(0.0, pr.in->t0_s + duration - shifts[r] - passage) + 1.0;
      }
    }
    if (o.weights.modal > 0 || o.weights.damping > 0) prepare_modal(sc0);
    layout_blocks();
  }

  std::size_t n_params() const { return n_params_; }
  std::size_t n_z() const { return n_params_; }
  Index n_residuals() const { return n_res_; }
  const std::vector<Block>& blocks() const { return blocks_; }
  std::size_t n_records() const { return records_.size(); }
  int simulations() const { return simulations_.load(); }
  const std::vector<std::string>& record_warnings() const { return record_warnings_; }

  std::vector<double> values_of(const double* z) const {
    std::vector<double> v(n_params_);
    for (std::size_t i = 0; i < n_params_; ++i) v[i] = from_unit(p_.params[i], std::clamp(z[i], 0.0, 1.0));
    return v;
  }
  // Alignment of each record: the shift (record time of the model's t = 0) that maximises the
  // summed, normalised cross-correlation of the mapped channels (parabolic sub-sample peak), so
  // the misfits are taken after the best alignment at every trial point.
  std::vector<double> align(const Simulated& s) const {
    std::vector<double> shifts(records_.size());
    for (std::size_t r = 0; r < records_.size(); ++r) {
      const auto& pr = records_[r];
      const double fs = pr.in->fs_hz;
      const Index n_y = pr.channels.front().y.size();
      const auto n_m = static_cast<Index>(std::floor(static_cast<double>(s.signal[r].front().size() - 1) / s.fs_model * fs)) + 1;
      const auto max_lag = static_cast<Index>(std::ceil(o_.max_shift_s * fs));
      const Index block = std::max(n_y, n_m) + max_lag;
      const auto n_c = static_cast<Index>(pr.channels.size());
      Vector x = Vector::Zero(block * n_c), y = Vector::Zero(block * n_c);
      for (Index c = 0; c < n_c; ++c) {
        const auto& ch = pr.channels[static_cast<std::size_t>(c)];
        const Vector& m = s.signal[r][static_cast<std::size_t>(c)];
        Vector mr(n_m);
        for (Index k = 0; k < n_m; ++k) mr[k] = sample_c1(m, s.fs_model, static_cast<double>(k) / fs);
        const double nm = mr.norm();
        if (nm > 0) x.segment(c * block, n_m) = mr / nm;
        y.segment(c * block, n_y) = ch.y / ch.y_norm;
      }
      shifts[r] = pr.in->t0_s + signal::best_lag(x, y, max_lag) / fs;
    }
    return shifts;
  }

  // Runs the model at `values`. Throws on failure.
  Simulated simulate_at(const std::vector<double>& values) const {
    ++simulations_;
    const Scenario sc = p_.scenario_at(values);
    Simulated out;
    out.fs_model = 1.0 / sc.settings.dt;
    const PreparedModel pm = prepare_model(sc, /*rail_outputs=*/false, with_effects_);
    if (!records_.empty()) {
      RunSettings rs = sc.settings;
      rs.filter.enabled = false;
      const bool filt = filter_.enabled;
      signal::Sos sos;
      if (filt) sos = signal::cheby1(filter_.cheby, out.fs_model);
      out.signal.resize(records_.size());
      out.raw.resize(records_.size());
      for (std::size_t r = 0; r < records_.size(); ++r) {
        const auto& pr = records_[r];
        if (pr.train_index >= sc.trains.size()) throw InputError("fit: the scenario lost its train");
        double speed = pr.in->speed > 0 ? pr.in->speed : sc.run_speed.value_or(0.0);
        if (!(speed > 0)) throw InputError("fit: record " + pr.in->name + " has no speed and the scenario no run.speed_kmh");
        // The model rings on as long as the record lasts (a model cut short would differ from the
        // record at its end, after filtering too).
        RunSettings rs_r = rs;
        const double duration = static_cast<double>(pr.channels.front().y.size()) / pr.in->fs_hz;
        rs_r.free_vibration_s = std::max(rs.free_vibration_s, pr.free_vibration_s > 0 ? pr.free_vibration_s : duration);
        const RunResult run = simulate(pm, sc.trains[pr.train_index], speed, rs_r);
        // The structure is at rest before t = 0: zeros ahead of the history for the filter.
        const auto lead = static_cast<Index>(std::ceil(0.5 * out.fs_model));
        for (const auto& ch : pr.channels) {
          const auto& h = run.stations[ch.station];
          Vector s = (ch.velocity ? station_response(run, ch.station, ResponseKind::velocity) : ch.acceleration ? h.acc : h.disp) * ch.scale;
          if (!ch.effect.empty()) {
            const auto e = std::find_if(run.effects.begin(), run.effects.end(), [&](const EffectHistory& x) { return x.name == ch.effect; });
            if (e == run.effects.end()) throw InputError("fit: the model has no " + ch.effect + " (stations[].fibre_m?)");
            s = e->value;
          }
          if (!s.allFinite()) throw SolverError("fit: the model's response is not finite at these values");
          Vector padded = Vector::Zero(lead + s.size());
          padded.tail(s.size()) = s;
          out.raw[r].push_back(pr.anti_alias.sections.empty() ? s : Vector(signal::sosfiltfilt(pr.anti_alias, padded).tail(s.size())));
          if (ch.acceleration && filt) s = signal::sosfiltfilt(sos, padded).tail(s.size());
          out.signal[r].push_back(std::move(s));
        }
      }
    }
    if (modal_) model_modes(pm.structure, sc, out);
    return out;
  }

  // Residuals of a simulation (records aligned first).
  void residuals(const Simulated& s, double* r) const {
    const FitWeights& w = o_.weights;
    const std::vector<double> shifts = align(s);
    std::size_t b = 0;
    for (std::size_t ri = 0; ri < records_.size(); ++ri) {
      const auto& pr = records_[ri];
      for (std::size_t c = 0; c < pr.channels.size(); ++c) {
        const auto& ch = pr.channels[c];
        const Vector m = processed(s, ri, c, shifts[ri]);
        if (w.time > 0) {
          const Block& bl = blocks_[b++];
          const double k = std::sqrt(w.time) / ch.y_norm;
          for (Index i = 0; i < bl.size; ++i) r[bl.offset + i] = k * (m[i] - ch.y[i]);
        }
        if (w.peak > 0) {
          const Block& bl = blocks_[b++];
          const double k = std::sqrt(w.peak);
          const double rms = std::sqrt(m.squaredNorm() / static_cast<double>(m.size()));
          r[bl.offset] = k * (m.cwiseAbs().maxCoeff() / ch.y_peak - 1.0);
          r[bl.offset + 1] = k * (rms / ch.y_rms - 1.0);
        }
        if (w.envelope > 0) {
          const Block& bl = blocks_[b++];
          const Vector e = envelope(m, pr.in->fs_hz);
          const double k = std::sqrt(w.envelope) / ch.env_norm;
          for (Index i = 0; i < bl.size; ++i) r[bl.offset + i] = k * (e[i] - ch.env_y[i]);
        }
        if (w.spectrum > 0) {
          const Block& bl = blocks_[b++];
          const auto a = signal::amplitude_spectrum(m, pr.in->fs_hz, signal::Window::hann);
          const double k = std::sqrt(w.spectrum) / ch.spec_norm;
          for (Index i = 0; i < bl.size; ++i) r[bl.offset + i] = k * (a.amplitude[ch.lines[static_cast<std::size_t>(i)]] - ch.spec_y[i]);
        }
      }
    }
    if (modal_ && w.modal > 0) {
      const double k = std::sqrt(w.modal);
      for (std::size_t mi = 0; mi < modal_->modes.size(); ++mi) {
        const Block& bl = blocks_[b++];
        const auto& tm = modal_->modes[mi];
        const Index j = pair_mode(s, tm);
        r[bl.offset] = k * (s.modal_f[j] / tm.frequency_hz - 1.0);
        if (tm.shape.size() > 0) {
          const Vector phi_t = tm.shape / tm.shape.norm();
          const Vector phi_m = s.modal_shapes.col(j);
          const double mm = phi_m.squaredNorm();
          const double alpha = mm > 0 ? phi_m.dot(phi_t) / mm : 0.0;
          for (Index i = 0; i < phi_t.size(); ++i) r[bl.offset + 1 + i] = k * (alpha * phi_m[i] - phi_t[i]);
        }
      }
    }
    if (modal_ && w.damping > 0) {
      const double k = std::sqrt(w.damping);
      for (const auto& tm : modal_->modes) {
        if (!std::isfinite(tm.damping_ratio)) continue;
        const Block& bl = blocks_[b++];
        r[bl.offset] = k * (s.modal_zeta[pair_mode(s, tm)] / tm.damping_ratio - 1.0);
      }
    }
  }

  // Pairing of an identified mode with a model mode: best MAC within a factor 1.5 in frequency
  // (nearest frequency without a shape, or when nothing is in range).
  Index pair_mode(const Simulated& s, const ModalTarget::Mode& tm) const {
    Index best = -1;
    double best_score = -kInf;
    for (Index j = 0; j < s.modal_f.size(); ++j) {
      const double ratio = s.modal_f[j] / tm.frequency_hz;
      if (tm.shape.size() > 0 && ratio > 1 / 1.5 && ratio < 1.5) {
        const double score = mac_real(tm.shape, s.modal_shapes.col(j)) - 1e-3 * std::abs(std::log(ratio));
        if (score > best_score) best_score = score, best = j;
      }
    }
    if (best >= 0 && best_score > 0.1) return best;
    double best_d = kInf;
    for (Index j = 0; j < s.modal_f.size(); ++j) {
      const double d = std::abs(std::log(s.modal_f[j] / tm.frequency_hz));
      if (d < best_d) best_d = d, best = j;
    }
    return best;
  }

  static double mac_real(const Vector& a, const Vector& b) {
    const double den = a.squaredNorm() * b.squaredNorm();
    return den > 0 ? std::pow(a.dot(b), 2) / den : 0.0;
  }

  // The model as the record was processed: aligned, sampled on the record's grid (anti-aliased),
  // then the same zero-phase filter over the same window, so that both share the edge effects.
  Vector processed(const Simulated& s, std::size_t r, std::size_t c, double shift) const {
    const auto& pr = records_[r];
    Vector m = aligned(s.raw[r][c], s.fs_model, pr, shift);
    if (pr.channels[c].acceleration && filter_.enabled) m = signal::sosfiltfilt(pr.band, m);
    return m;
  }

  Vector aligned(const Vector& model, double fs_model, const PreparedRecord& pr, double shift) const {
    const Index n = pr.channels.front().y.size();
    Vector m(n);
    const double fs = pr.in->fs_hz;
    for (Index i = 0; i < n; ++i) m[i] = sample_c1(model, fs_model, pr.in->t0_s + static_cast<double>(i) / fs - shift);
    return m;
  }

  Vector envelope(const Vector& x, double fs) const {
    const Index lw = std::max<Index>(2, static_cast<Index>(std::lround(o_.envelope_window_s * fs)));
    const Index nw = x.size() / lw;
    Vector e(nw);
    for (Index k = 0; k < nw; ++k) e[k] = std::sqrt(x.segment(k * lw, lw).squaredNorm() / static_cast<double>(lw));
    return e;
  }

  const ModalTarget* modal() const { return modal_; }
  const PreparedRecord& record(std::size_t r) const { return records_[r]; }
  const FilterSpec& filter() const { return filter_; }

 private:
  // What the misfits use of a channel's processed record: norms, peak, envelope, spectrum lines.
  void derive(PreparedChannel& pc, const FitRecord& rec, const FitChannel& ch) const {
    const Index n = pc.y.size();
    pc.lines.clear();  // derived again after a zero is removed
    pc.y_norm = pc.y.norm();
    pc.y_peak = pc.y.cwiseAbs().maxCoeff();
    pc.y_rms = std::sqrt(pc.y.squaredNorm() / static_cast<double>(n));
    if (!(pc.y_norm > 0)) throw InputError("fit: record " + rec.name + " channel " + ch.name + " is zero after filtering");
    pc.env_y = envelope(pc.y, rec.fs_hz);
    pc.env_norm = pc.env_y.norm();
    if (o_.weights.envelope > 0 && pc.env_y.size() < 4)
      throw InputError("fit: record " + rec.name + " is shorter than 4 envelope windows (envelope_window_s)");
    const auto a = signal::amplitude_spectrum(pc.y, rec.fs_hz, signal::Window::hann);
    double f_lo = 0.0, f_hi = rec.fs_hz / 2;
    if (filter_.enabled && ch.acceleration) {
      if (filter_.cheby.band != signal::BandType::lowpass) f_lo = filter_.cheby.low_hz;
      if (filter_.cheby.band != signal::BandType::highpass) f_hi = filter_.cheby.high_hz;
    }
    for (Index k = 0; k < a.frequency_hz.size(); ++k)
      if (a.frequency_hz[k] > 0 && a.frequency_hz[k] >= f_lo && a.frequency_hz[k] <= f_hi) pc.lines.push_back(k);
    pc.spec_y.resize(static_cast<Index>(pc.lines.size()));
    for (std::size_t k = 0; k < pc.lines.size(); ++k) pc.spec_y[static_cast<Index>(k)] = a.amplitude[pc.lines[k]];
    pc.spec_norm = pc.spec_y.norm();
    if (o_.weights.spectrum > 0 && (pc.lines.size() < 4 || !(pc.spec_norm > 0)))
      throw InputError("fit: record " + rec.name + " channel " + ch.name + ": fewer than 4 spectral lines in the band");
  }

  // A deflection or strain channel's zero (issue #39): the record before the train's entry (the
  // aligned model's response above 1 % of its peak) is its level; removed when asked (and the
  // channel's misfit data derived again), else a warning when it is an offset.
  void zero_records(const Simulated& s0, const std::vector<double>& shifts) {
    for (std::size_t r = 0; r < records_.size(); ++r) {
      auto& pr = records_[r];
      for (std::size_t c = 0; c < pr.channels.size(); ++c) {
        PreparedChannel& pc = pr.channels[c];
        const FitChannel& ch = pr.in->channels[c];
        if (pc.acceleration) continue;
        const double entry = shifts[r] + response_onset_s(s0.raw[r][c], s0.fs_model);
        const ZeroOutcome z = apply_zero(o_.zero, pc.y, pr.in->fs_hz, pr.in->t0_s, entry, ch.name, ch.strain ? "ue" : "m",
                                         "fit: record " + pr.in->name);
        if (z.removed != 0.0) derive(pc, *pr.in, ch);
        if (!z.warning.empty()) record_warnings_.push_back("record " + pr.in->name + ", " + z.warning);
      }
    }
  }

  // Each channel against the model at the initial values: a unit's factor apart with the same
  // shape (a record in g read as m/s²) is a unit slip the fit would otherwise absorb into its
  // parameters (unit_slip_warning). Initial values are off by tens of percent (the Old Guadiana
  // calibration record: peak ratios 1.24 and 1.03, RMS ratios 1.45 and 1.34): within 50 % of the
  // factor here.
  void unit_checks(const Simulated& s0, const std::vector<double>& shifts) {
    for (std::size_t r = 0; r < records_.size(); ++r)
      for (std::size_t c = 0; c < records_[r].channels.size(); ++c) {
        const PreparedChannel& pc = records_[r].channels[c];
        const Vector m = processed(s0, r, c, shifts[r]);
        const auto n = static_cast<double>(m.size());
        const double corr = detail::pearson(m, pc.y);
        const double peak = pc.y_peak > 0 ? m.cwiseAbs().maxCoeff() / pc.y_peak : 0.0;
        const double rms = pc.y_rms > 0 ? std::sqrt(m.squaredNorm() / n) / pc.y_rms : 0.0;
        const std::string w = unit_slip_warning(peak, rms, corr, records_[r].in->channels[c].name, 1.5);
        if (!w.empty()) record_warnings_.push_back("record " + records_[r].in->name + ", at the initial values: " + w);
      }
  }

  void prepare_records(const Scenario& sc0) {
    if (p_.records.empty()) throw InputError("fit: the record objectives (time, peak, envelope, spectrum) need at least one record");
    std::map<std::string, std::size_t> station_index;
    for (std::size_t i = 0; i < sc0.stations.size(); ++i) station_index[sc0.stations[i].name] = i;
    const double fs_model = 1.0 / sc0.settings.dt;
    if (filter_.enabled) {
      std::string why;
      if (!filter_.cheby.is_valid(fs_model, &why)) throw InputError("fit: filter at the model's rate: " + why);
    }
    for (const auto& rec : p_.records) {
      PreparedRecord pr;
      pr.in = &rec;
      require_positive(rec.fs_hz, "fit: record " + rec.name + " sampling rate [Hz]");
      require_finite(rec.t0_s, "fit: record " + rec.name + " start time [s]");
      if (rec.channels.empty()) throw InputError("fit: record " + rec.name + " maps no channel");
      if (!(rec.speed >= 0) || !std::isfinite(rec.speed)) throw InputError("fit: record " + rec.name + " speed must be >= 0");
      if (rec.speed == 0 && !sc0.run_speed)
        throw InputError("fit: record " + rec.name + " has no speed: give one or set run.speed_kmh");
      pr.train_index = sc0.trains.size();
      for (std::size_t t = 0; t < sc0.trains.size(); ++t)
        if (rec.train.empty() || sc0.trains[t].name == rec.train) {
          pr.train_index = t;
          break;
        }
      if (pr.train_index == sc0.trains.size()) throw InputError("fit: record " + rec.name + ": no train named '" + rec.train + "' in the scenario");
      signal::Sos sos;
      if (filter_.enabled) {
        std::string why;
        if (!filter_.cheby.is_valid(rec.fs_hz, &why)) throw InputError("fit: filter at the rate of record " + rec.name + ": " + why);
        sos = signal::cheby1(filter_.cheby, rec.fs_hz);
        pr.band = sos;
      }
      if (fs_model > 1.0001 * rec.fs_hz) {
        signal::Cheby1Spec aa;
        // Flat in the band: 1e-4 dB of ripple (twice that zero-phase) is 0.002 % in amplitude;
        // a 0.1 dB ripple here biased a pad stiffness by 29 % (measured on og-calibration.csv).
        aa.order = 8;
        aa.ripple_db = 1e-4;
        aa.band = signal::BandType::lowpass;
        aa.high_hz = 0.4 * rec.fs_hz;
        std::string why;
        if (!aa.is_valid(fs_model, &why)) throw InputError("fit: anti-alias filter for record " + rec.name + ": " + why);
        pr.anti_alias = signal::cheby1(aa, fs_model);
      }
      const Index n = rec.channels.front().samples.size();
      for (const auto& ch : rec.channels) {
        PreparedChannel pc;
        auto it = station_index.find(ch.station);
        if (it == station_index.end()) throw InputError("fit: record " + rec.name + " channel " + ch.name + ": no station '" + ch.station + "' in the scenario");
        pc.station = it->second;
        pc.acceleration = ch.acceleration && !ch.strain;
        pc.velocity = ch.velocity && pc.acceleration;
        if (ch.strain) {
          if (sc0.stations[pc.station].fibre_m == 0.0)
            throw InputError("fit: record " + rec.name + " channel " + ch.name + " is a strain; station '" + ch.station +
                             "' has no stations[].fibre_m (the gauge's distance below the neutral axis)");
          pc.effect = ch.station + "_strain_ue";
          with_effects_ = true;
        }
        pc.scale = ch.scale;
        if (ch.samples.size() != n) throw InputError("fit: record " + rec.name + ": channels of different lengths");
        if (n < 64) throw InputError("fit: record " + rec.name + " has fewer than 64 samples");
        if (!ch.samples.allFinite()) throw InputError("fit: record " + rec.name + " channel " + ch.name + " has non-finite samples");
        pc.y = ch.acceleration && filter_.enabled ? signal::sosfiltfilt(sos, ch.samples) : ch.samples;
        derive(pc, rec, ch);
        pr.channels.push_back(std::move(pc));
      }
      records_.push_back(std::move(pr));
    }
  }

  void prepare_modal(const Scenario& sc0) {
    if (!p_.modal || p_.modal->modes.empty()) throw InputError("fit: the modal and damping objectives need identified modes");
    modal_ = &*p_.modal;
    std::map<std::string, std::size_t> station_index;
    for (std::size_t i = 0; i < sc0.stations.size(); ++i) station_index[sc0.stations[i].name] = i;
    for (const auto& s : modal_->sensors) {
      auto it = station_index.find(s);
      if (it == station_index.end()) throw InputError("fit: modal sensor '" + s + "' is not a station of the scenario");
      sensor_stations_.push_back(it->second);
    }
    for (const auto& m : modal_->modes) {
      if (!(m.frequency_hz > 0) || !std::isfinite(m.frequency_hz)) throw InputError("fit: identified frequencies must be > 0");
      if (m.shape.size() > 0 && static_cast<std::size_t>(m.shape.size()) != modal_->sensors.size())
        throw InputError("fit: an identified shape has " + std::to_string(m.shape.size()) + " entries for " +
                         std::to_string(modal_->sensors.size()) + " sensors");
      if (m.shape.size() > 0 && !(m.shape.norm() > 0)) throw InputError("fit: an identified shape is zero");
      if (!std::isnan(m.damping_ratio) && !(m.damping_ratio > 0 && m.damping_ratio < 1))
        throw InputError("fit: identified damping ratios must be in (0, 1), got " + num(m.damping_ratio));
      f_max_target_ = std::max(f_max_target_, m.frequency_hz);
    }
  }

  void model_modes(const model::Structure& s, const Scenario& sc, Simulated& out) const {
    // The modes up to 2.25 × the highest identified frequency, and at least the lowest
    // n_identified + 4 modes (the start may be far off).
    // A few modes of a large model: shift-invert Lanczos (sparse), not all of them (dense).
    const auto solver = s.n_dofs > 200 ? model::ModeSolver::sparse : model::ModeSolver::dense;
    model::Modes md = model::compute_modes_up_to(s, 0, 2.25 * f_max_target_, solver);
    const auto n_min = static_cast<Index>(modal_->modes.size()) + 4;
    if (md.frequency_hz.size() < n_min) md = model::compute_modes_up_to(s, n_min, 0.0, solver);
    std::vector<StationSpec> specs;
    for (std::size_t i : sensor_stations_) specs.push_back(sc.stations[i]);
    const auto st = specs.empty() ? std::vector<ResolvedStation>{} : resolve_stations(s, specs);
    out.modal_f = md.frequency_hz;
    out.modal_zeta.resize(md.frequency_hz.size());
    for (Index j = 0; j < md.frequency_hz.size(); ++j) {
      const Vector phi = md.shape.col(j);
      const double omega = 2.0 * kPi * md.frequency_hz[j];
      out.modal_zeta[j] = omega > 0 ? phi.dot(s.C * phi) / (2.0 * omega) : 0.0;
    }
    out.modal_shapes.resize(static_cast<Index>(st.size()), md.frequency_hz.size());
    for (Index j = 0; j < md.frequency_hz.size(); ++j)
      for (std::size_t r = 0; r < st.size(); ++r)
        out.modal_shapes(static_cast<Index>(r), j) = (st[r].has_deck ? st[r].deck : st[r].rail).value(md.shape.col(j));
    if (out.modal_f.size() == 0) throw SolverError("fit: the model has no modes");
  }

  void layout_blocks() {
    const FitWeights& w = o_.weights;
    Index off = 0;
    auto add = [&](const std::string& obj, const std::string& rec, const std::string& ch, Index size, double kappa) {
      blocks_.push_back({obj, rec, ch, off, size, kappa});
      off += size;
    };
    for (const auto& pr : records_) {
      for (std::size_t c = 0; c < pr.channels.size(); ++c) {
        const auto& ch = pr.channels[c];
        const std::string& name = pr.in->channels[c].name;
        // Filtered samples are correlated over about fs / (2 B) samples.
        double band = pr.in->fs_hz / 2;
        if (filter_.enabled) {
          const auto& f = filter_.cheby;
          if (f.band == signal::BandType::bandpass && ch.acceleration) band = f.high_hz - f.low_hz;
          else if (f.band != signal::BandType::highpass) band = f.high_hz;
        }
        const double kappa = std::max(1.0, pr.in->fs_hz / (2.0 * band));
        if (w.time > 0) add("time", pr.in->name, name, ch.y.size(), kappa);
        if (w.peak > 0) add("peak", pr.in->name, name, 2, 1.0);
        if (w.envelope > 0) add("envelope", pr.in->name, name, ch.env_y.size(), 1.0);
        if (w.spectrum > 0) add("spectrum", pr.in->name, name, static_cast<Index>(ch.lines.size()), 1.0);
      }
    }
    if (modal_ && w.modal > 0)
      for (std::size_t k = 0; k < modal_->modes.size(); ++k)
        add("modal", "", "mode " + std::to_string(k + 1) + " (" + num(modal_->modes[k].frequency_hz) + " Hz)",
            1 + modal_->modes[k].shape.size(), 1.0);
    if (modal_ && w.damping > 0) {
      for (std::size_t k = 0; k < modal_->modes.size(); ++k)
        if (std::isfinite(modal_->modes[k].damping_ratio))
          add("damping", "", "mode " + std::to_string(k + 1) + " (" + num(modal_->modes[k].frequency_hz) + " Hz)", 1, 1.0);
      if (blocks_.empty() || blocks_.back().objective != "damping")
        throw InputError("fit: the damping objective needs identified damping ratios (none of the identified modes has one)");
    }
    n_res_ = off;
    if (n_res_ == 0) throw InputError("fit: no residuals: every objective weight is 0");
  }

  const FitProblem& p_;
  const FitOptions& o_;
  std::size_t n_params_ = 0;
  FilterSpec filter_;
  std::vector<PreparedRecord> records_;
  std::vector<std::string> record_warnings_;  // offsets before the train's entry (zero kept)
  bool with_effects_ = false;  // a strain channel: the runs record load effects
  const ModalTarget* modal_ = nullptr;
  std::vector<std::size_t> sensor_stations_;
  double f_max_target_ = 0.0;
  std::vector<Block> blocks_;
  Index n_res_ = 0;
  mutable std::atomic<int> simulations_{0};
};

// The residuals and their forward-difference Jacobian for Ceres. The last evaluation is cached:
// Ceres evaluates the cost at a trial point and, once accepted, asks for the Jacobian there.
class Cost : public ceres::CostFunction {
 public:
  Cost(const Evaluator& ev, const FitOptions& o) : ev_(ev), o_(o) {
    set_num_residuals(static_cast<int>(ev.n_residuals()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(ev.n_z()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* z = parameters[0];
    const std::size_t nz = ev_.n_z();
    ++evaluations_;
    try {
      const std::vector<double> zv(z, z + nz);
      const Index m = ev_.n_residuals();
      if (!cache_ || cache_->first != zv)
        cache_ = std::make_unique<std::pair<std::vector<double>, Simulated>>(zv, ev_.simulate_at(ev_.values_of(z)));
      const Simulated& base = cache_->second;
      Vector r0(m);
      ev_.residuals(base, r0.data());
      std::copy(r0.data(), r0.data() + m, residuals);
      if (!jacobians || !jacobians[0]) return true;
      Matrix J(m, static_cast<Index>(nz));
      std::vector<std::string> errors(nz);
      parallel_for(nz, std::max(1, o_.threads), [&](std::size_t j, int) {
        try {
          std::vector<double> zp = zv;
          double h = o_.fd_step;
          if (zp[j] + h > 1.0) h = -h;
          zp[j] += h;
          Vector r(m);
          ev_.residuals(ev_.simulate_at(ev_.values_of(zp.data())), r.data());
          J.col(static_cast<Index>(j)) = (r - r0) / h;
        } catch (const std::exception& e) {
          errors[j] = e.what();
        }
      });
      for (const auto& e : errors)
        if (!e.empty()) throw SolverError(e);
      for (Index i = 0; i < m; ++i)
        for (std::size_t j = 0; j < nz; ++j) jacobians[0][static_cast<std::size_t>(i) * nz + j] = J(i, static_cast<Index>(j));
      return true;
    } catch (const std::exception& e) {
      last_error_ = e.what();
      return false;
    }
  }

  int evaluations() const { return evaluations_; }
  const std::string& last_error() const { return last_error_; }

 private:
  const Evaluator& ev_;
  const FitOptions& o_;
  mutable std::unique_ptr<std::pair<std::vector<double>, Simulated>> cache_;
  mutable int evaluations_ = 0;
  mutable std::string last_error_;
};

class Trace : public ceres::IterationCallback {
 public:
  Trace(const Evaluator& ev, const double* z, int start, int stage, FitResult& out, const FitOptions& o)
      : ev_(ev), z_(z), start_(start), stage_(stage), out_(out), o_(o) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    FitTracePoint tp;
    tp.start = start_;
    tp.stage = stage_;
    tp.iteration = s.iteration;
    tp.cost = s.cost;
    tp.values = ev_.values_of(z_);
    out_.trace.push_back(tp);
    if (o_.progress) o_.progress(tp);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const Evaluator& ev_;
  const double* z_;
  int start_;
  int stage_;
  FitResult& out_;
  const FitOptions& o_;
};

struct StartOutcome {
  std::vector<double> z;
  double cost = kInf;
  FitResult::Status status = FitResult::Status::failed;
  std::string message;
  int iterations = 0;
};

StartOutcome run_start(const Evaluator& ev, const FitOptions& o, std::vector<double> z0, int start, int stage,
                       FitResult& out) {
  StartOutcome so;
  so.z = std::move(z0);
  auto* cost = new Cost(ev, o);  // owned by the problem
  ceres::Problem::Options po;
  ceres::Problem problem(po);
  problem.AddResidualBlock(cost, nullptr, so.z.data());
  for (std::size_t j = 0; j < so.z.size(); ++j) {
    problem.SetParameterLowerBound(so.z.data(), static_cast<int>(j), 0.0);
    problem.SetParameterUpperBound(so.z.data(), static_cast<int>(j), 1.0);
  }
  ceres::Solver::Options so_opts;
  so_opts.minimizer_type = ceres::TRUST_REGION;
  so_opts.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so_opts.linear_solver_type = ceres::DENSE_QR;
  so_opts.max_num_iterations = o.max_iterations;
  so_opts.max_solver_time_in_seconds = o.max_time_s;
  so_opts.function_tolerance = o.function_tolerance;
  so_opts.parameter_tolerance = o.parameter_tolerance;
  so_opts.gradient_tolerance = o.gradient_tolerance;
  so_opts.num_threads = 1;
  so_opts.logging_type = ceres::SILENT;
  so_opts.minimizer_progress_to_stdout = false;
  so_opts.update_state_every_iteration = true;
  Trace trace(ev, so.z.data(), start, stage, out, o);
  so_opts.callbacks.push_back(&trace);
  std::string why;
  if (!so_opts.IsValid(&why)) throw InputError("fit: solver options: " + why);
  ceres::Solver::Summary summary;
  ceres::Solve(so_opts, &problem, &summary);
  out.evaluations += cost->evaluations();
  so.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  so.cost = summary.final_cost;
  so.message = summary.message;
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
      so.status = FitResult::Status::converged;
      break;
    case ceres::NO_CONVERGENCE:
      so.status = FitResult::Status::no_convergence;
      so.message = "did not converge: " + summary.message;
      break;
    default:
      so.status = FitResult::Status::failed;
      so.message = summary.message + (cost->last_error().empty() ? "" : " (last model error: " + cost->last_error() + ")");
      so.cost = summary.IsSolutionUsable() ? summary.final_cost : kInf;
  }
  return so;
}

// Jacobian in z by forward differences at z (parallel columns) and the residuals there.
void jacobian_at(const Evaluator& ev, const FitOptions& o, const std::vector<double>& z, Vector& r, Matrix& J) {
  Cost c(ev, o);
  const Index m = ev.n_residuals();
  const auto nz = static_cast<Index>(ev.n_z());
  r.resize(m);
  std::vector<double> jr(static_cast<std::size_t>(m * nz));
  const double* pz = z.data();
  double* pj = jr.data();
  if (!c.Evaluate(&pz, r.data(), &pj)) throw SolverError("fit: the model failed at the estimate: " + c.last_error());
  J.resize(m, nz);
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < nz; ++j) J(i, j) = jr[static_cast<std::size_t>(i * nz + j)];
}

}  // namespace

bool FitWeights::is_valid(std::string* why) const {
  OptionsCheck c("FitWeights", why);
  for (auto [name, w] : {std::pair<const char*, double>{"time", time}, {"peak", peak}, {"envelope", envelope},
                         {"spectrum", spectrum}, {"modal", modal}, {"damping", damping}})
    if (!c.require(!bad_weight(w), name, w, std::string(name) + " >= 0 and finite")) return false;
  return time + peak + envelope + spectrum + modal + damping > 0 ||
         c.fail("time", format_number(time, 6), "at least one objective weight > 0");
}

bool FitOptions::is_valid(std::string* why) const {
  OptionsCheck c("FitOptions", why);
  return weights.is_valid(why) &&
         c.require(envelope_window_s > 0, "envelope_window_s", envelope_window_s, "envelope_window_s > 0 [s]") &&
         c.require(max_shift_s > 0, "max_shift_s", max_shift_s, "max_shift_s > 0 [s]") &&
         c.require(starts >= 1, "starts", starts, "starts >= 1") &&
         c.require(max_iterations >= 1, "max_iterations", max_iterations, "max_iterations >= 1") &&
         c.require(max_time_s > 0, "max_time_s", max_time_s, "max_time_s > 0 [s]") &&
         c.require(function_tolerance > 0, "function_tolerance", function_tolerance, "function_tolerance > 0") &&
         c.require(parameter_tolerance > 0, "parameter_tolerance", parameter_tolerance, "parameter_tolerance > 0") &&
         c.require(gradient_tolerance > 0, "gradient_tolerance", gradient_tolerance, "gradient_tolerance > 0") &&
         c.require(fd_step > 0 && fd_step <= 0.1, "fd_step", fd_step, "fd_step in (0, 0.1]") &&
         c.require(threads >= 1, "threads", threads, "threads >= 1") &&
         c.require(max_relative_std > 0, "max_relative_std", max_relative_std, "max_relative_std > 0") &&
         c.require(max_correlation > 0 && max_correlation < 1, "max_correlation", max_correlation,
                   "max_correlation in (0, 1)");
}

const char* to_string(FitResult::Status s) {
  switch (s) {
    case FitResult::Status::converged: return "converged";
    case FitResult::Status::no_convergence: return "no_convergence";
    default: return "failed";
  }
}

double to_unit(const FitParameter& p, double value) {
  if (p.scale == ParameterScale::log) return std::log(value / p.lower) / std::log(p.upper / p.lower);
  return (value - p.lower) / (p.upper - p.lower);
}

double from_unit(const FitParameter& p, double z) {
  if (p.scale == ParameterScale::log) return p.lower * std::exp(z * std::log(p.upper / p.lower));
  return p.lower + z * (p.upper - p.lower);
}

namespace {

// Pseudo-inverse of A = JᵀJ without its flat directions; marks the parameters in a null
// direction (in_null) and those sharing one with others (in_flat, with a warning).
Matrix flat_directions(const Matrix& A, const Matrix& J, const FitProblem& problem, std::vector<bool>& in_null,
                       std::vector<bool>& in_flat, std::vector<std::string>& warnings) {
  const Index nzi = A.rows();
  Eigen::SelfAdjointEigenSolver<Matrix> es(A);
  const Vector lam = es.eigenvalues();
  const double lam_max = std::max(lam.maxCoeff(), 0.0);
  Matrix Ainv = Matrix::Zero(nzi, nzi);
  for (Index k = 0; k < nzi; ++k) {
    if (lam[k] > 1e-10 * lam_max && lam[k] > 0) {
      Ainv += es.eigenvectors().col(k) * es.eigenvectors().col(k).transpose() / lam[k];
    } else {
      for (Index i = 0; i < nzi; ++i)
        if (std::abs(es.eigenvectors()(i, k)) > 0.1) in_null[static_cast<std::size_t>(i)] = true;
    }
  }
  for (Index k = 0; k < nzi; ++k) {
    if (lam[k] > 1e-10 * lam_max && lam[k] > 0) continue;
    std::string keys;
    int n_in = 0;
    for (Index i = 0; i < nzi; ++i)
      if (std::abs(es.eigenvectors()(i, k)) > 0.1 && J.col(i).norm() > 1e-9 * std::max(1.0, std::sqrt(lam_max))) {
        keys += (keys.empty() ? "" : ", ") + problem.params[static_cast<std::size_t>(i)].key;
        ++n_in;
      }
    if (n_in > 1) {
      warnings.push_back(keys + " are not determined separately: the data fix only a combination of them (a flat direction of the misfit)");
      for (Index i = 0; i < nzi; ++i)
        if (std::abs(es.eigenvectors()(i, k)) > 0.1) in_flat[static_cast<std::size_t>(i)] = true;
    }
  }
  return Ainv;
}

// Correlations of the parameters with finite standard errors; strongly correlated pairs flagged.
void fit_correlations(const FitProblem& problem, const FitOptions& options, const Matrix& Cz, const std::vector<bool>& in_null,
                      FitResult& out) {
  const std::size_t np = problem.params.size();
  out.correlation = Matrix::Constant(static_cast<Index>(np), static_cast<Index>(np), kNaN);
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t j = 0; j < np; ++j) {
      const auto ii = static_cast<Index>(i), jj = static_cast<Index>(j);
      if (!std::isfinite(out.std_error[i]) || !std::isfinite(out.std_error[j]) || in_null[i] || in_null[j]) continue;
      const double d = std::sqrt(Cz(ii, ii) * Cz(jj, jj));
      out.correlation(ii, jj) = d > 0 ? Cz(ii, jj) / d : (i == j ? 1.0 : 0.0);
    }
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t j = i + 1; j < np; ++j) {
      const double rho = out.correlation(static_cast<Index>(i), static_cast<Index>(j));
      if (std::isfinite(rho) && std::abs(rho) > options.max_correlation) {
        out.determined[i] = out.determined[j] = false;
        out.warnings.push_back(problem.params[i].key + " and " + problem.params[j].key + " are strongly correlated (rho = " +
                               num(rho, 4) + "): the data fix a combination of them, not each");
      }
    }
}

// Time overlays (measured, initial, fitted) and modal pairs before and after the fit.
void fit_overlays(const Evaluator& ev, const FitProblem& problem, FitResult& out) {
  const Simulated s_init = ev.simulate_at(out.initial);
  const Simulated s_fit = ev.simulate_at(out.estimate);
  const std::vector<double> sh_init = ev.align(s_init), sh_fit = ev.align(s_fit);
  out.shift_s.assign(problem.records.size(), kNaN);
  for (std::size_t r = 0; r < ev.n_records(); ++r) {
    const auto& pr = ev.record(r);
    out.shift_s[r] = sh_fit[r];
    for (std::size_t c = 0; c < pr.channels.size(); ++c) {
      FitOverlay ov;
      ov.record = pr.in->name;
      ov.channel = pr.in->channels[c].name;
      const Index n = pr.channels[c].y.size();
      ov.t = Vector::LinSpaced(n, pr.in->t0_s, pr.in->t0_s + static_cast<double>(n - 1) / pr.in->fs_hz);
      ov.measured = pr.channels[c].y;
      ov.initial = ev.processed(s_init, r, c, sh_init[r]);
      ov.fitted = ev.processed(s_fit, r, c, sh_fit[r]);
      out.overlays.push_back(std::move(ov));
    }
  }
  if (const ModalTarget* mt = ev.modal())
    for (const auto& tm : mt->modes) {
      ModalPair mp;
      mp.frequency_hz = tm.frequency_hz;
      const Index j0 = ev.pair_mode(s_init, tm), j1 = ev.pair_mode(s_fit, tm);
      mp.model_before_hz = s_init.modal_f[j0];
      mp.model_after_hz = s_fit.modal_f[j1];
      mp.mac_before = tm.shape.size() ? Evaluator::mac_real(tm.shape, s_init.modal_shapes.col(j0)) : kNaN;
      mp.mac_after = tm.shape.size() ? Evaluator::mac_real(tm.shape, s_fit.modal_shapes.col(j1)) : kNaN;
      mp.damping_ratio = tm.damping_ratio;
      mp.model_damping_before = s_init.modal_zeta[j0];
      mp.model_damping_after = s_fit.modal_zeta[j1];
      out.modal_pairs.push_back(mp);
    }
}

void check_fit_input(const FitProblem& problem, const FitOptions& options) {
  std::string why;
  if (!options.is_valid(&why)) throw InputError("fit: " + why);
  if (problem.params.empty()) throw InputError("fit: no parameter to fit");
  if (!problem.scenario_at) throw InputError("fit: no scenario builder");
  for (const auto& p : problem.params) {
    const std::string k = "fit: parameter " + p.key + ": ";
    if (!std::isfinite(p.lower) || !std::isfinite(p.upper) || !(p.lower < p.upper))
      throw InputError(k + "bounds must be finite with lower < upper (got " + num(p.lower) + ":" + num(p.upper) + ")");
    if (p.scale == ParameterScale::log && !(p.lower > 0))
      throw InputError(k + "a logarithmic scale needs lower > 0 (got " + num(p.lower) + "); use a linear scale");
    if (!(p.initial >= p.lower && p.initial <= p.upper))
      throw InputError(k + "initial value " + num(p.initial) + " is outside the bounds [" + num(p.lower) + ", " + num(p.upper) + "]");
  }
}

// Standard errors, sensitivities, correlations and the flags that qualify them, from the
// Jacobian at the estimate (sandwich form with per-block variances); fills `out`.
void fit_statistics(const Evaluator& ev, const FitProblem& problem, const FitOptions& options, const StartOutcome& bo,
                    const Vector& r_fit, const Matrix& J, FitResult& out) {
  const std::size_t np = ev.n_params(), nz = ev.n_z();
  const Index m = J.rows();
  const auto nzi = static_cast<Index>(nz);
  const Matrix A = J.transpose() * J;
  Matrix B = Matrix::Zero(nzi, nzi);
  const double dof_factor = m > nzi ? static_cast<double>(m) / static_cast<double>(m - nzi) : 1.0;
  for (const auto& b : ev.blocks()) {
    const Matrix Jb = J.middleRows(b.offset, b.size);
    const double s2 = r_fit.segment(b.offset, b.size).squaredNorm() / static_cast<double>(b.size) * dof_factor;
    B += b.kappa * s2 * (Jb.transpose() * Jb);
  }
  std::vector<bool> in_null(nz, false), in_flat(nz, false);
  const Matrix Ainv = flat_directions(A, J, problem, in_null, in_flat, out.warnings);
  const Matrix Cz = Ainv * B * Ainv;
  const bool no_dof = m <= nzi;  // as many residuals as parameters: no noise estimate
  if (no_dof)
    out.warnings.push_back("the fit has " + std::to_string(m) + " residuals for " + std::to_string(nzi) +
                           " parameters: no standard errors without more data (more modes, sensors or records)");
  double col_max = 0.0;
  for (std::size_t i = 0; i < np; ++i) col_max = std::max(col_max, J.col(static_cast<Index>(i)).norm());
  out.std_error.assign(np, kNaN);
  out.sensitivity.assign(np, 0.0);
  out.at_bound.assign(np, false);
  out.determined.assign(np, true);
  for (std::size_t i = 0; i < np; ++i) out.determined[i] = !in_flat[i];
  for (std::size_t i = 0; i < np; ++i) {
    const FitParameter& p = problem.params[i];
    const auto ii = static_cast<Index>(i);
    const double col = J.col(ii).norm();
    out.sensitivity[i] = col_max > 0 ? col / col_max : 0.0;
    const double z = bo.z[i];
    out.at_bound[i] = z <= 1e-6 || z >= 1.0 - 1e-6;
    const double dpdz = p.scale == ParameterScale::log ? out.estimate[i] * std::log(p.upper / p.lower) : p.upper - p.lower;
    if (col <= 1e-9 * std::max(1.0, col_max)) {
      out.std_error[i] = kInf;
      out.determined[i] = false;
      out.warnings.push_back(p.key + " is insensitive: the fitted data do not change with it over [" + num(p.lower) + ", " +
                             num(p.upper) + "]; it keeps no meaning in this fit");
      continue;
    }
    out.std_error[i] = in_null[i] ? kInf : no_dof ? kNaN : dpdz * std::sqrt(std::max(0.0, Cz(ii, ii)));
    const double ref = p.scale == ParameterScale::log || out.estimate[i] != 0.0 ? std::abs(out.estimate[i]) : p.upper - p.lower;
    if (out.at_bound[i]) {
      out.determined[i] = false;
      out.warnings.push_back(p.key + " ended on its " + std::string(z <= 0.5 ? "lower" : "upper") + " bound " +
                             num(z <= 0.5 ? p.lower : p.upper) +
                             ": the data want a value beyond it (widen the bounds or question the model); its standard error is not meaningful");
    } else if (!no_dof && !(out.std_error[i] <= options.max_relative_std * ref)) {
      out.determined[i] = false;
      out.warnings.push_back(p.key + " is not determined by the data: standard error " +
                             (std::isfinite(out.std_error[i]) ? num(100.0 * out.std_error[i] / ref, 3) + " % of the estimate" : "unbounded (flat direction)"));
    }
  }
  fit_correlations(problem, options, Cz, in_null, out);
}

}  // namespace

FitResult fit(const FitProblem& problem, const FitOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  // The library is quiet: Ceres' own log lines (glog) are dropped; its messages reach the result.
  static std::once_flag quiet_glog;
  std::call_once(quiet_glog, [] { FLAGS_minloglevel = google::GLOG_FATAL; });
  check_fit_input(problem, options);
  const Evaluator ev(problem, options);
  // The spectral pre-stage: amplitude spectra (and the modal objective) only.
  FitOptions pre_options = options;
  pre_options.weights = FitWeights{0, 0, 0, 1, options.weights.modal, options.weights.damping};
  std::unique_ptr<Evaluator> pre;
  if (options.spectral_start && (options.weights.time > 0 || options.weights.envelope > 0))
    pre = std::make_unique<Evaluator>(problem, pre_options);
  FitResult out;
  out.warnings = ev.record_warnings();
  out.n_residuals = static_cast<int>(ev.n_residuals());
  out.initial = initial_values(problem);
  const std::size_t np = ev.n_params(), nz = ev.n_z();
  std::vector<double> z_init(nz, 0.5);
  for (std::size_t i = 0; i < np; ++i) z_init[i] = to_unit(problem.params[i], problem.params[i].initial);

  // Starts: the initial values, then Halton points inside the box.
  static const int primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  std::vector<StartOutcome> outcomes;
  for (int s = 0; s < options.starts; ++s) {
    std::vector<double> z0 = z_init;
    if (s > 0)
      for (std::size_t i = 0; i < np; ++i) z0[i] = 0.05 + 0.9 * halton(s, primes[i % 16] + static_cast<int>(i / 16) * 59);
    if (pre) {
      const StartOutcome so = run_start(*pre, pre_options, z0, s, 1, out);
      out.iterations += so.iterations;
      if (std::isfinite(so.cost)) z0 = so.z;
    }
    outcomes.push_back(run_start(ev, options, z0, s, 0, out));
    out.start_costs.push_back(outcomes.back().cost);
    out.iterations += outcomes.back().iterations;
  }
  std::size_t best = 0;
  for (std::size_t s = 1; s < outcomes.size(); ++s)
    if (outcomes[s].cost < outcomes[best].cost) best = s;
  out.best_start = static_cast<int>(best);
  const StartOutcome& bo = outcomes[best];
  out.status = bo.status;
  out.message = bo.message;
  if (!std::isfinite(bo.cost)) {
    out.message = "every start failed; first: " + outcomes.front().message;
    out.estimate = out.initial;
    out.std_error.assign(np, kNaN);
    out.sensitivity.assign(np, kNaN);
    out.at_bound.assign(np, false);
    out.determined.assign(np, false);
    out.correlation = Matrix::Constant(static_cast<Index>(np), static_cast<Index>(np), kNaN);
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return out;
  }
  out.estimate = ev.values_of(bo.z.data());

  // Statistics from the Jacobian at the estimate (sandwich form with per-block variances).
  Vector r_fit, r_init;
  Matrix J, J_init;
  jacobian_at(ev, options, bo.z, r_fit, J);
  {
    Cost c(ev, options);
    r_init.resize(ev.n_residuals());
    const double* pz = z_init.data();
    if (!c.Evaluate(&pz, r_init.data(), nullptr)) throw SolverError("fit: the model fails at the initial values: " + c.last_error());
  }
  out.cost_initial = 0.5 * r_init.squaredNorm();
  out.cost_final = 0.5 * r_fit.squaredNorm();
  fit_statistics(ev, problem, options, bo, r_fit, J, out);

  // Terms, overlays and modal pairs before and after.
  for (const auto& b : ev.blocks())
    out.terms.push_back({b.objective, b.record, b.channel, r_init.segment(b.offset, b.size).squaredNorm(),
                         r_fit.segment(b.offset, b.size).squaredNorm()});
  fit_overlays(ev, problem, out);
  out.simulations = ev.simulations() + (pre ? pre->simulations() : 0);
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return out;
}

}  // namespace viaduct::study
