#include "viaduct/study/vehicles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/model/beam_element.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/signal/iir.hpp"
#include "divergence.hpp"
#include "viaduct/solve/integrator.hpp"

namespace viaduct::study {

const char* vehicle_model_name(VehicleModel m) {
  switch (m) {
    case VehicleModel::forces: return "forces";
    case VehicleModel::sprung: return "sprung";
    case VehicleModel::multibody: return "multibody";
  }
  return "?";
}

double VehicleHistory::max_unloading_ratio() const {
  double r = 0.0;
  for (Index k = 0; k < static_load.size() && k < min_contact.size(); ++k)
    r = std::max(r, (static_load[k] - min_contact[k]) / static_load[k]);
  return r;
}

VehiclePeaks vehicle_peaks(const RunResult& r) {
  VehiclePeaks p;
  const VehicleHistory& v = r.vehicles;
  if (v.empty()) return p;
  p.present = true;
  p.min_contact = v.min_contact.minCoeff();
  p.max_contact = v.max_contact.maxCoeff();
  p.max_unloading_ratio = v.max_unloading_ratio();
  p.max_airborne_s = v.airborne_s.size() > 0 ? v.airborne_s.maxCoeff() : 0.0;
  p.contact_lost = v.contact_lost();
  for (Index b = 0; b < v.body_acc.cols(); ++b) {
    const double a = v.body_acc.col(b).cwiseAbs().maxCoeff();
    if (a > p.max_body_acc) p.max_body_acc = a, p.body = v.body_names[static_cast<std::size_t>(b)];
    if (b < v.max_floor_acc.size() && v.max_floor_acc[b] > p.max_floor_acc)
      p.max_floor_acc = v.max_floor_acc[b], p.floor_body = v.body_names[static_cast<std::size_t>(b)];
  }
  return p;
}

std::vector<solve::Functional> vehicle_outputs(const std::vector<ResolvedStation>& stations,
                                               const std::vector<LoadEffect>& effects) {
  std::vector<solve::Functional> out;
  for (const auto& stn : stations) out.push_back(functional_of(stn.has_deck ? stn.deck : stn.rail));
  for (const auto& stn : stations)
    out.push_back(stn.has_deck && stn.has_rail ? functional_of(stn.rail) : solve::Functional{});
  for (const auto& e : effects) out.push_back(e.functional);
  return out;
}

bool vehicles_on_modes(const RunSettings& s) {
  return solve::method_traits(s.method).coupled == solve::Coordinates::modal;
}

std::shared_ptr<const solve::ModalReduction> vehicle_reduction(const model::Structure& s, const ModalSettings& ms,
                                                               const std::vector<solve::Functional>& outputs,
                                                               Vector* kept_hz) {
  const model::Modes modes = kept_modes(s, ms);
  const Index m = modes.frequency_hz.size();
  // The DOFs the wheels may touch: the load path's, each once.
  std::vector<Index> path;
  std::vector<bool> seen(static_cast<std::size_t>(s.K.rows()), false);
  for (const model::PathElement& e : s.load_path())
    for (const Index d : e.dofs)
      if (d >= 0 && !seen[static_cast<std::size_t>(d)]) {
        seen[static_cast<std::size_t>(d)] = true;
        path.push_back(d);
      }
  if (ms.static_correction && static_cast<Index>(path.size()) > kMaxResidualPathDofs)
    throw InputError("modal.static_correction = true: the vehicle fast path's correction stores the flexibility between the "
                     "load path's " + std::to_string(path.size()) + " DOFs, more than the " +
                     std::to_string(kMaxResidualPathDofs) +
                     " it takes (set modal.static_correction = false, or use analysis.method = \"newmark\")");
  if (kept_hz) *kept_hz = modes.frequency_hz.head(m);
  // The reduction mass-normalises the shapes.
  return std::make_shared<const solve::ModalReduction>(s.M, s.C, s.K, Matrix(modes.shape.leftCols(m)),
                                                       Vector((2.0 * M_PI) * modes.frequency_hz.head(m)), outputs,
                                                       ms.static_correction, path);
}

solve::LinearVehicle linear_vehicle(const load::Train& train, const RunSettings& s, load::TrainVehicles* detail) {
  const VehicleSettings& vs = s.vehicle;
  load::TrainVehicles tv;
  switch (vs.model) {
    case VehicleModel::forces:
      throw InputError("linear_vehicle: train.vehicle = \"forces\" has no vehicle model");
    case VehicleModel::sprung:
      if (vs.sprung) tv = load::sprung_vehicles(train, *vs.sprung, vs.gravity);
      else if (!train.coaches.empty()) {
        // Coaches of one kind share the reduction (a train of mixed coaches needs the keys).
        const load::SprungSpec sp = load::sprung_of(train.coaches.front());
        for (const auto& c : train.coaches)
          if (c.wheelset_mass != sp.unsprung_mass || c.primary_k != train.coaches.front().primary_k ||
              c.secondary_k != train.coaches.front().secondary_k)
            throw InputError("train '" + train.name + "': coaches differ; give train.unsprung_mass_kg and train.suspension_stiffness_N_m");
        tv = load::sprung_vehicles(train, sp, vs.gravity);
      } else
        throw InputError("train '" + train.name + "' is a list of axles: sprung masses need train.unsprung_mass_kg and "
                         "train.suspension_stiffness_N_m");
      break;
    case VehicleModel::multibody: tv = load::multibody_vehicles(train); break;
  }
  require_positive(s.load_factor, "train.load_factor");
  solve::LinearVehicle v;
  v.M = s.load_factor * tv.M;
  v.C = s.load_factor * tv.C;
  v.K = s.load_factor * tv.K;
  v.wheel_dof = tv.wheel_dof;
  v.release = vs.release;
  const Index na = static_cast<Index>(train.n_axles());
  v.static_load.resize(na);
  v.contact_stiffness.resize(na);
  for (Index k = 0; k < na; ++k) {
    const double P = train.load[static_cast<std::size_t>(k)];
    v.static_load[k] = s.load_factor * P;
    if (vs.contact == ContactModel::rigid) v.contact_stiffness[k] = std::numeric_limits<double>::infinity();
    else v.contact_stiffness[k] = s.load_factor * (vs.contact_stiffness > 0.0 ? vs.contact_stiffness : hertz_stiffness(P, vs.wheel_radius));
  }
  std::string why;
  if (!v.is_valid(&why)) throw InputError("train '" + train.name + "': " + why);
  if (detail) *detail = std::move(tv);
  return v;
}

std::shared_ptr<const load::RailProfile> rail_profile(const model::Structure& s, const IrregularitySettings& irr) {
  if (!irr.enabled()) return nullptr;
  require_non_negative(irr.taper, "irregularity.taper_m [m]");
  require_non_negative(irr.run_in, "irregularity.run_in_m [m]");
  const double x0 = s.path_start() - irr.run_in, x1 = s.path_end() + irr.taper;
  if (irr.measured) {
    const load::RailProfile& p = *irr.measured;
    if (p.x0 > x0 || p.end() < x1)
      throw InputError("irregularity.profile covers x = " + format_number(p.x0, 6) + " to " + format_number(p.end(), 6) +
                       " m; the run needs " + format_number(x0, 6) + " to " + format_number(x1, 6) +
                       " m (irregularity.run_in_m before the load path, the path, and irregularity.taper_m past its end)");
    return irr.measured;
  }
  load::ProfileSpec spec;
  spec.spectrum = load::irregularity_spectrum(irr.spectrum);
  spec.lambda_min = irr.lambda_min;
  spec.lambda_max = irr.lambda_max;
  spec.dx = irr.dx;
  spec.seed = irr.seed;
  spec.x0 = x0;
  spec.length = std::max(x1 - x0, irr.lambda_max);
  std::string why;
  if (!spec.is_valid(&why)) throw InputError("irregularity: " + why);
  return std::make_shared<const load::RailProfile>(load::random_profile(spec));
}

namespace {

solve::Functional project(const solve::Functional& f, const Matrix* phi) {
  if (!phi) return f;
  solve::Functional p;
  for (Index j = 0; j < phi->cols(); ++j) {
    double s = 0.0;
    for (std::size_t q = 0; q < f.dof.size(); ++q) s += f.weight[q] * (*phi)(f.dof[q], j);
    p.dof.push_back(j);
    p.weight.push_back(s);
  }
  return p;
}

double apply(const solve::Functional& f, const Vector& x) {
  double y = 0.0;
  for (std::size_t q = 0; q < f.dof.size(); ++q) y += f.weight[q] * x[f.dof[q]];
  return y;
}

// The static correction's share of each displacement output of a run (vehicle_outputs() order):
// the contact forces P through the dropped modes' flexibility from the rail under each wheel.
class OutputCorrection {
 public:
  // `r` null or without the correction: at() must not be called.
  OutputCorrection(const solve::ContactPath& full, const solve::ModalReduction* r, std::size_t n_wheels, std::size_t n_outputs)
      : full_(full), r_(r), nw_(n_wheels), corr_(Vector::Zero(static_cast<Index>(n_outputs))) {}
  const Vector& at(double t, const Vector& P) {
    corr_.setZero();
    double rw = 0.0;
    for (std::size_t w = 0; w < nw_; ++w) {
      full_.contact(w, t, d_, w_, rw);
      for (std::size_t q = 0; q < d_.size(); ++q)
        corr_.noalias() += (P[static_cast<Index>(w)] * w_[q]) * r_->contact_output_residual().row(r_->contact_slot(d_[q])).transpose();
    }
    return corr_;
  }

 private:
  const solve::ContactPath& full_;
  const solve::ModalReduction* r_;
  std::size_t nw_;
  Vector corr_;
  std::vector<Index> d_;
  std::vector<double> w_;
};

// [m/s²] per body: the largest |acceleration| of its floor at the centre and above the bogie
// centres (bounce ∓ arm × pitch), low-passed zero-phase from rest when
// st.vehicle.comfort_lowpass_hz > 0 (the filter's order and ripple); InputError when that
// frequency is not below Nyquist.
Vector floor_accelerations(const Matrix& bounce, const Matrix& pitch, const std::vector<double>& arm, const RunSettings& st) {
  const Index nb = bounce.cols();
  Vector out = Vector::Zero(nb);
  const double f = st.vehicle.comfort_lowpass_hz;
  require_non_negative(f, "train.comfort_lowpass_hz [Hz]");
  std::optional<signal::Sos> sos;
  if (f > 0.0) {
    signal::Cheby1Spec spec;
    spec.order = st.filter.cheby.order;
    spec.ripple_db = st.filter.cheby.ripple_db;
    spec.band = signal::BandType::lowpass;
    spec.high_hz = f;
    std::string why;
    if (!spec.is_valid(1.0 / st.dt, &why))
      throw InputError("train.comfort_lowpass_hz = " + format_number(f, 6) + " Hz at analysis.dt = " + format_number(st.dt, 6) +
                       " s: " + why);
    sos = signal::cheby1(spec, 1.0 / st.dt);
  }
  for (Index b = 0; b < nb; ++b) {
    const double h = arm[static_cast<std::size_t>(b)];
    for (const double side : {0.0, 1.0, -1.0}) {
      if (side != 0.0 && h == 0.0) continue;
      Vector a = bounce.col(b) + (side * h) * pitch.col(b);
      if (sos) a = signal::filtfilt_from_rest(*sos, a);
      out[b] = std::max(out[b], a.cwiseAbs().maxCoeff());
    }
  }
  return out;
}

// The divergence guard of a vehicle run: the stations' deflections and the load effects (`outs`,
// vehicle_outputs()' order) against their static values under the whole train, the contact forces
// against the static axle loads.
solve::DivergenceBound vehicle_bound(const PreparedModel& m, const std::vector<solve::Functional>& outs,
                                     const load::Train& train, double load_factor) {
  std::vector<std::string> names;
  for (const auto& stn : m.stations) names.push_back(stn.name + (stn.has_deck ? " deflection [m]" : " rail deflection [m]"));
  for (const auto& stn : m.stations) names.push_back(stn.name + " rail deflection [m]");
  for (const auto& e : m.effects) names.push_back(e.name);
  return divergence_bound(influence_maxima(m.structure, outs, m.statics.get()), names, train, load_factor, true);
}

// A vehicle run's result with its histories sized: the stations (the rail above a deck station
// when `rail` has its functional), the load effects, the contact forces and car-body accelerations.
RunResult vehicle_result(const PreparedModel& m, double speed, const RunSettings& st, Index n_samples,
                         const std::vector<solve::Functional>& rail, const solve::LinearVehicle& veh,
                         const load::TrainVehicles& tv) {
  RunResult r;
  r.speed = speed;
  r.method = st.method;
  r.t.resize(n_samples);
  for (Index k = 0; k < n_samples; ++k) r.t[k] = static_cast<double>(k) * st.dt;
  for (std::size_t i = 0; i < m.stations.size(); ++i) {
    StationHistory h;
    h.name = m.stations[i].name;
    h.on_deck = m.stations[i].has_deck;
    h.disp.resize(n_samples);
    h.acc.resize(n_samples);
    if (!rail[i].dof.empty()) h.rail_disp.resize(n_samples);
    r.stations.push_back(std::move(h));
  }
  for (const auto& e : m.effects) r.effects.push_back({e.name, Vector(n_samples)});
  VehicleHistory& vh = r.vehicles;
  vh.model = vehicle_model_name(st.vehicle.model);
  vh.static_load = veh.static_load;
  vh.contact_stiffness = veh.contact_stiffness;
  vh.contact_force.resize(n_samples, static_cast<Index>(veh.n_contacts()));
  vh.body_names = tv.body_names;
  vh.body_acc.resize(n_samples, static_cast<Index>(tv.body_dof.size()));
  vh.n_dofs = veh.n_dofs();
  return r;
}

// A rigid bearing's own element passes the contact forces on it straight to the bearing.
void add_bearing_loads(const PreparedModel& m, const load::Train& train, double speed, RunResult& r) {
  const model::Structure& s = m.structure;
  for (std::size_t j = 0; j < m.effects.size(); ++j) {
    if (m.effects[j].bearing < 0) continue;
    load::Train at = train;
    for (Index k = 0; k < r.t.size(); ++k) {
      for (std::size_t a = 0; a < train.n_axles(); ++a) at.load[a] = r.vehicles.contact_force(k, static_cast<Index>(a));
      r.effects[j].value[k] += bearing_load(s, m.effects[j], at, 1.0, s.path_start() + speed * r.t[k]);
    }
  }
}

}  // namespace

RunResult simulate_vehicles(const PreparedModel& m, const load::Train& train, double speed, const RunSettings& st) {
  require_positive(speed, "speed [m/s]");
  require_non_negative(st.free_vibration_s, "free_vibration_s [s]");
  require_positive(st.dt, "analysis.dt [s]");
  const model::Structure& s = m.structure;
  load::TrainVehicles tv;
  const solve::LinearVehicle veh = linear_vehicle(train, st, &tv);
  // The integrator says in which coordinates it takes the structure: every DOF (newmark) or its
  // modes with the vehicles physical (the modal fast path, IDA).
  const auto integrator = solve::make_integrator(st.integration(), {});
  const bool modal = integrator->coupled_coordinates() == solve::Coordinates::modal;
  // The displacement outputs in vehicle_outputs()' order, the order of the static correction's.
  const std::vector<solve::Functional> outs = vehicle_outputs(m.stations, m.effects);
  std::shared_ptr<const solve::ModalReduction> basis = m.vehicle_modal;
  if (modal && !basis) basis = vehicle_reduction(s, st.modal, outs);
  const bool sc = modal && basis->static_correction();
  const Matrix* phi = modal ? &basis->shapes() : nullptr;

  const double t_end = (s.path_end() - s.path_start() + train.length()) / speed + st.free_vibration_s;
  const Index n_samples = solve::TimeGrid{st.dt, t_end}.n_steps() + 1;
  // With a profile the run starts a run-in earlier (a whole number of steps), unrecorded.
  const Index k0 = m.profile ? static_cast<Index>(std::ceil(st.irregularity.run_in / (speed * st.dt) - 1e-9)) : 0;
  require_transition(s, st.vehicle.end_transition);
  const solve::TimeGrid grid{st.dt, static_cast<double>(n_samples - 1 + k0) * st.dt};
  const std::size_t na = train.n_axles(), nb = tv.body_dof.size();
  const double bytes = static_cast<double>(n_samples) *
                       static_cast<double>(1 + 4 * m.stations.size() + 2 * m.effects.size() + na + 2 * nb) * sizeof(double);
  if (bytes > kMaxHistoryBytes)
    throw InputError("a run of " + format_number(t_end, 6) + " s at dt = " + format_number(st.dt, 6) + " s would record " +
                     format_number(bytes / (1 << 30), 3) + " GiB of histories: raise the speed or analysis.dt");

  // Outputs: each station's main point (and the rail above a deck station), the load effects.
  const std::size_t ns = m.stations.size();
  std::vector<solve::Functional> main, rail;
  for (std::size_t i = 0; i < ns; ++i) {
    main.push_back(project(outs[i], phi));
    rail.push_back(outs[ns + i].dof.empty() ? solve::Functional{} : project(outs[ns + i], phi));
  }
  struct Eff {
    solve::Functional f, inertia, damping;
  };
  std::vector<Eff> eff;
  for (std::size_t j = 0; j < m.effects.size(); ++j)
    eff.push_back({project(outs[2 * ns + j], phi), project(m.effects[j].inertia, phi), project(m.effects[j].damping, phi)});

  RunResult r = vehicle_result(m, speed, st, n_samples, rail, veh, tv);
  VehicleHistory& vh = r.vehicles;

  const std::unique_ptr<solve::ContactPath> full_path = train_contacts(
      s, train, speed, m.profile.get(), st.irregularity.run_in, st.irregularity.taper, static_cast<double>(k0) * st.dt,
      st.vehicle.end_transition);
  const solve::ContactPath& full = *full_path;
  OutputCorrection correction(full, basis.get(), na, outs.size());
  const solve::DivergenceBound bound = vehicle_bound(m, outs, train, st.load_factor);
  const std::string cause = "the wheel-rail contact (train.contact) or the time integration at analysis.dt = " +
                            format_number(st.dt, 6) + " s";
  Matrix pitch_acc(n_samples, static_cast<Index>(nb));  // [rad/s²] the bodies' pitch
  auto observe = [&](Index step, double t, const solve::CoupledState& x) {
    if (step < k0) return;
    const Index k = step - k0;
    for (std::size_t i = 0; i < main.size(); ++i) {
      r.stations[i].disp[k] = apply(main[i], x.u);
      r.stations[i].acc[k] = apply(main[i], x.a);
      if (!rail[i].dof.empty()) r.stations[i].rail_disp[k] = apply(rail[i], x.u);
    }
    for (std::size_t j = 0; j < eff.size(); ++j)
      r.effects[j].value[k] = apply(eff[j].f, x.u) + apply(eff[j].inertia, x.a) + apply(eff[j].damping, x.v);
    if (sc) {  // accelerations keep the kept modes' (the correction's would need the forces' second derivative)
      const Vector& corr = correction.at(t, x.contact_force);
      for (std::size_t i = 0; i < main.size(); ++i) {
        r.stations[i].disp[k] += corr[static_cast<Index>(i)];
        if (!rail[i].dof.empty()) r.stations[i].rail_disp[k] += corr[static_cast<Index>(ns + i)];
      }
      for (std::size_t j = 0; j < eff.size(); ++j) r.effects[j].value[k] += corr[static_cast<Index>(2 * ns + j)];
    }
    for (std::size_t i = 0; i < ns; ++i) {
      solve::check_output(bound, static_cast<Index>(i), r.stations[i].disp[k], t, cause);
      if (!rail[i].dof.empty()) solve::check_output(bound, static_cast<Index>(ns + i), r.stations[i].rail_disp[k], t, cause);
    }
    vh.contact_force.row(k) = x.contact_force.transpose();
    for (std::size_t b = 0; b < nb; ++b) {
      vh.body_acc(k, static_cast<Index>(b)) = x.za[tv.body_dof[b]];
      pitch_acc(k, static_cast<Index>(b)) = tv.body_pitch_dof[b] >= 0 ? x.za[tv.body_pitch_dof[b]] : 0.0;
    }
  };
  const std::unique_ptr<solve::ContactPath> mc = modal ? solve::modal_contacts(full, *basis, na) : nullptr;
  solve::CoupledCase cc;
  cc.M = modal ? &basis->coupled_matrices().M : &s.M;
  cc.C = modal ? &basis->coupled_matrices().C : &s.C;
  cc.K = modal ? &basis->coupled_matrices().K : &s.K;
  cc.vehicle = &veh;
  cc.path = modal ? mc.get() : &full;
  cc.grid = grid;
  cc.observe = observe;
  cc.bound = &bound;
  solve::CoupledSummary cs = integrator->run_coupled(cc);
  if (modal) {
    cs.summary.n_modes = basis->n_modes();
    r.n_modes = cs.summary.n_modes;
  }
  r.summary = cs.summary;
  vh.min_contact = cs.min_contact_force;
  vh.max_contact = cs.max_contact_force;
  vh.n_cached_columns = cs.n_cached_columns;
  vh.released = veh.release;
  vh.airborne_s = cs.airborne_s;
  vh.max_floor_acc = floor_accelerations(vh.body_acc, pitch_acc, tv.body_arm, st);
  vh.first_loss_s = Vector::Constant(static_cast<Index>(na), std::numeric_limits<double>::quiet_NaN());
  for (const solve::ContactEvent& e : cs.events)
    if (!e.landed && std::isnan(vh.first_loss_s[static_cast<Index>(e.wheel)]))
      vh.first_loss_s[static_cast<Index>(e.wheel)] = e.t - static_cast<double>(k0) * st.dt;
  add_bearing_loads(m, train, speed, r);
  return r;
}

}  // namespace viaduct::study
