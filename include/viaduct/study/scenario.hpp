#pragma once
/// \file A resolved scenario: plain data in SI units, produced by io::load_scenario.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/load/vehicle.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/solve/options.hpp"

namespace viaduct::study {

/// Where a response is recorded.
struct StationSpec {
  std::string name;          ///< unique, used in column names
  bool on_deck = true;       ///< true: on span `span` at x_local; false: on the rail at x_track
  std::size_t span = 0;      ///< 0-based span index (deck stations)
  double x_local = 0.0;      ///< [m] from the span's left end (deck stations)
  double x_track = 0.0;      ///< [m] global x (rail stations)
  /// [m] deck stations: distance of a strain gauge's fibre from the neutral axis, positive below
  /// it (tension under a sagging moment); 0: no strain output.
  double fibre_m = 0.0;
};

/// Post-processing filter of accelerations (zero-phase Chebyshev I).
struct FilterSpec {
  bool enabled = true;
  signal::Cheby1Spec cheby;
};

/// What a sensor measures at a station, as records and comparisons name it.
enum class ResponseKind {
  acceleration,  ///< [m/s²] the deck's (rail's at a rail station)
  deflection,    ///< [m] positive down
  strain,        ///< [µε] the station's <station>_strain_ue (a model prepared with load effects)
  velocity,      ///< [m/s] the deck's (a geophone), the acceleration integrated from rest (trapezoidal)
};
/// Deflection and strain: quasi-static content, low-passed only, zero offsets meaningful.
inline bool quasi_static_kind(ResponseKind k) { return k == ResponseKind::deflection || k == ResponseKind::strain; }
/// "acc", "disp", "strain" or "vel" (report columns).
const char* response_name(ResponseKind k);
/// The unit of a response as viaduct's columns write it: "mps2", "m" or "ue".
const char* response_unit(ResponseKind k);
/// The filter a response is compared under: accelerations the scenario's own; deflection and
/// strain, which carry the quasi-static load, only its low-pass part (the same order and
/// ripple, a low-pass at its upper edge), so that only the noise above the band goes.
FilterSpec filter_for(const FilterSpec& scenario_filter, ResponseKind k);

/// How the equations of motion are solved (chosen in one place: solve::make_integrator).
using Method = solve::Method;

/// How a train's response is composed.
enum class Superposition {
  direct,         ///< every (train, speed) case simulated with all its axles
  unit_response,  ///< one unit axle per speed, shifted and scaled for every axle of every train
};

/// Modal basis selection. The modes kept are the lowest ones satisfying both limits.
struct ModalSettings {
  Index n_modes = 0;              ///< at most this many (0: no count limit)
  double max_frequency_hz = 0.0;  ///< [Hz] only modes up to this frequency (0: no limit)
  bool static_correction = true;  ///< mode-acceleration correction of displacements
  /// Blocks of damping-correction vectors appended to the modes when the damping couples them
  /// (solve::damping_enriched_basis); 0: the modes alone.
  int damping_vectors = 1;
};

/// How a train acts on the rail (docs/vehicles.md): the rungs of the interaction ladder.
enum class VehicleModel {
  forces,     ///< constant moving axle loads (no vehicle dynamics)
  sprung,     ///< one sprung mass on one unsprung mass per axle
  multibody,  ///< 2D coaches: body and bogies in bounce and pitch, four wheelsets (trains of coaches)
};
/// "forces", "sprung", "multibody".
const char* vehicle_model_name(VehicleModel m);
/// The wheel–rail contact of vehicle models.
enum class ContactModel {
  hertz,  ///< linearised Hertz spring per axle
  rigid,  ///< the wheel follows the rail
};

/// Vehicles on the rail (RunSettings::vehicle; ignored with VehicleModel::forces).
struct VehicleSettings {
  VehicleModel model = VehicleModel::forces;
  ContactModel contact = ContactModel::hertz;
  /// [N/m] contact stiffness per axle of a whole train (both rails; × load_factor in the model),
  /// > 0; 0: linearised Hertz at the static wheel load, 3 P^{1/3} / G per axle with
  /// G = 4.57e-8 R^-0.149 m/N^{2/3} (Zhai's conical tread, to confirm).
  double contact_stiffness = 0.0;
  double wheel_radius = 0.43;  ///< [m] > 0, for the Hertz stiffness
  /// true: unilateral contact, a wheel whose force would pull leaves the rail and lands again
  /// (solve::LinearVehicle::release); false: the linear contact holds it with a tensile force.
  bool release = true;
  /// Per-axle sprung masses for every train (VehicleModel::sprung); absent: each train's coaches
  /// give them (load::sprung_of), and a list of axles is an error.
  std::optional<load::SprungSpec> sprung;
  double gravity = load::kGravity;  ///< [m/s²] masses of the axles' static loads
  /// [m] >= 0, track models: within this length of either end of the load path a wheel's load
  /// passes gradually between rigid ground and the rail (study::train_contacts); shorter than the
  /// approach and exit track.
  double end_transition = 10.0;
  /// [Hz] >= 0: the car-body floor accelerations (VehicleHistory::max_floor_acc, the comfort
  /// check's) low-passed at this frequency, zero-phase Chebyshev I of the filter's order and
  /// ripple, from rest; 0: unfiltered.
  double comfort_lowpass_hz = 0.0;
};

/// Rail irregularities seen by vehicle models (a dip positive in the coupled equations).
struct IrregularitySettings {
  /// "" (a smooth rail), or a spectrum of load::irregularity_spectrum() for a random profile.
  std::string spectrum;
  /// A measured profile along the load path (io::read_rail_profile), instead of a spectrum.
  std::shared_ptr<const load::RailProfile> measured;
  std::string measured_file;  ///< where `measured` came from (manifest)
  double lambda_min = 1.0;    ///< [m] random profile's shortest wavelength
  double lambda_max = 80.0;   ///< [m] its longest
  double dx = 0.05;           ///< [m] its sampling step
  std::uint64_t seed = 1;
  /// [m] >= taper: rigid, irregular track the train rolls over before the first axle reaches the
  /// load path (the run starts run_in / v earlier; histories still begin with the first axle at
  /// the path's start), so that the vehicles arrive moving as on any track.
  double run_in = 100.0;
  /// [m] >= 0: the profile fades in over the first taper metres of the run-in and out over taper
  /// metres past the load path's end (cosine ramps); the rail is smooth beyond. The vehicles start
  /// in static equilibrium on a smooth rail.
  double taper = 20.0;
  bool enabled() const { return !spectrum.empty() || measured != nullptr; }
};

/// Integration and run settings shared by `run` and `sweep`.
struct RunSettings {
  Method method = Method::newmark;
  double dt = 1e-3;                ///< [s] the analysis step: Newmark's step, modal load sampling, recording interval
  Superposition superposition = Superposition::direct;
  ModalSettings modal;             ///< the modal basis (Method::modal)
  solve::NewmarkOptions newmark;   ///< beta, gamma, alpha (Method::newmark)
  solve::IdaOptions ida;           ///< tolerances; log: SUNDIALS' messages, called from any sweep thread (Method::ida)
  double free_vibration_s = 1.0;   ///< [s] simulated after the last axle leaves, >= 0
  double load_factor = 1.0;        ///< [-] multiplies every axle load, > 0
  FilterSpec filter;
  VehicleSettings vehicle;             ///< how the trains act on the rail (forces by default)
  IrregularitySettings irregularity;   ///< rail profile seen by vehicle models
  /// What solve::make_integrator() takes: the method, dt and the options of each method.
  solve::IntegrationSettings integration() const;
};

struct Scenario {
  std::string title;
  model::BridgeParams bridge;
  std::optional<model::TrackParams> track;  ///< absent: no track DOFs, loads on the deck
  /// What the track file says it models (track.rails): "one" rail line on half a deck (axle
  /// loads halved: train.load_factor = 0.5), "both" rails on the whole deck, or "unstated".
  std::string track_rails = "unstated";
  std::vector<load::Train> trains;           ///< at least one
  std::vector<StationSpec> stations;         ///< at least one
  /// Deck stations along a span (stations[].every_m): load effects only — their deflection,
  /// moment, strain and shear among the load effects (prepare_model with load effects), no
  /// acceleration or station history.
  std::vector<StationSpec> effect_stations;
  RunSettings settings;
  std::optional<double> run_speed;           ///< [m/s] default speed of `viaduct run`
  std::vector<double> sweep_speeds;          ///< [m/s] speeds of `viaduct sweep`
};

/// One parameter variant of a sweep: a fully resolved scenario (trains, speeds, stations included).
struct Variant {
  std::string label;  ///< e.g. "reference", "Kp x0.5"
  Scenario scenario;
  /// Non-empty: the variant could not be formed (a factor breaking its key's rule); `scenario`
  /// is then the reference's, for its trains and speeds, and every case of the variant fails
  /// with this reason.
  std::string error{};
  /// The factor on each varied key of the sweep, in the order of sweep.variants (1 for keys this
  /// variant leaves alone); empty for a sweep without variants. One envelope column per key.
  std::vector<std::pair<std::string, double>> factors{};
  /// Optional: the speeds [m/s] of each train (one list per scenario.trains entry), instead of
  /// scenario.sweep_speeds for all (an assessment refines each train around its own resonances).
  std::vector<std::vector<double>> train_speeds{};
};

}  // namespace viaduct::study
