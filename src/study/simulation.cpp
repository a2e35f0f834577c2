#include "viaduct/study/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/vehicles.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "divergence.hpp"
#include "modal_path_table.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::study {

std::vector<ResolvedStation> resolve_stations(const model::Structure& s,
                                              const std::vector<StationSpec>& specs) {
  if (specs.empty()) throw InputError("at least one station is needed");
  std::vector<ResolvedStation> out;
  for (const auto& sp : specs) {
    ResolvedStation r;
    r.name = sp.name;
    try {
      if (sp.on_deck) {
        r.deck = s.deck_point(sp.span, sp.x_local);
        r.has_deck = true;
        if (s.has_track) {
          r.rail = s.rail_point(s.span_start[sp.span] + sp.x_local);
          r.has_rail = true;
        }
      } else {
        r.rail = s.rail_point(sp.x_track);
        r.has_rail = true;
      }
    } catch (const InputError& e) {
      throw InputError("station '" + sp.name + "': " + e.what());
    }
    out.push_back(r);
  }
  return out;
}

solve::Functional functional_of(const model::PointCoupling& c) {
  solve::Functional f;
  for (std::size_t i = 0; i < 4; ++i)
    if (c.dofs[i] >= 0) {
      f.dof.push_back(c.dofs[i]);
      f.weight.push_back(c.N[i]);
    }
  return f;
}

std::vector<LoadEffect> load_effects(const model::Structure& s, const std::vector<StationSpec>& stations,
                                     const std::vector<StationSpec>& along) {
  auto functional = [](const model::DofWeights& w, double scale) {
    solve::Functional f;
    f.dof = w.dof;
    for (double x : w.weight) f.weight.push_back(scale * x);
    return f;
  };
  std::vector<LoadEffect> out;
  auto station_effects = [&](const StationSpec& st) {
    const model::DofWeights m = s.deck_moment(st.span, st.x_local);
    out.push_back({st.name + "_moment_Nm", functional(m, 1.0)});
    // ε = M·y/EI exactly: the same functional scaled (to microstrain).
    if (st.fibre_m != 0.0) out.push_back({st.name + "_strain_ue", functional(m, 1e6 * st.fibre_m / s.span_EI[st.span])});
    out.push_back({st.name + "_shear_N", functional(s.deck_shear(st.span, st.x_local), 1.0)});
  };
  for (const auto& st : stations)
    if (st.on_deck) station_effects(st);
  for (const auto& st : along) {
    if (!st.on_deck) throw InputError("station '" + st.name + "': load effects along a span need a deck station");
    out.push_back({st.name + "_disp_m", functional_of(s.deck_point(st.span, st.x_local))});
    station_effects(st);
  }
  if (s.continuous) {  // the deck's rotation over every support (a span's end is the next one's start)
    for (const model::BearingForce& bf : s.bearings)
      out.push_back({bf.name + "_rot_rad", functional(s.deck_end_rotation(bf.span, bf.end), 1.0)});
  } else {
    for (std::size_t k = 0; k < s.span_start.size(); ++k) {
      const std::string span = "span" + std::to_string(k + 1);
      out.push_back({span + "_start_rot_rad", functional(s.deck_end_rotation(k, false), 1.0)});
      out.push_back({span + "_end_rot_rad", functional(s.deck_end_rotation(k, true), 1.0)});
    }
  }
  for (std::size_t b = 0; b < s.bearings.size(); ++b) {
    const model::BearingForce& bf = s.bearings[b];
    out.push_back({bf.name + "_reaction_N", functional(bf.k, 1.0), functional(bf.m, 1.0), functional(bf.c, 1.0), static_cast<int>(b)});
  }
  return out;
}

double bearing_load(const model::Structure& s, const LoadEffect& e, const load::Train& train, double load_factor, double x_head) {
  if (e.bearing < 0 || s.has_track) return 0.0;  // with a track the axles load the rail
  const model::BearingForce& bf = s.bearings[static_cast<std::size_t>(e.bearing)];
  if (!bf.rigid) return 0.0;
  double f = 0.0;
  for (std::size_t k = 0; k < train.n_axles(); ++k) {
    const double o = train.offset[k];
    // An element holds [x0, x0 + h), the path's last one its end too: load::MovingLoads' rule,
    // so that an axle exactly on the joint of two spans loads the next span's start bearing and
    // one at the bridge's end (no track) its end bearing; over a continuous deck's support, once.
    // Compared in head positions, o + x0 and o + x1, as fold_train's breaks are: the peaks kernel
    // finds the same axles on the same elements.
    for (const auto& be : bf.elements) {
      const double x0 = be.element.x0, x1 = x0 + be.element.h, lo = o + x0, hi = o + x1;
      if (x_head < lo || x_head > hi || (x_head == hi && x1 < s.path_end())) continue;
      const double xi = (x_head - lo) / be.element.h;
      f += load_factor * train.load[k] * model::hermite_shape(xi, be.element.h)[static_cast<std::size_t>(be.fixed_local)];
    }
  }
  return f;
}

model::Modes kept_modes(const model::Structure& s, const ModalSettings& ms) {
  if (ms.n_modes < 0) throw InputError("modal.n_modes must be >= 0");
  require_non_negative(ms.max_frequency_hz, "modal.max_frequency_hz [Hz]");
  model::Modes modes = model::compute_modes_up_to(s, ms.n_modes, ms.max_frequency_hz);
  if (modes.frequency_hz.size() < 1) {
    const model::Modes first = model::compute_modes_up_to(s, 1, 0.0);
    throw InputError("modal.max_frequency_hz = " + format_number(ms.max_frequency_hz, 6) +
                     " Hz keeps no mode: the lowest is " + format_number(first.frequency_hz[0], 6) + " Hz");
  }
  return modes;
}

namespace {

// The outputs one effect records: its functional, then its inertia and damping parts if any.
std::vector<solve::Functional> effect_outputs(const LoadEffect& e) {
  std::vector<solve::Functional> out = {e.functional};
  if (!e.inertia.dof.empty()) out.push_back(e.inertia);
  if (!e.damping.dof.empty()) out.push_back(e.damping);
  return out;
}

std::shared_ptr<const ModalPathTable> make_path_table(const model::Structure& s, const solve::ModalReduction& r) {
  auto t = std::make_shared<ModalPathTable>();
  t->m = static_cast<std::size_t>(r.n_channels());
  t->flex = r.static_correction();
  t->n_out = t->flex ? static_cast<std::size_t>(r.n_outputs()) : 0;
  t->stride = 4 * (t->m + t->n_out);
  t->x_start = s.path_start();
  t->x_end = s.path_end();
  const auto& path = s.load_path();
  t->coef.assign(path.size() * t->stride, 0.0);
  // g(ξ) = N1 a + N2 b + N3 c + N4 d (Hermite, model::hermite_shape) expanded in powers of ξ.
  auto cubic = [](double a, double b, double c, double d, double h, double* out) {
    out[0] = a;
    out[1] = h * b;
    out[2] = -3.0 * a - 2.0 * h * b + 3.0 * c - h * d;
    out[3] = 2.0 * a + h * b - 2.0 * c + h * d;
  };
  for (std::size_t e = 0; e < path.size(); ++e) {
    const model::PathElement& pe = path[e];
    t->x0.push_back(pe.x0);
    t->h.push_back(pe.h);
    t->inv_h.push_back(1.0 / pe.h);
    double* ce = &t->coef[e * t->stride];
    auto value = [&](const solve::ModalReduction::RowMatrix& rows, std::size_t q, std::size_t col) {
      return pe.dofs[q] >= 0 ? rows(pe.dofs[q], static_cast<Index>(col)) : 0.0;
    };
    for (std::size_t i = 0; i < t->m; ++i) {
      const auto& R = r.load_rows();
      cubic(value(R, 0, i), value(R, 1, i), value(R, 2, i), value(R, 3, i), pe.h, ce + 4 * i);
    }
    for (std::size_t j = 0; j < t->n_out; ++j) {
      const auto& R = r.flexibility_rows();
      cubic(value(R, 0, j), value(R, 1, j), value(R, 2, j), value(R, 3, j), pe.h, ce + 4 * (t->m + j));
    }
  }
  return t;
}

// A train's axles projected through the path table. Keeps the window of axles on the path and
// each axle's element, both advanced incrementally (time never goes back).
class MovingModalForce : public solve::ModalForce {
 public:
  MovingModalForce(const ModalPathTable& t, const load::Train& train, double speed, double load_factor)
      : t_(t), offset_(train.offset), load_(train.load), elem_(train.offset.size(), 0), speed_(speed) {
    for (double& p : load_) p *= load_factor;
  }
  bool has_second_derivative() const override { return true; }
  void project(double t, double* p, double* g, double* p2, double* g2) override {
    std::fill(p, p + t_.m, 0.0);
    if (g) std::fill(g, g + t_.n_out, 0.0);
    if (p2) std::fill(p2, p2 + t_.m, 0.0);
    if (g2) std::fill(g2, g2 + t_.n_out, 0.0);
    const double head = t_.x_start + speed_ * t;
    const std::size_t n = offset_.size(), ne = t_.x0.size();
    while (last_ < n && head - offset_[last_] >= t_.x_start) ++last_;
    while (first_ < last_ && head - offset_[first_] > t_.x_end) ++first_;
    for (std::size_t k = first_; k < last_; ++k) {
      const double x = head - offset_[k];
      std::size_t e = elem_[k];
      while (e + 1 < ne && x >= t_.x0[e + 1]) ++e;
      elem_[k] = e;
      const double xi = std::clamp((x - t_.x0[e]) * t_.inv_h[e], 0.0, 1.0);
      const double P = load_[k];
      const double* c = &t_.coef[e * t_.stride];
      for (std::size_t i = 0; i < t_.m; ++i, c += 4) p[i] += P * (c[0] + xi * (c[1] + xi * (c[2] + xi * c[3])));
      if (g)
        for (std::size_t j = 0; j < t_.n_out; ++j, c += 4) g[j] += P * (c[0] + xi * (c[1] + xi * (c[2] + xi * c[3])));
      if (p2) {
        // d²/dt² of a load moving at v: v² d²/dx², and d/dx = (1/h) d/dξ on the element.
        const double s2 = P * speed_ * speed_ * t_.inv_h[e] * t_.inv_h[e];
        const double* d = &t_.coef[e * t_.stride];
        for (std::size_t i = 0; i < t_.m; ++i, d += 4) p2[i] += s2 * (2.0 * d[2] + 6.0 * d[3] * xi);
        if (g2)
          for (std::size_t j = 0; j < t_.n_out; ++j, d += 4) g2[j] += s2 * (2.0 * d[2] + 6.0 * d[3] * xi);
      }
    }
  }

 private:
  const ModalPathTable& t_;
  std::vector<double> offset_, load_;
  std::vector<std::size_t> elem_;
  double speed_;
  std::size_t first_ = 0, last_ = 0;
};

// Output functionals of the modal model: each station's main point, then the rail above deck
// stations (track models).
std::vector<solve::Functional> station_functionals(const std::vector<ResolvedStation>& stations, bool rail) {
  std::vector<solve::Functional> out;
  for (const auto& st : stations) out.push_back(functional_of(st.has_deck ? st.deck : st.rail));
  if (rail)
    for (const auto& st : stations)
      if (st.has_deck && st.has_rail) out.push_back(functional_of(st.rail));
  return out;
}

// Their names, in the same order (the divergence guard's messages).
std::vector<std::string> station_output_names(const std::vector<ResolvedStation>& stations, bool rail) {
  std::vector<std::string> out;
  for (const auto& st : stations) out.push_back(st.name + (st.has_deck ? " deflection [m]" : " rail deflection [m]"));
  if (rail)
    for (const auto& st : stations)
      if (st.has_deck && st.has_rail) out.push_back(st.name + " rail deflection [m]");
  return out;
}

std::shared_ptr<const solve::ModalReduction> make_modal(const model::Structure& s,
                                                        const std::vector<ResolvedStation>& stations,
                                                        const ModalSettings& ms, bool rail, Vector* kept_hz,
                                                        double dt, const std::vector<LoadEffect>& effects = {}) {
  const model::Modes modes = kept_modes(s, ms);
  const Index n = modes.frequency_hz.size();
  if (kept_hz) *kept_hz = modes.frequency_hz.head(n);
  Matrix shapes = modes.shape.leftCols(n);
  for (Index j = 0; j < n; ++j) shapes.col(j) /= std::sqrt(shapes.col(j).dot(s.M * shapes.col(j)));
  Vector omega = (2.0 * M_PI) * modes.frequency_hz.head(n);
  if (ms.damping_vectors < 0 || ms.damping_vectors > 3) throw InputError("modal.damping_vectors must be in [0, 3]");
  if (ms.damping_vectors > 0)
    // Ritz pairs up to 80 % of the output's Nyquist frequency π/dt: above it they would alias
    // into the filter's band (the vectors are then seeded by fewer modes).
    shapes = solve::damping_enriched_basis(s.M, s.C, s.K, shapes, Vector(omega), ms.damping_vectors, &omega,
                                           0.8 * M_PI / dt);
  std::vector<solve::Functional> outputs = station_functionals(stations, rail);
  for (const auto& e : effects)
    for (auto& f : effect_outputs(e)) outputs.push_back(std::move(f));
  return std::make_shared<const solve::ModalReduction>(s.M, s.C, s.K, shapes, omega, outputs, ms.static_correction);
}

RunResult allocate_histories(const std::vector<ResolvedStation>& stations, double t_end, double dt,
                             std::size_t n_effect_outputs = 0) {
  const double n_samples_real = std::ceil(t_end / dt - 1e-9) + 1;
  // Every step is recorded: refuse runs whose histories alone would not fit comfortably (each
  // effect output records a deflection and an acceleration history).
  const double bytes =
      n_samples_real * static_cast<double>(1 + 4 * stations.size() + 2 * n_effect_outputs) * sizeof(double);
  if (bytes > kMaxHistoryBytes)
    throw InputError("a run of " + format_number(t_end, 6) + " s at dt = " + format_number(dt, 6) + " s records " +
                     format_number(n_samples_real, 6) + " samples (" + format_number(bytes / (1 << 30), 3) +
                     " GiB of histories; at most " + format_number(kMaxHistoryBytes / (1 << 30), 3) +
                     " GiB): raise the speed or analysis.dt");
  const auto n_samples = static_cast<Index>(n_samples_real);
  RunResult r;
  r.t.resize(n_samples);
  for (Index k = 0; k < n_samples; ++k) r.t[k] = static_cast<double>(k) * dt;
  for (const auto& st : stations) {
    StationHistory h;
    h.name = st.name;
    h.on_deck = st.has_deck;
    h.disp.resize(n_samples);
    h.acc.resize(n_samples);
    if (st.has_deck && st.has_rail) h.rail_disp.resize(n_samples);
    r.stations.push_back(std::move(h));
  }
  return r;
}

void apply_filter(RunResult& r, const RunSettings& settings) {
  if (!settings.filter.enabled) return;
  const signal::FiltfiltFromRest filt(signal::cheby1(settings.filter.cheby, 1.0 / settings.dt));
  // The response starts at rest and is cut after free_vibration_s: filtered as zero outside
  // the record, so that maxima do not depend on the step (docs/accuracy.md).
  for (auto& h : r.stations) h.acc_filt = filt(h.acc);
}

// The recorded outputs: each station's main point, then the rail above deck stations (track
// models; rail_out[i] its column, -1 when not recorded). A modal model holds its own outputs in
// this order (rails only when prepared with rail_outputs).
// Load effects follow (effect_out: the column of the first).
struct OutputMap {
  std::vector<solve::Functional> outputs;
  std::vector<std::string> names;  // per output, for the divergence guard's messages
  std::vector<Index> rail_out;
  struct Effect {
    std::string name;
    Index value = -1, inertia = -1, damping = -1;  // output columns (-1: none)
  };
  std::vector<Effect> effects;
};

// `rail`: the rails above deck stations are outputs (a modal model prepared without them has
// none); `effects` are the model's load effects (a modal model holds them after its stations).
OutputMap output_map(const std::vector<ResolvedStation>& stations, bool rail, const std::vector<LoadEffect>& effects) {
  OutputMap o;
  o.outputs = station_functionals(stations, rail);
  o.names = station_output_names(stations, rail);
  Index next = static_cast<Index>(stations.size());
  o.rail_out.assign(stations.size(), -1);
  for (std::size_t i = 0; i < stations.size(); ++i)
    if (rail && stations[i].has_deck && stations[i].has_rail) o.rail_out[i] = next++;
  for (const auto& e : effects) {
    // The columns in effect_outputs' order: the functional, then inertia and damping if any.
    OutputMap::Effect m;
    m.name = e.name;
    Index col = static_cast<Index>(o.outputs.size());
    m.value = col++;
    if (!e.inertia.dof.empty()) m.inertia = col++;
    if (!e.damping.dof.empty()) m.damping = col++;
    for (auto& f : effect_outputs(e)) o.outputs.push_back(std::move(f));
    o.names.push_back(e.name);
    if (m.inertia >= 0) o.names.push_back(e.name + " (its inertia part)");
    if (m.damping >= 0) o.names.push_back(e.name + " (its damping part)");
    o.effects.push_back(m);
  }
  return o;
}

// A case's recorded outputs into the station histories of `r` (allocated for the same samples).
void take_histories(const solve::CaseResult& c, const OutputMap& map, RunResult& r) {
  for (std::size_t i = 0; i < r.stations.size(); ++i) {
    StationHistory& h = r.stations[i];
    h.disp = c.disp.col(static_cast<Index>(i));
    h.acc = c.acc.col(static_cast<Index>(i));
    if (map.rail_out[i] >= 0) h.rail_disp = c.disp.col(map.rail_out[i]);
    else h.rail_disp.resize(0);  // not an output of this modal model
  }
  r.effects.clear();
  for (const auto& e : map.effects) {
    Vector y = c.disp.col(e.value);
    if (e.inertia >= 0) y += c.acc.col(e.inertia);
    if (e.damping >= 0) {  // damping·v, v the trapezoidal integral of the recorded damping·a
      const Vector ca = c.acc.col(e.damping);
      double v = 0.0;
      for (Index k = 1; k < y.size(); ++k) {
        v += 0.5 * (r.t[k] - r.t[k - 1]) * (ca[k - 1] + ca[k]);
        y[k] += v;
      }
    }
    r.effects.push_back({e.name, y});
  }
  r.summary = c.summary;
  r.n_modes = c.summary.n_modes;
}

// Axles on a rigid bearing's own element load its fixed DOF directly: added to the bearing
// forces recorded in `r` (a run of `train` at r.speed).
void add_bearing_loads(const model::Structure& s, const std::vector<LoadEffect>& effects, const load::Train& train,
                       double load_factor, RunResult& r) {
  for (std::size_t j = 0; j < effects.size() && j < r.effects.size(); ++j)
    if (effects[j].bearing >= 0)
      for (Index k = 0; k < r.t.size(); ++k)
        r.effects[j].value[k] += bearing_load(s, effects[j], train, load_factor, s.path_start() + r.speed * r.t[k]);
}

// Integrates the loads of `sys` for t in [0, t_end] into histories (unfiltered), with the
// integrator the settings choose.
// The outputs of a case: the stations (with their rails, unless a modal model left them out) and
// the load effects the model was prepared with.
struct CaseOutputs {
  const std::vector<ResolvedStation>& stations;
  bool modal_rails = true;
  const std::vector<LoadEffect>& effects;
  const model::Structure& structure;
  const StaticFactor* statics = nullptr;  // K factored (null: factored for the guard here)
};

RunResult integrate(const CaseOutputs& out,
                    const std::shared_ptr<const solve::ModalReduction>& modal, const ModalPathTable* path,
                    const solve::SecondOrderSystem& sys, const load::Train& train, double speed, double t_end,
                    const RunSettings& settings) {
  const auto& stations = out.stations;
  const bool modal_run = solve::method_traits(settings.method).needs_reduction;
  const OutputMap map = output_map(stations, !modal_run || out.modal_rails, out.effects);
  RunResult r = allocate_histories(stations, t_end, settings.dt, map.outputs.size() - stations.size());
  r.method = settings.method;
  const auto integrator = solve::make_integrator(settings.integration(), map.outputs, modal);
  solve::LoadCase c;
  c.system = &sys;
  c.t_end = t_end;
  std::unique_ptr<MovingModalForce> force;
  if (modal_run && path) {
    force = std::make_unique<MovingModalForce>(*path, train, speed, settings.load_factor);
    c.modal_force = force.get();
  }
  const solve::DivergenceBound bound =
      divergence_bound(influence_maxima(out.structure, map.outputs, out.statics), map.names, train, settings.load_factor);
  c.bound = &bound;
  solve::Recording rec;
  rec.max_history_bytes = kMaxHistoryBytes;
  take_histories(integrator->run(c, rec), map, r);
  return r;
}

RunResult simulate_impl(const model::Structure& s, const CaseOutputs& out,
                        const std::shared_ptr<const solve::ModalReduction>& modal, const ModalPathTable* path,
                        const load::Train& train, double speed,
                        const RunSettings& settings, double t_end_min = 0.0) {
  require_positive(speed, "speed [m/s]");
  require_non_negative(settings.free_vibration_s, "free_vibration_s [s]");
  require_positive(settings.dt, "analysis.dt [s]");
  const load::MovingLoads loads(s, train, speed, settings.load_factor);
  const MovingLoadSystem sys(s, loads);
  const double t_end = std::max(loads.t_exit() + settings.free_vibration_s, t_end_min);
  RunResult r = integrate(out, modal, path, sys, train, speed, t_end, settings);
  r.speed = speed;
  add_bearing_loads(s, out.effects, train, settings.load_factor, r);
  return r;
}

// 4-point Lagrange weights for a value at fractional position u in [0, 1) between samples
// j and j+1, using samples j-1 .. j+2.
std::array<double, 4> lagrange4(double u) {
  return {-u * (u - 1.0) * (u - 2.0) / 6.0, (u + 1.0) * (u - 1.0) * (u - 2.0) / 2.0,
          -(u + 1.0) * u * (u - 2.0) / 2.0, (u + 1.0) * u * (u - 1.0) / 6.0};
}

// y[n] += P · r(n·dt − shift) for n in [0, y.size()), with r = 0 before its first sample and
// r held at its last sample beyond its end (never reached: the unit run covers every train).
void add_shifted(const Vector& r, double shift_samples, double P, Vector& y) {
  const Index n_r = r.size(), n_y = y.size();
  const auto m = static_cast<Index>(std::floor(shift_samples));
  const double u = shift_samples - static_cast<double>(m);
  // r(n - m - u): between samples j = n - m - 1 and j + 1 at fraction 1 - u (u > 0), or at j + 1.
  if (u < 1e-12) {
    for (Index n = std::max<Index>(m, 0); n < n_y; ++n) {
      const Index j = n - m;
      y[n] += P * r[std::min(j, n_r - 1)];
    }
    return;
  }
  const auto w = lagrange4(1.0 - u);
  auto at = [&](Index j) { return j < 0 ? 0.0 : r[std::min(j, n_r - 1)]; };
  for (Index n = std::max<Index>(m + 1, 0); n < n_y; ++n) {
    const Index j = n - m - 1;  // r(j + 1 - u) = r(j + (1 - u))
    y[n] += P * (w[0] * at(j - 1) + w[1] * at(j) + w[2] * at(j + 1) + w[3] * at(j + 2));
  }
}

bool same_functionals(const std::vector<solve::Functional>& a, const std::vector<solve::Functional>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].dof != b[i].dof || a[i].weight != b[i].weight) return false;
  return true;
}

}  // namespace

// influence_maxima(m.structure, outputs, m.statics) through m.imax: the value kept for this
// structure and these outputs, or computed and kept (one K solve per output and the path's
// Hermite weights: 3 % of the 31-station sweep of docs/benchmarks.md when each of its 360 jobs
// computed them).
Vector guard_influence_maxima(const PreparedModel& m, const std::vector<solve::Functional>& outputs) {
  if (!m.imax) return influence_maxima(m.structure, outputs, m.statics.get());
  {
    const std::lock_guard<std::mutex> lock(m.imax->m);
    if (m.imax->structure == &m.structure && same_functionals(m.imax->outputs, outputs)) return m.imax->value;
  }
  Vector v = influence_maxima(m.structure, outputs, m.statics.get());
  const std::lock_guard<std::mutex> lock(m.imax->m);
  m.imax->structure = &m.structure;
  m.imax->outputs = outputs;
  m.imax->value = v;
  return v;
}

PreparedModel prepare_model(model::Structure s, const std::vector<StationSpec>& stations,
                            const RunSettings& settings, bool rail_outputs, bool with_load_effects,
                            const std::vector<StationSpec>& effect_stations) {
  PreparedModel m;
  m.structure = std::move(s);
  m.stations = resolve_stations(m.structure, stations);
  if (with_load_effects) m.effects = load_effects(m.structure, stations, effect_stations);
  m.modal_rails = rail_outputs;
  m.statics = factor_statics(m.structure);
  m.imax = std::make_shared<InfluenceMaximaCache>();
  if (settings.vehicle.model != VehicleModel::forces) {
    // Vehicles: the coupled kernel on every DOF or on the modes (the fast path), and the profile.
    m.profile = rail_profile(m.structure, settings.irregularity);
    if (vehicles_on_modes(settings)) {  // the fast path and IDA
      m.vehicle_modal = vehicle_reduction(m.structure, settings.modal, vehicle_outputs(m.stations, m.effects),
                                          &m.modal_frequency_hz);
    }
  } else if (solve::method_traits(settings.method).needs_reduction) {
    m.modal = make_modal(m.structure, m.stations, settings.modal, rail_outputs, &m.modal_frequency_hz, settings.dt,
                         m.effects);
    m.modal_path = make_path_table(m.structure, *m.modal);
  }
  return m;
}

PreparedModel prepare_model(const Scenario& sc, bool rail_outputs, bool with_load_effects) {
  return prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, sc.settings, rail_outputs,
                       with_load_effects, sc.effect_stations);
}

double passage_speed(const Scenario& sc, const std::optional<double>& speed_kmh, const std::string& option) {
  if (speed_kmh) {
    const double v = *speed_kmh / 3.6;
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(option + " must be > 0");
    return v;
  }
  if (sc.run_speed) return *sc.run_speed;
  throw InputError("no speed: give " + option + " or run.speed_kmh in the scenario");
}

const load::Train& passage_train(const Scenario& sc, const std::optional<std::string>& name) {
  if (!name) return sc.trains.front();
  std::string names;
  for (const auto& t : sc.trains) {
    names += " " + t.name;
    if (t.name == *name) return t;
  }
  throw InputError("no train named '" + *name + "'; the scenario has:" + names);
}

std::size_t station_index(const Scenario& sc, const std::string& name, const std::string& who) {
  for (std::size_t i = 0; i < sc.stations.size(); ++i)
    if (sc.stations[i].name == name) return i;
  std::string have;
  for (const auto& s : sc.stations) have += " " + s.name;
  throw InputError(who + ": no station '" + name + "' in the scenario; it has:" + have);
}

void require_strain_fibre(const Scenario& sc, std::size_t station, const std::string& channel, ResponseKind k,
                          const std::string& who) {
  // Strain against the model's <station>_strain_ue = 1e6 M y / EI at the gauge's fibre.
  if (k == ResponseKind::strain && sc.stations[station].fibre_m == 0.0)
    throw InputError(who + ": channel '" + channel + "' is a strain; station '" + sc.stations[station].name +
                     "' has no stations[].fibre_m (the gauge's distance below the neutral axis) to give the model's strain");
}

RunResult simulate(const PreparedModel& m, const load::Train& train, double speed, const RunSettings& settings) {
  if (settings.vehicle.model != VehicleModel::forces) {
    RunResult r = simulate_vehicles(m, train, speed, settings);
    apply_filter(r, settings);
    return r;
  }
  RunResult r = simulate_impl(m.structure, {m.stations, m.modal_rails, m.effects, m.structure, m.statics.get()}, m.modal,
                              m.modal_path.get(), train, speed, settings);
  apply_filter(r, settings);
  return r;
}

RunResult simulate(const model::Structure& s, const std::vector<ResolvedStation>& stations,
                   const load::Train& train, double speed, const RunSettings& settings) {
  if (settings.vehicle.model != VehicleModel::forces) {
    PreparedModel m;
    m.structure = s;
    m.stations = stations;
    m.profile = rail_profile(s, settings.irregularity);
    return simulate(m, train, speed, settings);
  }
  std::shared_ptr<const solve::ModalReduction> modal;
  std::shared_ptr<const ModalPathTable> path;
  if (solve::method_traits(settings.method).needs_reduction) {
    modal = make_modal(s, stations, settings.modal, true, nullptr, settings.dt);
    path = make_path_table(s, *modal);
  }
  RunResult r = simulate_impl(s, {stations, true, {}, s}, modal, path.get(), train, speed, settings);
  apply_filter(r, settings);
  return r;
}

std::vector<RunResult> simulate_batch(const PreparedModel& m, const load::Train& train,
                                      const std::vector<double>& speeds, const RunSettings& settings) {
  std::vector<RunResult> out;
  if (!solve::method_traits(settings.method).batches_histories || settings.vehicle.model != VehicleModel::forces) {
    for (double v : speeds) out.push_back(simulate(m, train, v, settings));
    return out;
  }
  require_non_negative(settings.free_vibration_s, "free_vibration_s [s]");
  require_positive(settings.dt, "analysis.dt [s]");
  const OutputMap map = output_map(m.stations, true, m.effects);
  const auto integrator = solve::make_integrator(settings.integration(), map.outputs);
  const std::size_t width = integrator->batch_width();
  const solve::DivergenceBound bound =
      divergence_bound(guard_influence_maxima(m, map.outputs), map.names, train, settings.load_factor);
  solve::Recording rec;
  rec.max_history_bytes = kMaxHistoryBytes;
  for (std::size_t first = 0; first < speeds.size(); first += width) {
    const std::size_t n = std::min(width, speeds.size() - first);
    std::vector<std::unique_ptr<load::MovingLoads>> loads;
    std::vector<std::unique_ptr<MovingLoadSystem>> systems;
    std::vector<solve::LoadCase> cases;
    std::vector<RunResult> runs;
    for (std::size_t l = 0; l < n; ++l) {
      const double v = speeds[first + l];
      require_positive(v, "speed [m/s]");
      loads.push_back(std::make_unique<load::MovingLoads>(m.structure, train, v, settings.load_factor));
      systems.push_back(std::make_unique<MovingLoadSystem>(m.structure, *loads.back()));
      solve::LoadCase c;
      c.system = systems.back().get();
      c.t_end = loads.back()->t_exit() + settings.free_vibration_s;
      c.bound = &bound;
      cases.push_back(c);
      // refuses oversized runs
      runs.push_back(allocate_histories(m.stations, c.t_end, settings.dt, map.outputs.size() - m.stations.size()));
    }
    const std::vector<solve::CaseResult> h = integrator->run_batch(cases, rec);
    for (std::size_t l = 0; l < n; ++l) {
      RunResult& r = runs[l];
      r.method = Method::newmark;
      r.speed = speeds[first + l];
      take_histories(h[l], map, r);
      add_bearing_loads(m.structure, m.effects, train, settings.load_factor, r);
      apply_filter(r, settings);
      out.push_back(std::move(r));
    }
  }
  return out;
}

std::vector<RunResult> simulate_by_unit_response(const PreparedModel& m, const std::vector<load::Train>& trains,
                                                 double speed, const RunSettings& settings) {
  require_positive(speed, "speed [m/s]");
  require_positive(settings.load_factor, "train.load_factor");
  if (trains.empty()) throw InputError("unit-response superposition needs at least one train");
  if (settings.vehicle.model != VehicleModel::forces)
    throw InputError("analysis.superposition = \"unit-response\" composes constant axle loads: it cannot take train.vehicle = \"" +
                     std::string(vehicle_model_name(settings.vehicle.model)) + "\" (use direct)");
  const auto wall0 = std::chrono::steady_clock::now();
  const double dt = settings.dt;
  // Every train's duration; the unit run covers the longest.
  double t_end_max = 0.0;
  std::vector<double> t_end(trains.size());
  for (std::size_t i = 0; i < trains.size(); ++i) {
    trains[i].validate();
    const load::MovingLoads loads(m.structure, trains[i], speed, 1.0);
    t_end[i] = loads.t_exit() + settings.free_vibration_s;
    t_end_max = std::max(t_end_max, t_end[i]);
  }
  load::Train unit;
  unit.name = "unit axle";
  unit.offset = {0.0};
  unit.load = {1.0};
  RunSettings us = settings;
  us.load_factor = 1.0;
  const RunResult unit_run =
      simulate_impl(m.structure, {m.stations, m.modal_rails, {}, m.structure, m.statics.get()}, m.modal,
                    m.modal_path.get(), unit, speed, us, t_end_max + 3 * dt);
  const double unit_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  std::vector<RunResult> out;
  for (std::size_t i = 0; i < trains.size(); ++i) {
    const auto w0 = std::chrono::steady_clock::now();
    RunResult r = allocate_histories(m.stations, t_end[i], dt);
    r.speed = speed;
    r.method = unit_run.method;
    r.n_modes = unit_run.n_modes;
    for (Index k = 0; k < r.t.size(); ++k) r.t[k] = static_cast<double>(k) * dt;
    for (std::size_t j = 0; j < r.stations.size(); ++j) {
      StationHistory& h = r.stations[j];
      const StationHistory& u = unit_run.stations[j];
      h.disp.setZero();
      h.acc.setZero();
      if (u.rail_disp.size() == 0) h.rail_disp.resize(0);  // not recorded by the unit run
      if (h.rail_disp.size()) h.rail_disp.setZero();
      for (std::size_t a = 0; a < trains[i].offset.size(); ++a) {
        const double shift = trains[i].offset[a] / speed / dt;
        const double P = trains[i].load[a] * settings.load_factor;
        add_shifted(u.disp, shift, P, h.disp);
        add_shifted(u.acc, shift, P, h.acc);
        if (h.rail_disp.size()) add_shifted(u.rail_disp, shift, P, h.rail_disp);
      }
    }
    apply_filter(r, settings);
    r.summary = unit_run.summary;
    r.summary.n_steps = r.t.size() - 1;
    r.summary.t_reached = r.t[r.t.size() - 1];
    r.summary.stop_reason = "composed from a unit-axle run";
    r.summary.wall_s = unit_wall + std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<StationPeaks> peaks(const RunResult& r) {
  std::vector<StationPeaks> out;
  for (const auto& h : r.stations) {
    StationPeaks p;
    const Vector& disp = h.disp;
    // A filtered acceleration is band-limited and well sampled: its maximum between samples is
    // taken (parabolic vertex), so that it does not depend on where the samples fall (up to
    // 1 − cos(π f dt): 0.6 % for 35 Hz at 1 ms). Raw accelerations are not band-limited.
    p.max_abs_acc = h.acc_filt.size() > 0 ? signal::max_abs_between_samples(h.acc_filt)
                                          : (h.acc.size() ? h.acc.cwiseAbs().maxCoeff() : 0.0);
    p.max_abs_disp = disp.size() ? disp.cwiseAbs().maxCoeff() : 0.0;
    out.push_back(p);
  }
  return out;
}

const char* response_name(ResponseKind k) {
  return k == ResponseKind::acceleration ? "acc" : k == ResponseKind::deflection ? "disp" : k == ResponseKind::velocity ? "vel" : "strain";
}

const char* response_unit(ResponseKind k) {
  return k == ResponseKind::acceleration ? "mps2" : k == ResponseKind::deflection ? "m" : k == ResponseKind::velocity ? "mps" : "ue";
}

Vector station_response(const RunResult& r, std::size_t station, ResponseKind k) {
  VIADUCT_ASSERT(station < r.stations.size());
  const StationHistory& h = r.stations[station];
  if (k == ResponseKind::acceleration) return h.acc;
  if (k == ResponseKind::deflection) return h.disp;
  if (k == ResponseKind::velocity) {  // from rest at t = 0: the trapezoidal rule is Newmark's own with gamma = 1/2
    Vector v = Vector::Zero(h.acc.size());
    for (Index i = 1; i < v.size(); ++i) v[i] = v[i - 1] + 0.5 * (r.t[i] - r.t[i - 1]) * (h.acc[i] + h.acc[i - 1]);
    return v;
  }
  for (const auto& e : r.effects)
    if (e.name == h.name + "_strain_ue") return e.value;
  throw SolverError("no strain history for station " + h.name + " (it needs stations[].fibre_m and a model with load effects)");
}

FilterSpec filter_for(const FilterSpec& scenario_filter, ResponseKind k) {
  FilterSpec f = scenario_filter;
  if (quasi_static_kind(k)) f.cheby.band = signal::BandType::lowpass;
  return f;
}

std::vector<std::string> quantity_names(const PreparedModel& m) {
  std::vector<std::string> out;
  for (const auto& st : m.stations)
    if (st.has_deck) out.push_back(st.name + "_disp_m");
  for (const auto& e : m.effects) out.push_back(e.name);
  return out;
}

std::vector<EffectPeak> quantity_peaks(const PreparedModel& m, const RunResult& r) {
  auto extremes = [](const Vector& y) {
    return y.size() ? EffectPeak{y.maxCoeff(), y.minCoeff()} : EffectPeak{};
  };
  std::vector<EffectPeak> out;
  for (std::size_t i = 0; i < m.stations.size() && i < r.stations.size(); ++i)
    if (m.stations[i].has_deck) out.push_back(extremes(r.stations[i].disp));
  for (const auto& e : r.effects) out.push_back(extremes(e.value));
  return out;
}

solve::IntegrationSettings RunSettings::integration() const {
  solve::IntegrationSettings s;
  s.method = method;
  s.dt = dt;
  s.newmark = newmark;
  s.ida = ida;
  return s;
}

namespace {

// A rigid bearing's force without a track: axles on its own elements load its fixed DOF
// directly (bearing_load), a part no functional of the response holds.
bool has_direct_load(const model::Structure& s, const LoadEffect& e) {
  return e.bearing >= 0 && !s.has_track && s.bearings[static_cast<std::size_t>(e.bearing)].rigid;
}

// A bearing force's direct load on the path's elements, as fold_train's per-element cubics in ξ
// (channel `ch` of `nc` in `elem`): the Hermite shape of its fixed DOF on each of its elements.
void add_direct_load_channel(const model::BearingForce& bf, const ModalPathTable& T, std::size_t nc, std::size_t ch,
                             std::vector<double>& elem) {
  for (const auto& be : bf.elements) {
    std::size_t e = 0;
    while (e < T.x0.size() && !(T.x0[e] == be.element.x0 && T.h[e] == be.element.h)) ++e;
    if (e == T.x0.size()) throw std::logic_error("fold_train: a bearing's element is not on the load path");
    // N1(ξ) = 1 − 3ξ² + 2ξ³ (w0, fixed_local 0) or N3(ξ) = 3ξ² − 2ξ³ (w1, fixed_local 2).
    const double sign = be.fixed_local == 0 ? 1.0 : -1.0;
    double* out = &elem[(e * nc + ch) * 4];
    out[0] += be.fixed_local == 0 ? 1.0 : 0.0;
    out[2] += -3.0 * sign;
    out[3] += 2.0 * sign;
  }
}

}  // namespace

bool folds_trains(const PreparedModel& m, const RunSettings& s) {
  return solve::method_traits(s.method).needs_reduction && s.superposition == Superposition::direct && s.vehicle.model == VehicleModel::forces &&
         m.modal && m.modal_path;
}

// Pieces a TrainFold chunk writes: 32 of 359 channels' 4 powers (Old Guadiana with track) are
// 368 KB, written by every axle on the path in turn, so a chunk stays in the core's cache.
constexpr std::size_t kFoldChunk = 32;

struct TrainFold::Plan {
  const ModalPathTable* T = nullptr;
  std::vector<double> offset, load;  // the train's axles: offset [m], load × load_factor [N]
  std::size_t nc = 0, ne = 0, n_pieces = 0;
  std::vector<double> elem;  // per element and channel, the cubic in ξ (constructor)
  // Per axle and element, the pieces [first, second) the axle crosses the element in.
  std::vector<std::pair<std::size_t, std::size_t>> range;
  std::shared_ptr<solve::MovingChannels> t;
  // Head position where axle k leaves element e (elem_end in the constructor).
  double elem_end(std::size_t k, std::size_t e) const { return offset[k] + (e + 1 < ne ? T->x0[e + 1] : T->x_end); }
};

TrainFold::TrainFold(const PreparedModel& m, const load::Train& train, double load_factor) : p_(std::make_unique<Plan>()) {
  if (!m.modal || !m.modal_path) throw InputError("folding a train needs a model prepared for the modal method");
  require_positive(load_factor, "train.load_factor");
  train.validate();
  Plan& P = *p_;
  const ModalPathTable& T = *m.modal_path;
  const solve::ModalReduction& r = *m.modal;
  P.T = &T;
  P.offset = train.offset;
  for (double l : train.load) P.load.push_back(l * load_factor);
  std::vector<int> direct;  // the bearings whose direct load is an extra channel, in the effects' order
  for (const LoadEffect& e : m.effects)
    if (has_direct_load(m.structure, e)) direct.push_back(e.bearing);
  const std::size_t nm = T.m, no = T.flex ? T.n_out : 0, nx = direct.size(), nc = nm + no + nx, ne = T.x0.size();
  P.nc = nc, P.ne = ne;

  // Per element and channel, the cubic in ξ: the load channels as tabulated, and the residual
  // flexibility of each output, g_j − Σᵢ Wⱼᵢ pᵢ (W p: the kept coordinates' static share, S Ω⁻² φ
  // for classical modes): what the static correction adds to the coordinates' deflection (and,
  // times v² and differentiated twice, to their acceleration).
  std::vector<double>& elem = P.elem;
  elem.assign(ne * nc * 4, 0.0);
  const Matrix Ss = r.static_channel_weights();  // n_outputs × load channels
  for (std::size_t e = 0; e < ne; ++e) {
    const double* ce = &T.coef[e * T.stride];
    double* out = &elem[e * nc * 4];
    for (std::size_t i = 0; i < nm; ++i)
      for (std::size_t p = 0; p < 4; ++p) out[4 * i + p] = ce[4 * i + p];
    for (std::size_t j = 0; j < no; ++j)
      for (std::size_t p = 0; p < 4; ++p) {
        double v = ce[4 * (nm + j) + p];
        for (std::size_t i = 0; i < nm; ++i)
          v -= Ss(static_cast<Index>(j), static_cast<Index>(i)) * ce[4 * i + p];
        out[4 * (nm + j) + p] = v;
      }
  }
  for (std::size_t x = 0; x < nx; ++x)
    add_direct_load_channel(m.structure.bearings[static_cast<std::size_t>(direct[x])], T, nc, nm + no + x, elem);

  auto t = std::make_shared<solve::MovingChannels>();
  t->n_modes = nm;
  t->n_outputs = no;
  t->n_extra = nx;
  t->n_channels = nc;
  t->length = train.length();
  t->x_start = T.x_start;
  t->x_end = T.x_end;
  // Breakpoints: every axle at every element boundary and at the path's end. The very numbers
  // used as element limits (elem_end, fill) are inserted, so the lookups find them exactly.
  std::vector<double>& B = t->breaks;
  B.reserve(P.offset.size() * (ne + 1));
  for (std::size_t k = 0; k < P.offset.size(); ++k) {
    for (std::size_t e = 0; e < ne; ++e) B.push_back(P.offset[k] + T.x0[e]);
    B.push_back(P.elem_end(k, ne - 1));
  }
  std::sort(B.begin(), B.end());
  B.erase(std::unique(B.begin(), B.end()), B.end());
  const std::size_t n_pieces = B.size() - 1;
  P.n_pieces = n_pieces;
  // The first axle (offset 0, Train::validate) enters at the path's start: no piece before it.
  if (B.front() != T.x_start) throw InputError("train '" + train.name + "': the first axle must have offset 0");
  if (static_cast<double>(n_pieces) * static_cast<double>(4 * nc) * sizeof(double) > kMaxHistoryBytes)
    throw InputError("train '" + train.name + "' folded over " + std::to_string(nc) +
                     " modal channels would not fit in memory: lower modal.max_frequency_hz or modal.n_modes");
  t->coef.resize((n_pieces + 1) * 4 * nc);  // not zeroed: fill() zeroes each chunk's pieces, the last the block after
  t->residual_bounds.resize(2 * n_pieces * t->n_outputs);  // each chunk's by fill()
  // An axle exactly at the path's end is still on its last element (bearing_load's rule): the
  // extra channels' value there, g(ξ = 1), at that break only.
  t->point.assign(nx ? (n_pieces + 1) * nx : 0, 0.0);
  for (std::size_t k = 0; k < P.offset.size() && nx; ++k) {
    const auto i = static_cast<std::size_t>(std::lower_bound(B.begin(), B.end(), P.elem_end(k, ne - 1)) - B.begin());
    for (std::size_t x = 0; x < nx; ++x) {
      const double* a = &elem[((ne - 1) * nc + nm + no + x) * 4];
      t->point[i * nx + x] += P.load[k] * (a[0] + a[1] + a[2] + a[3]);
    }
  }
  P.range.reserve(P.offset.size() * ne);
  for (std::size_t k = 0; k < P.offset.size(); ++k)
    for (std::size_t e = 0; e < ne; ++e) {
      const auto i0 = static_cast<std::size_t>(std::lower_bound(B.begin(), B.end(), P.offset[k] + T.x0[e]) - B.begin());
      const auto i1 = static_cast<std::size_t>(std::lower_bound(B.begin(), B.end(), P.elem_end(k, e)) - B.begin());
      P.range.emplace_back(std::min(i0, n_pieces), std::min(i1, n_pieces));
    }
  P.t = std::move(t);
}

TrainFold::~TrainFold() = default;

std::size_t TrainFold::n_chunks() const { return std::max<std::size_t>(1, (p_->n_pieces + kFoldChunk - 1) / kFoldChunk); }

void TrainFold::fill(std::size_t chunk) noexcept {
  const Plan& P = *p_;
  const ModalPathTable& T = *P.T;
  const std::size_t nc = P.nc, ne = P.ne, p0 = chunk * kFoldChunk, p1 = std::min(P.n_pieces, p0 + kFoldChunk);
  const std::vector<double>& B = P.t->breaks;
  double* coef = P.t->coef.data();
  const std::size_t zero_to = chunk + 1 == n_chunks() ? P.n_pieces + 1 : p1;  // the last: the block beyond the last break
  std::fill(coef + p0 * 4 * nc, coef + zero_to * 4 * nc, 0.0);
  // Every axle's share of the chunk's pieces, the axles and elements in the same order for every
  // piece whichever chunk it is in: the same sums as folding the table in one pass.
  for (std::size_t k = 0; k < P.offset.size(); ++k) {
    const double o = P.offset[k], Pk = P.load[k];
    for (std::size_t e = 0; e < ne; ++e) {
      const auto [i0, i1] = P.range[k * ne + e];
      if (i1 <= p0 || i0 >= p1) continue;
      const double lo = o + T.x0[e], w = T.inv_h[e];
      const double* c = &P.elem[e * nc * 4];
      for (std::size_t i = std::max(i0, p0); i < std::min(i1, p1); ++i) {
        // ξ = ξa + w s: the element cubic re-expanded in powers of s.
        const double xa = (B[i] - lo) * w;
        double* d = coef + i * 4 * nc;
        for (std::size_t ch = 0; ch < nc; ++ch) {
          const double* a = c + 4 * ch;
          d[ch] += Pk * (a[0] + xa * (a[1] + xa * (a[2] + xa * a[3])));
          d[nc + ch] += Pk * w * (a[1] + xa * (2.0 * a[2] + 3.0 * xa * a[3]));
          d[2 * nc + ch] += Pk * w * w * (a[2] + 3.0 * xa * a[3]);
          d[3 * nc + ch] += Pk * w * w * w * a[3];
        }
      }
    }
  }
  solve::bound_residuals(*P.t, p0, p1);
}

std::shared_ptr<const solve::MovingChannels> TrainFold::table() const { return p_->t; }

std::shared_ptr<const solve::MovingChannels> fold_train(const PreparedModel& m, const load::Train& train,
                                                        double load_factor) {
  TrainFold f(m, train, load_factor);
  for (std::size_t c = 0; c < f.n_chunks(); ++c) f.fill(c);
  return f.table();
}

std::vector<CasePeaks> simulate_peaks(const PreparedModel& m, const load::Train& train, const std::vector<double>& speeds,
                                      const RunSettings& settings, const solve::MovingChannels* folded) {
  std::vector<CasePeaks> out;
  if (!folded) {
    for (const RunResult& r : simulate_batch(m, train, speeds, settings)) {
      CasePeaks p{peaks(r), {}, r.summary.n_steps, r.summary.wall_s, vehicle_peaks(r)};
      if (!m.effects.empty()) p.quantities = quantity_peaks(m, r);
      out.push_back(std::move(p));
    }
    return out;
  }
  if (!folds_trains(m, settings)) throw InputError("the peaks kernel needs the modal method with direct superposition");
  if (folded->x_start != m.structure.path_start() || folded->x_end != m.structure.path_end())
    throw InputError("the folded train belongs to another model");
  require_non_negative(settings.free_vibration_s, "free_vibration_s [s]");
  require_positive(settings.dt, "analysis.dt [s]");
  // Only the stations' peaks and the load effects' signed extremes: no history but the
  // accelerations the filter takes. The outputs as the model holds them (make_modal): stations,
  // then each effect's functional with its inertia and damping parts; a bearing force with such
  // parts or a direct load is a sum of them, tracked by the kernel.
  const OutputMap map = output_map(m.stations, false, m.effects);
  const std::vector<solve::Functional>& outputs = map.outputs;
  const std::vector<std::string>& names = map.names;
  const std::size_t n_st = m.stations.size();
  if (outputs.size() != static_cast<std::size_t>(m.modal->n_outputs()))
    throw InputError("the peaks kernel needs a modal model prepared without rail outputs");
  solve::Recording rec;
  std::vector<Index> sum_of(m.effects.size(), -1);
  Index n_direct = 0;
  for (std::size_t e = 0; e < m.effects.size(); ++e) {
    const OutputMap::Effect& col = map.effects[e];
    const bool direct = has_direct_load(m.structure, m.effects[e]);
    if (col.inertia < 0 && col.damping < 0 && !direct) continue;
    sum_of[e] = static_cast<Index>(rec.sums.size());
    rec.sums.push_back({col.value, col.inertia, col.damping, direct ? n_direct++ : -1});
  }
  if (static_cast<std::size_t>(n_direct) != folded->n_extra) throw InputError("the folded train belongs to another model");
  const auto integrator = solve::make_integrator(settings.integration(), outputs, m.modal);
  const solve::DivergenceBound bound =
      divergence_bound(guard_influence_maxima(m, outputs), names, train, settings.load_factor);
  std::vector<solve::LoadCase> cases;
  for (double v : speeds) {
    require_positive(v, "speed [m/s]");
    solve::LoadCase c;
    c.moving = folded;
    c.speed = v;
    // The duration of simulate(): until free_vibration_s after the last axle leaves the path.
    c.t_end = folded->t_exit(v) + settings.free_vibration_s;
    c.bound = &bound;
    cases.push_back(c);
  }
  rec.disp_history = false;
  rec.acc_history = settings.filter.enabled;
  rec.acc_outputs = static_cast<Index>(n_st);  // the filter takes the stations' accelerations only
  rec.max_history_bytes = kMaxHistoryBytes;
  const std::vector<solve::CaseResult> res = integrator->run_batch(cases, rec);
  std::optional<signal::FiltfiltFromRest> filt;  // one filter for every case and station
  if (settings.filter.enabled) filt.emplace(signal::cheby1(settings.filter.cheby, 1.0 / settings.dt));
  // With a filter the maxima are taken after it, on the recorded accelerations: each station's
  // records of every case filtered together (four at a time: 8 % of the 31-station sweep of
  // docs/benchmarks.md was this filter, one record after another).
  std::vector<std::vector<double>> filtered_max(n_st);
  for (std::size_t j = 0; j < n_st && filt; ++j) {
    std::vector<Vector> recs;
    recs.reserve(res.size());
    for (const solve::CaseResult& r : res) recs.emplace_back(r.acc.col(static_cast<Index>(j)));
    for (const Vector& y : (*filt)(recs)) filtered_max[j].push_back(signal::max_abs_between_samples(y));
  }
  for (std::size_t c = 0; c < res.size(); ++c) {
    const solve::CaseResult& r = res[c];
    CasePeaks p;
    for (Index j = 0; j < static_cast<Index>(n_st); ++j) {
      StationPeaks sp;
      sp.max_abs_disp = r.max_abs_disp[j];
      sp.max_abs_acc = filt ? filtered_max[static_cast<std::size_t>(j)][c] : r.max_abs_acc[j];
      p.peaks.push_back(sp);
    }
    if (!m.effects.empty()) {  // quantity_peaks' order: deck stations' deflections, then the effects
      for (std::size_t j = 0; j < n_st; ++j)
        if (m.stations[j].has_deck) p.quantities.push_back({r.max_disp[static_cast<Index>(j)], r.min_disp[static_cast<Index>(j)]});
      for (std::size_t e = 0; e < m.effects.size(); ++e) {
        const Index k = map.effects[e].value, su = sum_of[e];
        p.quantities.push_back(su >= 0 ? EffectPeak{r.max_sum[su], r.min_sum[su]} : EffectPeak{r.max_disp[k], r.min_disp[k]});
      }
    }
    p.n_steps = r.summary.n_steps;
    p.wall_s = r.summary.wall_s;
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace viaduct::study
