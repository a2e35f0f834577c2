#pragma once
/// \file The engine of every study: one train at one speed (or one batch of speeds) over one
/// structure, integrated by the solve::Integrator that the settings choose; station time
/// histories or only their peaks. Workflows (sweep, trade-off, compare, fit, forced tests) call
/// these and never a kernel.

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "viaduct/load/moving_loads.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::study {

/// The bridge–track structure under a train's moving loads, as the integrators see it.
class MovingLoadSystem : public solve::SecondOrderSystem {
 public:
  /// `s` must outlive this object.
  MovingLoadSystem(const model::Structure& s, const load::MovingLoads& loads)
      : s_(s), loads_(loads) {}
  const SparseMatrix& mass() const override { return s_.M; }
  const SparseMatrix& damping() const override { return s_.C; }
  const SparseMatrix& stiffness() const override { return s_.K; }
  void force(double t, Vector& f) const override {
    f.setZero();
    loads_.add_to(t, f);
  }
  std::vector<double> discontinuities(double t_end) const override {
    std::vector<double> t = loads_.event_times();
    while (!t.empty() && t.back() >= t_end) t.pop_back();
    return t;
  }
  bool force_entries(double t, SparseForce& out) const override {
    loads_.entries(t, out);
    return true;
  }

 private:
  const model::Structure& s_;
  const load::MovingLoads& loads_;
};

/// A station mapped onto the structure's DOFs.
struct ResolvedStation {
  std::string name;
  bool has_deck = false;
  bool has_rail = false;
  model::PointCoupling deck;
  model::PointCoupling rail;
};

/// Maps station specs onto the structure (deck stations also record the rail above them when
/// the structure has a track). Throws InputError for stations outside the model.
std::vector<ResolvedStation> resolve_stations(const model::Structure& s,
                                              const std::vector<StationSpec>& specs);

/// A load effect, linear in the state: y = functional·u + inertia·a + damping·v (+ the axle loads
/// on a rigid bearing's element when the loads act on the deck). A bending moment, strain or
/// rotation has only `functional`; a bearing force all three. Its name carries its unit
/// (S1_mid_moment_Nm). v is the trapezoidal integral of the recorded damping·a from rest (exact
/// for Newmark's average acceleration).
struct LoadEffect {
  std::string name;
  solve::Functional functional;
  solve::Functional inertia{};
  solve::Functional damping{};
  int bearing = -1;  ///< index into Structure::bearings for a bearing force
};

/// The deflection at a point (its interpolation) as a recorded functional.
solve::Functional functional_of(const model::PointCoupling& c);

/// The load effects of a model: at each deck station its bending moment (sagging positive) and,
/// with a fibre distance, the strain M·y/EI there [µε, tension positive; y positive below the
/// neutral axis], then its shear force V = dM/dx [N]; at each span's start and end the deck rotation dw/dx [rad] and the bearing
/// force [N, compression positive] (model::BearingForce; traffic only, without the permanent
/// load).
/// `along`: stations of load effects only (Scenario::effect_stations), each giving first its
/// deflection (<name>_disp_m), then its moment, strain and shear; after the stations' effects.
std::vector<LoadEffect> load_effects(const model::Structure& s, const std::vector<StationSpec>& stations,
                                     const std::vector<StationSpec>& along = {});

/// The part of a bearing force that the axles put straight on a rigid bearing's fixed DOF (those
/// on its element; 0 for other effects, elastic bearings and loads on a track), with the first
/// axle at x_head [m] on the load path.
double bearing_load(const model::Structure& s, const LoadEffect& e, const load::Train& train, double load_factor,
                    double x_head);

/// Histories of one station. The main quantities are the deck's for deck stations and the
/// rail's for rail stations; rail_disp is the rail above a deck station (track models only).
struct StationHistory {
  std::string name;
  bool on_deck = true;
  Vector disp;       ///< [m] deflection, positive down
  Vector acc;        ///< [m/s²] acceleration, unfiltered
  Vector acc_filt;   ///< [m/s²] filtered as RunSettings::filter says (empty if disabled)
  Vector rail_disp;  ///< [m] rail deflection above a deck station (empty without track)
};

/// History of one load effect (unfiltered).
struct EffectHistory {
  std::string name;  ///< with its unit, as LoadEffect::name
  Vector value;
};

/// What the vehicles did in one run (sprung and multibody models; empty with moving forces).
struct VehicleHistory {
  std::string model;          ///< "sprung" or "multibody"; empty: moving forces
  Vector static_load;         ///< [N] per axle, × load_factor (P0)
  Vector contact_stiffness;   ///< [N/m] per axle as used (+inf: rigid contact)
  Matrix contact_force;       ///< [N] n_samples × n_axles, P0 + p, compression positive
  std::vector<std::string> body_names;  ///< "c1" … per coach, "a1" … per sprung axle
  Matrix body_acc;            ///< [m/s²] n_samples × n_bodies, car-body bounce (positive down)
  /// [m/s²] per body: the largest |acceleration| of its floor at the centre and above the bogie
  /// centres, max over time of |bounce| + arm·|pitch| (load::TrainVehicles::body_arm); unfiltered.
  Vector max_floor_acc;
  Vector min_contact, max_contact;  ///< [N] per axle over the run
  /// [s] per axle: time off the rail (unilateral contact), the run-in included; 0 without release.
  Vector airborne_s;
  /// [s] per axle: when it first left the rail, on the recorded time axis (NaN: never; the run-in
  /// before t = 0 gives negative times). IDA locates it by root finding, Newmark to its step.
  Vector first_loss_s;
  bool released = false;      ///< the contact was unilateral (VehicleSettings::release)
  Index n_dofs = 0;           ///< vehicle DOFs
  Index n_cached_columns = 0; ///< structure inverse columns the contacts needed (sparse solves)
  bool empty() const { return model.empty(); }
  /// True when some wheel left the rail (unilateral contact) or, with the linear contact, its
  /// force went below zero (the wheel would have lifted: the result past that time is not physical).
  bool contact_lost() const {
    return !empty() && ((airborne_s.size() > 0 && airborne_s.maxCoeff() > 0.0) ||
                        (min_contact.size() > 0 && min_contact.minCoeff() < 0.0));
  }
  /// Largest (P0 − P_min)/P0 over the axles (1: a wheel just unloaded; > 1: lifted).
  double max_unloading_ratio() const;
};

struct RunResult {
  Vector t;  ///< [s] sample times (every step, t = 0 included)
  std::vector<StationHistory> stations;
  std::vector<EffectHistory> effects;  ///< when the model was prepared with load effects
  solve::Summary summary;         ///< kernel, steps, counters, time reached, wall time (any method)
  VehicleHistory vehicles;        ///< sprung or multibody vehicles (empty with moving forces)
  double speed = 0.0;             ///< [m/s]
  Method method = Method::newmark;
  Index n_modes = 0;              ///< modes used (modal method)
};

/// Largest history one run may record [bytes] (every station at every step).
constexpr double kMaxHistoryBytes = 2.0 * (1 << 30);

/// Modal loads of a unit axle along the load path, tabulated per path element as cubics in the
/// element coordinate (built with the modal model; speed-independent).
struct ModalPathTable;
/// One factorisation of K (the divergence guard's static responses; src/study/divergence.hpp).
struct StaticFactor;
struct InfluenceMaximaCache;

/// Everything the cases of one model share, built once (per sweep variant).
struct PreparedModel {
  model::Structure structure;
  std::vector<ResolvedStation> stations;
  /// Modal model for the stations (Method::modal only).
  std::shared_ptr<const solve::ModalReduction> modal;
  std::shared_ptr<const ModalPathTable> modal_path;  ///< with `modal`
  Vector modal_frequency_hz;  ///< [Hz] frequencies of the modes kept (Method::modal only)
  bool modal_rails = true;    ///< the modal model's outputs include the rail above deck stations
  /// Recorded with the stations when prepared with load effects (modal: outputs of the reduction,
  /// with its static correction, i.e. the mode-acceleration method).
  std::vector<LoadEffect> effects;
  /// The rail profile vehicle models see (null: a smooth rail or moving forces).
  std::shared_ptr<const load::RailProfile> profile;
  /// The structure's modes for the coupled vehicle kernels (vehicle models with Method::modal or
  /// ida: vehicle_reduction() in study/vehicles.hpp).
  std::shared_ptr<const solve::ModalReduction> vehicle_modal;
  /// K factored once: the divergence guard's bounds of every case (solve/guard.hpp).
  std::shared_ptr<const StaticFactor> statics;
  /// The guard's influence maxima of the outputs the peaks path reads, kept by the first batch
  /// of cases that computes them for this structure and these outputs (they depend on nothing
  /// else: the trains and speeds of a sweep's jobs share them).
  std::shared_ptr<InfluenceMaximaCache> imax;
};

/// The divergence guard's influence maxima (max over load positions of |output per newton|) of
/// `outputs` on m's structure, kept in m.imax for the next call with the same outputs (a sweep's
/// jobs share them).
Vector guard_influence_maxima(const PreparedModel& m, const std::vector<solve::Functional>& outputs);

/// The structure's modes `ms` keeps (modal.n_modes, or those up to modal.max_frequency_hz): the
/// basis of the modal method with moving loads and with vehicles. InputError naming the key for
/// an invalid value or when no mode is kept (giving the lowest frequency); SolverError from the
/// eigensolver.
model::Modes kept_modes(const model::Structure& s, const ModalSettings& ms);

/// Builds the structure, maps the stations and, for the modal method, solves the eigenproblem
/// and keeps the modes settings.modal selects. rail_outputs = false leaves the rail above deck
/// stations out of the modal outputs (StationHistory::rail_disp then stays empty; sweeps, which
/// only take deck peaks, save the work). InputError/SolverError on failure.
/// with_load_effects records load_effects() in simulate() (RunResult::effects).
PreparedModel prepare_model(const Scenario& sc, bool rail_outputs = true, bool with_load_effects = false);
/// The same from a built structure.
/// `effect_stations`: Scenario::effect_stations (load effects only).
PreparedModel prepare_model(model::Structure s, const std::vector<StationSpec>& stations,
                            const RunSettings& settings, bool rail_outputs = true, bool with_load_effects = false,
                            const std::vector<StationSpec>& effect_stations = {});

/// The speed of a one-passage command [m/s]: `speed_kmh` when given (> 0 and finite), else the
/// scenario's run.speed_kmh; InputError naming `option` (how the caller calls speed_kmh: the
/// CLI's "--speed-kmh", the Python package's "speed_kmh") otherwise.
double passage_speed(const Scenario& sc, const std::optional<double>& speed_kmh, const std::string& option);
/// The train called `name`, else the scenario's first; InputError listing the scenario's trains.
const load::Train& passage_train(const Scenario& sc, const std::optional<std::string>& name);

/// The index of the scenario's station `name`; InputError "WHO: no station 'NAME' in the
/// scenario; it has: ..." otherwise.
std::size_t station_index(const Scenario& sc, const std::string& name, const std::string& who);

/// A record channel of kind `k` mapped to station `station` (--map, --channel): a strain needs
/// the station's stations[].fibre_m to give the model's strain; InputError naming both otherwise.
void require_strain_fibre(const Scenario& sc, std::size_t station, const std::string& channel, ResponseKind k,
                          const std::string& who);

/// Runs `train` at `speed` [m/s] from the entry of its first axle until free_vibration_s after
/// the last axle has left, with settings.method, and records every station at every step.
/// InputError when the histories would exceed kMaxHistoryBytes.
RunResult simulate(const PreparedModel& m, const load::Train& train, double speed, const RunSettings& settings);
/// Convenience for one-off runs: prepares the model (modes included) on every call.
RunResult simulate(const model::Structure& s, const std::vector<ResolvedStation>& stations,
                   const load::Train& train, double speed, const RunSettings& settings);

/// The same as simulate() at each of `speeds` [m/s], in order, through the integrator's batch
/// (solve::Integrator::run_batch). Newmark: kNewmarkBatch speeds at a time (one factorisation, the
/// sparse products and solves on all of them at once: same answers up to rounding, a fraction of
/// the time); other methods one case at a time.
std::vector<RunResult> simulate_batch(const PreparedModel& m, const load::Train& train,
                                      const std::vector<double>& speeds, const RunSettings& settings);

/// Unit-response superposition: simulates one unit axle at `speed` (settings.method) long
/// enough for every train, then composes each train's histories as Σₖ Pₖ r(t − xₖ/v) with the
/// shifts interpolated by 4-point cubic Lagrange (exact for cubics). Valid because the models are
/// linear and the loads constant. One RunResult per train; summary.wall_s is the shared unit run
/// plus that train's composition.
std::vector<RunResult> simulate_by_unit_response(const PreparedModel& m, const std::vector<load::Train>& trains,
                                                 double speed, const RunSettings& settings);

/// Peak values of one station.
struct StationPeaks {
  double max_abs_acc = 0.0;   ///< [m/s²] filtered acceleration (raw when the filter is off)
  double max_abs_disp = 0.0;  ///< [m] deflection
};
std::vector<StationPeaks> peaks(const RunResult& r);

/// Station `station`'s history of `k` in `r` (unfiltered). SolverError when `r` has no strain
/// history for it (the model was prepared without load effects or the station has no fibre).
Vector station_response(const RunResult& r, std::size_t station, ResponseKind k);

/// Signed extremes of one quantity over a case.
struct EffectPeak {
  double max = 0.0, min = 0.0;  ///< largest and smallest value (sagging moment, compression positive)
  double max_abs() const { return std::max(max, -min); }
};

/// The quantities whose extremes a sweep with load effects keeps, in order: each deck station's
/// deflection (<station>_disp_m), then the load effects `m` was prepared with (LoadEffect::name).
std::vector<std::string> quantity_names(const PreparedModel& m);
/// Their extremes over a run of `m` (simulate()'s result), in quantity_names' order.
std::vector<EffectPeak> quantity_peaks(const PreparedModel& m, const RunResult& r);

/// True when the cases of `m` under `s` can run on a folded train (fold_train, simulate_peaks):
/// modal method (the model prepared for it) and direct superposition.
bool folds_trains(const PreparedModel& m, const RunSettings& s);

/// `train` (loads × load_factor, > 0) folded over the unit-axle table of `m` (prepared for the
/// modal method): its modal loads as one piecewise cubic of the head position, exact and
/// speed-independent, built once per (model, train). InputError for an invalid train or a model
/// without a modal table.
std::shared_ptr<const solve::MovingChannels> fold_train(const PreparedModel& m, const load::Train& train,
                                                        double load_factor);

/// fold_train in parts that threads share (a sweep's threads that need the same train fold it
/// together instead of waiting for one of them): the constructor checks the train, sets the
/// breakpoints and allocates the table (InputError as fold_train); fill(c) writes chunk c's
/// pieces, each chunk once, by any thread and in any order (distinct chunks concurrently); table()
/// once every chunk is filled. The numbers do not depend on the chunks: fold_train is the
/// constructor, every fill in turn and table(). `m` must outlive the TrainFold (fill reads its
/// path table); the table does not need either.
class TrainFold {
 public:
  TrainFold(const PreparedModel& m, const load::Train& train, double load_factor);
  ~TrainFold();
  TrainFold(const TrainFold&) = delete;
  TrainFold& operator=(const TrainFold&) = delete;
  std::size_t n_chunks() const;
  /// Arithmetic on memory the constructor allocated: cannot fail (a sweep's threads that wait for
  /// the other chunks rely on it; noexcept makes a failure stop the program, not hang it).
  void fill(std::size_t chunk) noexcept;
  std::shared_ptr<const solve::MovingChannels> table() const;

 private:
  struct Plan;
  std::unique_ptr<Plan> p_;
};

/// The vehicles' extremes in one case (sprung and multibody models).
struct VehiclePeaks {
  bool present = false;          ///< false with moving forces
  double min_contact = 0.0;      ///< [N] smallest contact force of any axle (negative: a wheel lifted)
  double max_contact = 0.0;      ///< [N] largest
  double max_unloading_ratio = 0.0;  ///< (P0 − P_min)/P0, largest over the axles
  double max_body_acc = 0.0;     ///< [m/s²] largest |car-body acceleration|, unfiltered
  std::string body;              ///< where ("c3", "a5")
  double max_floor_acc = 0.0;    ///< [m/s²] largest VehicleHistory::max_floor_acc (the comfort check's)
  std::string floor_body;        ///< whose
  double max_airborne_s = 0.0;   ///< [s] longest time an axle spent off the rail
  bool contact_lost = false;     ///< VehicleHistory::contact_lost()
};
VehiclePeaks vehicle_peaks(const RunResult& r);

/// Peaks of one case, as peaks(simulate(...)) gives them.
struct CasePeaks {
  std::vector<StationPeaks> peaks;  ///< per station
  /// quantity_peaks() when the model was prepared with load effects
  std::vector<EffectPeak> quantities;
  Index n_steps = 0;
  double wall_s = 0.0;  ///< [s]
  VehiclePeaks vehicle;  ///< with vehicles
};

/// The peaks of `train` at each of `speeds` [m/s], in order, the cheapest way the settings allow
/// (with CasePeaks::quantities when `m` has load effects; the kernel keeps a bearing force's
/// inertia, damping and direct-load parts as sums of outputs, solve::OutputSum):
/// with a folded train (`folded` from fold_train, folds_trains(m, settings)) the modal peaks kernel
/// (no history but the accelerations a filter needs, four speeds per SIMD pass); otherwise
/// simulate_batch(). Same values as peaks(simulate()) up to rounding.
std::vector<CasePeaks> simulate_peaks(const PreparedModel& m, const load::Train& train, const std::vector<double>& speeds,
                                      const RunSettings& settings, const solve::MovingChannels* folded = nullptr);

}  // namespace viaduct::study
