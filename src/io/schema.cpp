// The scenario schema: every key with type, default, unit, constraint, doc and, for the keys that
// set one field of study::Scenario, that field's setter and getter (DESIGN.md §3.9 and §5: deal.II's
// add_parameter; the getter lets a test hold the field's initialiser to the schema's default).
// to_scenario (convert.cpp) applies the setters; it reads by hand only what combines several keys
// (per-span lists, the rail's E·I and ρ·A, trains, stations, speeds, the preset, fit sections).
#include <stdexcept>

#include "viaduct/io/scenario.hpp"

namespace viaduct::io {

namespace {
// Enumerations: each value's name once, read both ways (the setter, the getter that the tests
// compare with the default). The schema's constraint has already refused any other string, so a
// value not listed here is a logic error (a new enum value added to the schema but not mapped),
// never a silent default.
template <class E>
struct Named {
  const char* name;
  E value;
};
const Named<model::DampingKind> kDampingKinds[] = {
    {"none", model::DampingKind::none}, {"modal", model::DampingKind::modal}, {"rayleigh", model::DampingKind::rayleigh}};
const Named<study::Method> kMethods[] = {
    {"newmark", study::Method::newmark}, {"modal", study::Method::modal}, {"ida", study::Method::ida}};
const Named<study::Superposition> kSuperpositions[] = {
    {"direct", study::Superposition::direct}, {"unit-response", study::Superposition::unit_response}};
const Named<study::VehicleModel> kVehicleModels[] = {
    {"forces", study::VehicleModel::forces}, {"sprung", study::VehicleModel::sprung}, {"multibody", study::VehicleModel::multibody}};
const Named<study::ContactModel> kContacts[] = {{"hertz", study::ContactModel::hertz}, {"rigid", study::ContactModel::rigid}};
const Named<signal::BandType> kBands[] = {
    {"lowpass", signal::BandType::lowpass}, {"highpass", signal::BandType::highpass}, {"bandpass", signal::BandType::bandpass}};

template <class E, std::size_t N>
E enum_of(const Named<E> (&names)[N], const std::string& s, const char* key) {
  for (const Named<E>& n : names)
    if (s == n.name) return n.value;
  throw std::logic_error(std::string(key) + ": unmapped value '" + s + "'");
}
template <class E, std::size_t N>
std::string name_of(const Named<E> (&names)[N], E v, const char* key) {
  for (const Named<E>& n : names)
    if (v == n.value) return n.name;
  throw std::logic_error(std::string(key) + ": an enum value without a name");
}

using T = ValueType;
using S = study::Scenario;
using V = Value;

// The keys by section, in the order docs/scenarios.md lists them.
std::vector<KeySpec> general_keys() {  // general
  return {
      {"title", T::string, "\"\"", "", "", "Free text shown in outputs.",
       [](S& sc, const V& v) { sc.title = v.s; }, nullptr, [](const S& sc) { return sc.title; }},
      {"description", T::string, "\"\"", "", "", "Free text: what the scenario studies and where its numbers come from."},
  };
}

std::vector<KeySpec> bridge_keys() {  // bridge
  return {
      {"bridge.file", T::string, "", "", "", "Bridge component file; its keys are read under bridge. (path relative to the referencing file)."},
      {"bridge.notes", T::string, "\"\"", "", "", "Free text: sources and readings of the parameters."},
      {"bridge.span_lengths", T::number_list, "", "m", "> 0", "Length of each span (simply supported, or of the continuous deck: bridge.continuous), in order along the line (required)."},
      {"bridge.EI", T::number_or_list, "", "N·m²", "> 0", "Bending stiffness: one value for all spans or one per span (required)."},
      {"bridge.mass_per_m", T::number_or_list, "", "kg/m", "> 0", "Mass per metre: one value or one per span (required)."},
      {"bridge.mass_includes_track", T::boolean, "false", "", "", "true: mass_per_m includes the track on the deck; a modelled track's mass per metre is then taken off the deck.",
       [](S& sc, const V& v) { sc.bridge.mass_includes_track = v.b; },
       [](const S& sc) { return static_cast<double>(sc.bridge.mass_includes_track); }},
      {"bridge.added_mass_per_m", T::number, "0.0", "kg/m", ">= 0", "Non-structural mass added to every span.",
       [](S& sc, const V& v) { sc.bridge.added_mass_per_m = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.added_mass_per_m); }},
      {"bridge.element_size", T::number, "0.5", "m", "> 0", "Target deck element length (each span gets a whole number of equal elements).",
       [](S& sc, const V& v) { sc.bridge.element_size = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.element_size); }},
      {"bridge.continuous", T::boolean, "false", "", "", "true: the spans form one continuous deck over intermediate supports (one bearing per support, nodes shared); false: a chain of simply supported spans.",
       [](S& sc, const V& v) { sc.bridge.continuous = v.b; },
       [](const S& sc) { return static_cast<double>(sc.bridge.continuous); }},
      {"bridge.bearings.rigid", T::boolean, "true", "", "", "true: span ends fixed vertically; false: springs k and dashpots c.",
       [](S& sc, const V& v) { sc.bridge.bearings.rigid = v.b; },
       [](const S& sc) { return static_cast<double>(sc.bridge.bearings.rigid); }},
      {"bridge.bearings.k", T::number, "0.0", "N/m", ">= 0", "Vertical stiffness of each bearing (span end) when not rigid; must then be > 0.",
       [](S& sc, const V& v) { sc.bridge.bearings.k = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.bearings.k); }},
      {"bridge.bearings.c", T::number, "0.0", "N·s/m", ">= 0", "Vertical damping of each bearing when not rigid.",
       [](S& sc, const V& v) { sc.bridge.bearings.c = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.bearings.c); }},
      {"bridge.bearings.rotational_k", T::number, "0.0", "N·m/rad", ">= 0", "Rotational spring at each span end (integral or frame abutments): 0 free (simply supported), very large (1e15) clamped.",
       [](S& sc, const V& v) { sc.bridge.bearings.rotational_k = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.bearings.rotational_k); }},
      {"bridge.damping.kind", T::string, "\"modal\"", "", "none|modal|rayleigh", "Structural damping of the bridge: one ratio for every span mode, or Rayleigh through two (frequency, ratio) pairs.",
       [](S& sc, const V& v) { sc.bridge.damping.kind = enum_of(kDampingKinds, v.s, "bridge.damping.kind"); }, nullptr,
       [](const S& sc) { return name_of(kDampingKinds, sc.bridge.damping.kind, "bridge.damping.kind"); }},
      {"bridge.damping.ratio", T::number, "0.0", "-", "[0, 1)", "modal: ratio of critical damping for every span mode (0.01565 = 1.565 %).",
       [](S& sc, const V& v) { sc.bridge.damping.ratio = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.damping.ratio); }},
      {"bridge.damping.f1_hz", T::number, "0.0", "Hz", ">= 0", "rayleigh: first frequency.",
       [](S& sc, const V& v) { sc.bridge.damping.f1_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.damping.f1_hz); }},
      {"bridge.damping.ratio1", T::number, "0.0", "-", "[0, 1)", "rayleigh: damping ratio at f1_hz.",
       [](S& sc, const V& v) { sc.bridge.damping.ratio1 = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.damping.ratio1); }},
      {"bridge.damping.f2_hz", T::number, "0.0", "Hz", ">= 0", "rayleigh: second frequency (> f1_hz).",
       [](S& sc, const V& v) { sc.bridge.damping.f2_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.damping.f2_hz); }},
      {"bridge.damping.ratio2", T::number, "0.0", "-", "[0, 1)", "rayleigh: damping ratio at f2_hz.",
       [](S& sc, const V& v) { sc.bridge.damping.ratio2 = v.x; },
       [](const S& sc) { return static_cast<double>(sc.bridge.damping.ratio2); }},
  };
}

std::vector<KeySpec> track_keys() {  // track
  return {
      {"track.file", T::string, "", "", "", "Track component file; its keys are read under track. Without any track key the model has no track."},
      {"track.notes", T::string, "\"\"", "", "", "Free text: sources and readings of the parameters."},
      {"track.rails", T::string, "\"unstated\"", "", "unstated|one|both",
       "What the track's values describe: one rail line (with half a deck: each rail carries half of each axle, train.load_factor = 0.5) or both rails summed (the whole deck, load_factor = 1). A mismatch with train.load_factor is warned of.",
       [](S& sc, const V& v) { sc.track_rails = v.s; }, nullptr, [](const S& sc) { return sc.track_rails; }},
      {"track.approach_length", T::number, "20.0", "m", ">= 0", "Track before the bridge (axles enter at its start); rounded down to whole sleeper bays with exit_length.",
       [](S& sc, const V& v) { sc.track->approach_length = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.approach_length); }},
      {"track.exit_length", T::number, "20.0", "m", ">= 0", "Track after the bridge.",
       [](S& sc, const V& v) { sc.track->exit_length = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.exit_length); }},
      {"track.sleeper_spacing", T::number, "0.6", "m", "> 0", "Distance between sleepers (rail seats).",
       [](S& sc, const V& v) { sc.track->sleeper_spacing = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.sleeper_spacing); }},
      {"track.first_sleeper_offset", T::number, "", "m", ">= 0", "Where the sleepers sit: the first sleeper on the bridge this far from its start (< sleeper_spacing); the approach track then begins at the first sleeper at or before approach_length. Unset: the track starts at -approach_length with a sleeper. Identical spans coupled by the track are sensitive to it (docs/model.md).",
       [](S& sc, const V& v) { sc.track->first_sleeper_offset = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.first_sleeper_offset); }},
      {"track.rail_elements_per_bay", T::integer, "1", "-", ">= 1", "Rail beam elements between two sleepers.",
       [](S& sc, const V& v) { sc.track->rail_elements_per_bay = static_cast<int>(v.x); },
       [](const S&) { return static_cast<double>(model::TrackParams{}.rail_elements_per_bay); }},
      {"track.rail.E", T::number, "", "Pa", "> 0", "Rail Young's modulus (required)."},
      {"track.rail.I", T::number, "", "m⁴", "> 0", "Rail second moment of area (required)."},
      {"track.rail.A", T::number, "", "m²", "> 0", "Rail cross-section area (required)."},
      {"track.rail.density", T::number, "7850.0", "kg/m³", "> 0", "Rail density."},
      {"track.sleeper_mass", T::number, "", "kg", "> 0", "Sleeper mass per rail seat (required).",
       [](S& sc, const V& v) { sc.track->sleeper_mass = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.sleeper_mass); }},
      {"track.ballast_mass", T::number, "", "kg", "> 0", "Vibrating ballast mass per rail seat (required).",
       [](S& sc, const V& v) { sc.track->ballast_mass = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.ballast_mass); }},
      {"track.pad.k", T::number, "", "N/m", "> 0", "Rail pad stiffness per rail seat (required).",
       [](S& sc, const V& v) { sc.track->pad.k = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.pad.k); }},
      {"track.pad.c", T::number, "0.0", "N·s/m", ">= 0", "Rail pad damping per rail seat.",
       [](S& sc, const V& v) { sc.track->pad.c = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.pad.c); }},
      {"track.ballast.k", T::number, "", "N/m", "> 0", "Ballast stiffness per rail seat, sleeper to ballast mass (required).",
       [](S& sc, const V& v) { sc.track->ballast.k = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.ballast.k); }},
      {"track.ballast.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast damping per rail seat.",
       [](S& sc, const V& v) { sc.track->ballast.c = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.ballast.c); }},
      {"track.shear.k", T::number, "0.0", "N/m", ">= 0", "Ballast shear stiffness between neighbouring ballast masses.",
       [](S& sc, const V& v) { sc.track->shear.k = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.shear.k); }},
      {"track.shear.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast shear damping between neighbouring ballast masses.",
       [](S& sc, const V& v) { sc.track->shear.c = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.shear.c); }},
      {"track.subgrade.k", T::number, "", "N/m", "> 0", "Subgrade stiffness per rail seat off the bridge, ballast mass to ground (required).",
       [](S& sc, const V& v) { sc.track->subgrade.k = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.subgrade.k); }},
      {"track.subgrade.c", T::number, "0.0", "N·s/m", ">= 0", "Subgrade damping per rail seat off the bridge.",
       [](S& sc, const V& v) { sc.track->subgrade.c = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.subgrade.c); }},
      {"track.subgrade_on_bridge.k", T::number, "", "N/m", "> 0", "Ballast mass to deck stiffness per rail seat on the bridge (required).",
       [](S& sc, const V& v) { sc.track->subgrade_on_bridge.k = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.subgrade_on_bridge.k); }},
      {"track.subgrade_on_bridge.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast mass to deck damping per rail seat on the bridge.",
       [](S& sc, const V& v) { sc.track->subgrade_on_bridge.c = v.x; },
       [](const S&) { return static_cast<double>(model::TrackParams{}.subgrade_on_bridge.c); }},
  };
}

std::vector<KeySpec> train_keys() {  // trains
  return {
      {"train.files", T::string_list, "", "", "", "Train files (.toml: hslm, regular or axles; .csv: position_m,load_kN), relative to the referencing file (required); \"hslm:A1-A10\" (or hslm:A4, hslm:A1,A5) names the Eurocode HSLM-A trains without files."},
      {"train.load_factor", T::number, "1.0", "-", "> 0", "Multiplies every axle load (0.5: one rail of a half-deck model carries half of each axle).",
       [](S& sc, const V& v) { sc.settings.load_factor = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.load_factor); }},
      {"train.vehicle", T::string, "\"forces\"", "", "forces|sprung|multibody", "How the trains act on the rail (docs/vehicles.md): forces, constant axle loads; sprung, one sprung mass on one unsprung mass per axle (train.unsprung_mass_kg and train.suspension_*, or each train's coaches); multibody, 2D coaches with bogies (trains of kind \"coaches\" only).",
       [](S& sc, const V& v) { sc.settings.vehicle.model = enum_of(kVehicleModels, v.s, "train.vehicle"); }, nullptr,
       [](const S& sc) { return name_of(kVehicleModels, sc.settings.vehicle.model, "train.vehicle"); }},
      {"train.contact", T::string, "\"hertz\"", "", "hertz|rigid", "Wheel-rail contact of sprung and multibody vehicles: a linearised Hertz spring per axle, or the wheel following the rail.",
       [](S& sc, const V& v) { sc.settings.vehicle.contact = enum_of(kContacts, v.s, "train.contact"); }, nullptr,
       [](const S& sc) { return name_of(kContacts, sc.settings.vehicle.contact, "train.contact"); }},
      {"train.comfort_lowpass_hz", T::number, "0.0", "Hz", ">= 0", "Sprung and multibody vehicles: the car-body floor accelerations of the comfort check (max_floor_acc_mps2) low-passed at this frequency (zero-phase Chebyshev I of filter.order and filter.ripple_db, from rest); 0: unfiltered.",
       [](S& sc, const V& v) { sc.settings.vehicle.comfort_lowpass_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.vehicle.comfort_lowpass_hz); }},
      {"train.contact_release", T::boolean, "true", "", "", "Sprung and multibody vehicles: true, a wheel whose contact force would pull leaves the rail and lands again (unilateral contact; the time in the air is reported); false, the linear contact holds it with a tensile force (reported as a lost contact).",
       [](S& sc, const V& v) { sc.settings.vehicle.release = v.b; },
       [](const S& sc) { return static_cast<double>(sc.settings.vehicle.release); }},
      {"train.contact_stiffness_N_m", T::number, "", "N/m", "> 0", "Contact stiffness per axle, both rails (default: linearised Hertz at the static wheel load, 3 P^(1/3)/G with G = 4.57e-8 R^-0.149, Zhai's conical tread).",
       [](S& sc, const V& v) { sc.settings.vehicle.contact_stiffness = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.vehicle.contact_stiffness); }},
      {"train.wheel_radius_m", T::number, "0.43", "m", "> 0", "Wheel radius R of the Hertz contact stiffness.",
       [](S& sc, const V& v) { sc.settings.vehicle.wheel_radius = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.vehicle.wheel_radius); }},
      {"train.end_transition_m", T::number, "10.0", "m", ">= 0", "Sprung and multibody vehicles on a track: within this length of either end of the load path a wheel's load passes gradually (a cosine) between rigid ground and the rail, the rail's level under it weighted alike: a free rail end, deflecting several times more than the track, would otherwise be a dip every wheel hits. Shorter than the approach and exit track.",
       [](S& sc, const V& v) { sc.settings.vehicle.end_transition = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.vehicle.end_transition); }},
      {"train.unsprung_mass_kg", T::number, "", "kg", ">= 0", "Sprung vehicles: unsprung mass per axle (with train.suspension_stiffness_N_m; the sprung mass is the axle load / g minus it). Not set: each train's coaches give the sprung masses.",},
      {"train.suspension_stiffness_N_m", T::number, "", "N/m", "> 0", "Sprung vehicles: suspension stiffness per axle.",},
      {"train.suspension_damping_Ns_m", T::number, "0.0", "N·s/m", ">= 0", "Sprung vehicles: suspension damping per axle."},
  };
}

std::vector<KeySpec> irregularity_keys() {  // irregularity
  return {
      {"irregularity.spectrum", T::string, "\"\"", "", "|fra1|fra2|fra3|fra4|fra5|fra6|german-low|german-high", "Random vertical rail profile seen by sprung and multibody vehicles (viaduct irregularity draws it): an FRA class or a German spectrum; \"\" a smooth rail.",
       [](S& sc, const V& v) { sc.settings.irregularity.spectrum = v.s; }, nullptr,
       [](const S& sc) { return sc.settings.irregularity.spectrum; }},
      {"irregularity.profile", T::string, "", "", "", "A measured profile instead (x_m,z_mm CSV, x along the load path, z up), relative to this file; it must cover the run-in, the load path and taper_m past its end."},
      {"irregularity.seed", T::integer, "1", "-", ">= 0", "Seed of the random profile (same seed, same profile).",
       [](S& sc, const V& v) { sc.settings.irregularity.seed = static_cast<std::uint64_t>(v.x); },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.seed); }},
      {"irregularity.min_wavelength_m", T::number, "1.0", "m", "> 0", "Shortest wavelength of the random profile.",
       [](S& sc, const V& v) { sc.settings.irregularity.lambda_min = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.lambda_min); }},
      {"irregularity.max_wavelength_m", T::number, "80.0", "m", "> 0", "Longest wavelength of the random profile.",
       [](S& sc, const V& v) { sc.settings.irregularity.lambda_max = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.lambda_max); }},
      {"irregularity.step_m", T::number, "0.05", "m", "> 0", "Sampling step of the random profile.",
       [](S& sc, const V& v) { sc.settings.irregularity.dx = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.dx); }},
      {"irregularity.run_in_m", T::number, "100.0", "m", ">= 0", "Rigid, irregular track rolled over before the first axle reaches the load path (the run starts run_in_m / v earlier; histories still start with the first axle at the path's start), so that the vehicles arrive moving; at least taper_m.",
       [](S& sc, const V& v) { sc.settings.irregularity.run_in = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.run_in); }},
      {"irregularity.taper_m", T::number, "20.0", "m", ">= 0", "The profile fades in over the first taper_m of the run-in and out over taper_m past the load path's end (the vehicles start on a smooth rail).",
       [](S& sc, const V& v) { sc.settings.irregularity.taper = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.irregularity.taper); }},
  };
}

std::vector<KeySpec> analysis_keys() {  // analysis
  return {
      {"analysis.dt", T::number, "0.001", "s", "> 0", "Analysis step of every method: the Newmark step, the load-sampling interval of modal superposition and the recording interval (IDA chooses its own steps and is sampled at it).",
       [](S& sc, const V& v) { sc.settings.dt = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.dt); }},
      {"analysis.beta", T::number, "0.25", "-", "> 0", "Newmark β (0.25: constant average acceleration); not given with analysis.alpha != 0: (1-alpha)²/4. With alpha != 0 it must satisfy 2 beta >= gamma (unconditional stability).",
       [](S& sc, const V& v) { sc.settings.newmark.beta = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.newmark.beta); }},
      {"analysis.gamma", T::number, "0.5", "-", ">= 0.5", "Newmark γ; not given with analysis.alpha != 0: (1-2 alpha)/2. With alpha != 0 it must be >= 1/2 - alpha (unconditional stability).",
       [](S& sc, const V& v) { sc.settings.newmark.gamma = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.newmark.gamma); }},
      {"analysis.alpha", T::number, "0.0", "-", "[-1/3, 0]", "HHT-α (0: plain Newmark): numerical damping of the highest modes. analysis.beta and analysis.gamma not given take alpha's own, (1-alpha)²/4 and (1-2 alpha)/2; given ones outside the unconditionally stable set (gamma >= 1/2 - alpha, 2 beta >= gamma) are refused.",
       [](S& sc, const V& v) { sc.settings.newmark.alpha = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.newmark.alpha); }},
      {"analysis.preset", T::string, "\"\"", "", "|fast|default|reference", "Named speed/accuracy setting (docs/accuracy.md): sets analysis.method, analysis.dt and modal.* from the band edge f_c (filter.high_hz, or 30 Hz); keys given explicitly override it. fast and default take modal superposition, or Newmark when the rail's resonance on its pads lies below their modal cut-off (soft pads, docs/reliability.md)."},
      {"analysis.method", T::string, "\"newmark\"", "", "newmark|modal|ida", "newmark: fixed-step integration of the whole model; modal: superposition of its modes up to modal.max_frequency_hz / modal.n_modes, solved exactly per step; ida: adaptive BDF of the whole model (SUNDIALS IDA, ida.* tolerances), sampled every analysis.dt (docs/accuracy.md); with vehicles, of the modes up to modal.max_frequency_hz with the vehicles physical, contact losses and landings located in time (docs/vehicles.md; ida.rtol <= 1e-4).",
       [](S& sc, const V& v) { sc.settings.method = enum_of(kMethods, v.s, "analysis.method"); }, nullptr,
       [](const S& sc) { return name_of(kMethods, sc.settings.method, "analysis.method"); }},
      {"ida.rtol", T::number, "1e-6", "-", "[1e-12, 0.1]", "ida: relative tolerance.",
       [](S& sc, const V& v) { sc.settings.ida.rtol = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.ida.rtol); }},
      {"ida.atol_disp_m", T::number, "1e-10", "m", "> 0", "ida: absolute tolerance of displacements.",
       [](S& sc, const V& v) { sc.settings.ida.atol_disp = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.ida.atol_disp); }},
      {"ida.atol_vel_mps", T::number, "1e-8", "m/s", "> 0", "ida: absolute tolerance of velocities.",
       [](S& sc, const V& v) { sc.settings.ida.atol_vel = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.ida.atol_vel); }},
      {"ida.max_order", T::integer, "5", "-", "[1, 5]", "ida: highest BDF order.",
       [](S& sc, const V& v) { sc.settings.ida.max_order = static_cast<int>(v.x); },
       [](const S& sc) { return static_cast<double>(sc.settings.ida.max_order); }},
      {"analysis.superposition", T::string, "\"direct\"", "", "direct|unit-response", "direct: one run per train and speed; unit-response: one run of a unit axle per speed, superposed over every train's axles (linear models only; same answer, much less work with several trains).",
       [](S& sc, const V& v) { sc.settings.superposition = enum_of(kSuperpositions, v.s, "analysis.superposition"); }, nullptr,
       [](const S& sc) { return name_of(kSuperpositions, sc.settings.superposition, "analysis.superposition"); }},
      {"modal.n_modes", T::integer, "0", "-", ">= 0", "modal: keep at most this many of the lowest modes (0: no count limit).",
       [](S& sc, const V& v) { sc.settings.modal.n_modes = static_cast<Index>(v.x); },
       [](const S& sc) { return static_cast<double>(sc.settings.modal.n_modes); }},
      {"modal.max_frequency_hz", T::number, "0.0", "Hz", ">= 0", "modal: keep the modes up to this frequency (0: no frequency limit).",
       [](S& sc, const V& v) { sc.settings.modal.max_frequency_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.modal.max_frequency_hz); }},
      {"modal.static_correction", T::boolean, "true", "", "", "modal: add the quasi-static response of the dropped modes to displacements and load effects (mode-acceleration method); with vehicles (modal and ida) also to the rail under each wheel.",
       [](S& sc, const V& v) { sc.settings.modal.static_correction = v.b; },
       [](const S& sc) { return static_cast<double>(sc.settings.modal.static_correction); }},
      {"modal.damping_vectors", T::integer, "1", "-", "[0, 3]", "modal: blocks of damping-correction vectors (K⁻¹ − ΦΩ⁻²Φᵀ)Cφ appended to the modes when discrete dashpots couple them (the part of the low complex modes that the undamped modes miss; 0: the modes alone; docs/accuracy.md).",
       [](S& sc, const V& v) { sc.settings.modal.damping_vectors = static_cast<int>(v.x); },
       [](const S& sc) { return static_cast<double>(sc.settings.modal.damping_vectors); }},
      {"analysis.free_vibration_s", T::number, "1.0", "s", ">= 0", "Time simulated after the last axle has left the model.",
       [](S& sc, const V& v) { sc.settings.free_vibration_s = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.free_vibration_s); }},
  };
}

std::vector<KeySpec> filter_keys() {  // filter
  return {
      {"filter.enabled", T::boolean, "true", "", "", "Filter accelerations before taking maxima.",
       [](S& sc, const V& v) { sc.settings.filter.enabled = v.b; },
       [](const S& sc) { return static_cast<double>(sc.settings.filter.enabled); }},
      {"filter.band", T::string, "\"bandpass\"", "", "lowpass|highpass|bandpass", "Filter band.",
       [](S& sc, const V& v) { sc.settings.filter.cheby.band = enum_of(kBands, v.s, "filter.band"); }, nullptr,
       [](const S& sc) { return name_of(kBands, sc.settings.filter.cheby.band, "filter.band"); }},
      {"filter.order", T::integer, "3", "-", ">= 1", "Chebyshev I order N (band-pass: 2N poles), SciPy's convention.",
       [](S& sc, const V& v) { sc.settings.filter.cheby.order = static_cast<int>(v.x); },
       [](const S& sc) { return static_cast<double>(sc.settings.filter.cheby.order); }},
      {"filter.ripple_db", T::number, "0.5", "dB", "> 0", "Passband ripple; edges are where one pass drops below -ripple_db (zero-phase: -2·ripple_db).",
       [](S& sc, const V& v) { sc.settings.filter.cheby.ripple_db = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.filter.cheby.ripple_db); }},
      {"filter.low_hz", T::number, "1.0", "Hz", "> 0", "Lower band edge (highpass, bandpass).",
       [](S& sc, const V& v) { sc.settings.filter.cheby.low_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.filter.cheby.low_hz); }},
      {"filter.high_hz", T::number, "30.0", "Hz", "> 0", "Upper band edge (lowpass, bandpass); must be below 1/(2·dt).",
       [](S& sc, const V& v) { sc.settings.filter.cheby.high_hz = v.x; },
       [](const S& sc) { return static_cast<double>(sc.settings.filter.cheby.high_hz); }},
  };
}

std::vector<KeySpec> station_keys() {  // stations
  return {
      {"stations[].name", T::string, "", "", "", "Station name, unique; used in column names (required)."},
      {"stations[].span", T::integer, "", "-", ">= 1", "Span number (1-based) of a deck station; give at or x with it."},
      {"stations[].at", T::number, "", "-", "[0, 1]", "Deck station position as a fraction of the span length."},
      {"stations[].x", T::number, "", "m", ">= 0", "Deck station position from the span's left end (instead of at)."},
      {"stations[].every_m", T::number, "", "m", "> 0", "Deck stations along the whole span instead of at or x: the span cut into round(L/every_m) equal parts (at most 1000), a station at each end of each part, named <name>_<x>m with x from the span's start in metres to two decimals: stations of load effects only (deflection, moment, strain, shear with sweep --load-effects and assess; plot_load_effects.py), no acceleration."},
      {"stations[].track_x", T::number, "", "m", "", "Rail station at this global x (x = 0 at the bridge start), instead of span."},
      {"stations[].fibre_m", T::number, "", "m", "", "Deck stations: a strain gauge's distance from the neutral axis, positive below it (tension under a sagging moment), |y| <= 10 m: run writes <name>_strain_ue = 1e6 M y / EI."},
  };
}

std::vector<KeySpec> run_keys() {  // run
  return {
      {"run.speed_kmh", T::number, "", "km/h", "> 0", "Default speed of `viaduct run` (--speed-kmh overrides).",
       [](S& sc, const V& v) { sc.run_speed = v.x / 3.6; }},
  };
}

std::vector<KeySpec> sweep_keys() {  // sweep
  return {
      {"sweep.speeds_kmh", T::number_list, "", "km/h", "> 0", "Explicit list of speeds."},
      {"sweep.speed_min_kmh", T::number, "", "km/h", "> 0", "Range of speeds with speed_max_kmh and speed_step_kmh."},
      {"sweep.speed_max_kmh", T::number, "", "km/h", "> 0", "Last speed of the range (included when on the step grid)."},
      {"sweep.speed_step_kmh", T::number, "", "km/h", "> 0", "Step of the range."},
      {"sweep.speed_min_mps", T::number, "", "m/s", "> 0", "Evenly spaced speeds with speed_max_mps and n_speeds (both ends included)."},
      {"sweep.speed_max_mps", T::number, "", "m/s", "> 0", "Last speed of the evenly spaced set."},
      {"sweep.n_speeds", T::integer, "", "-", ">= 1", "Number of evenly spaced speeds."},
      {"sweep.mode", T::string, "\"one-at-a-time\"", "", "one-at-a-time|grid|reference|sample", "one-at-a-time: each variant key alone with the others at reference; grid: every combination; reference: ignore the variants; sample: draw the variant keys' factors from their distributions (docs/sampled.md)."},
      {"sweep.n_samples", T::integer, "", "-", ">= 1", "Samples of a sampled study (with sweep.sensitivity: base points, each run d + 2 times for d keys); needed by mode = \"sample\", >= 2."},
      {"sweep.sampling", T::string, "\"lhs\"", "", "lhs|sobol|random", "Design of a sampled study: Latin hypercube, Sobol sequence (digitally shifted by the seed) or independent random draws."},
      {"sweep.seed", T::integer, "1", "-", ">= 0", "Seed of the design (and of the bootstrap): the same seed draws the same samples on any machine."},
      {"sweep.sensitivity", T::boolean, "false", "", "", "Sobol sensitivity indices (Saltelli's design: n_samples x (d + 2) runs); needs independent keys."},
      {"sweep.percentiles", T::number_list, "[5.0, 50.0, 95.0]", "%", ">= 0", "Percentiles of each peak over the samples, each in [0, 100]."},
      {"sweep.acceleration_limit_mps2", T::number, "3.5", "m/s²", "> 0", "Limit whose probability of exceedance is estimated (EN 1990 A2.4.4.2.1: 3.5 ballasted, 5 direct fastening)."},
      {"sweep.n_bootstrap", T::integer, "200", "-", ">= 0", "Bootstrap resamples of the Sobol indices' 95 % intervals (0: none)."},
      {"sweep.batch", T::integer, "16", "-", ">= 1", "Samples run (and held in memory) at once; results are flushed after each batch."},
      {"sweep.variants[].key", T::string, "", "", "", "Numeric scenario key to vary, e.g. track.pad.k (required)."},
      {"sweep.variants[].label", T::string, "\"\"", "", "", "Short name in outputs, e.g. Kp (default: the key)."},
      {"sweep.variants[].factors", T::number_list, "", "-", ">= 0", "Multipliers of the reference value (one-at-a-time and grid sweeps)."},
      {"sweep.variants[].distribution", T::string, "", "", "uniform|normal|lognormal|truncated", "Sampled studies (needed there): the factor's distribution; uniform (low, high), normal (mean, sd), lognormal (the factor's mean, sd), truncated normal (mean, sd, low, high)."},
      {"sweep.variants[].low", T::number, "", "-", "", "Lower bound of a uniform or truncated factor (>= 0)."},
      {"sweep.variants[].high", T::number, "", "-", "", "Upper bound of a uniform or truncated factor."},
      {"sweep.variants[].mean", T::number, "", "-", "", "Mean of a normal, lognormal or truncated (before truncation) factor."},
      {"sweep.variants[].sd", T::number, "", "-", "", "Standard deviation of a normal, lognormal or truncated (before truncation) factor (> 0)."},
      {"sweep.correlations[].keys", T::string_list, "", "", "", "Two variant keys (or labels) whose factors are correlated (sampled studies)."},
      {"sweep.correlations[].rho", T::number, "", "-", "", "Correlation in [-1, 1] of the normals behind the two factors (Gaussian copula)."},
  };
}

std::vector<KeySpec> assess_keys() {  // assess (viaduct assess; docs/assess.md)
  return {
      {"assess.line_speed_kmh", T::number, "", "km/h", "> 0", "Maximum line speed: speeds are assessed up to assess.speed_factor (1.2) times it (EN 1991-2 6.4.6.2); viaduct assess needs it."},
      {"assess.deck_type", T::string, "", "", "steel|composite|prestressed|reinforced|filler-beam", "Deck type of the damping lower bound, EN 1991-2 Table 6.6; viaduct assess needs it."},
      {"assess.track", T::string, "\"ballasted\"", "", "ballasted|direct", "ballasted: deck acceleration limit 3.5 m/s2; direct: direct fastening, 5 m/s2 (EN 1990 A2.4.4.2.1(4))."},
      {"assess.edition", T::string, "\"2003\"", "", "2003|2023", "Edition of EN 1991-2 (with EN 1990's Annex A2) whose clauses the report and checks.csv cite: 2023 cites Section 8 where viaduct knows the clause (HSLM-A Fig. 8.12 / Table 8.4, Lphi Table 8.2) and names the 2003 clause to confirm elsewhere; the values are the 2003 edition's in both (the report lists the keys that take the 2023 ones)."},
      {"assess.acceleration_limit_mps2", T::number, "", "m/s²", "> 0", "Deck acceleration limit (default: from assess.track)."},
      {"assess.speed_factor", T::number, "1.2", "-", ">= 1", "Highest speed assessed over the line speed (EN 1991-2 6.4.6.2: 1.2; a key so that an edition or a national annex that changes it can be followed)."},
      {"assess.speed_min_kmh", T::number, "", "km/h", "> 0", "Lowest speed assessed (default: the smaller of 100 km/h and half the line speed)."},
      {"assess.speed_step_kmh", T::number, "5.0", "km/h", "> 0", "Speed step between the lowest and the highest speed."},
      {"assess.refine_step_kmh", T::number, "1.0", "km/h", "> 0", "Finer step around each resonance speed f d / j of each train."},
      {"assess.refine_band", T::number, "0.03", "-", "[0, 1)", "Half-width of the refined band, as a fraction of the resonance speed."},
      {"assess.harmonics", T::integer, "4", "-", ">= 1", "Resonances f d / j refined for j = 1 .. harmonics, f every deck bending frequency below the cut-off."},
      {"assess.damping_ratio", T::number, "", "-", "[0, 1)", "Structural damping ratio instead of EN 1991-2 Table 6.6 (and instead of the additional damping)."},
      {"assess.interaction_damping", T::boolean, "true", "", "", "Add the damping of Fig. 6.8 / Eq. 6.13 for spans under 30 m (the vehicle-bridge interaction is not modelled)."},
      {"assess.ballast_mass_per_m", T::number, "", "kg/m", ">= 0", "Nominal ballast mass per metre of deck, included in bridge.mass_per_m (default: the modelled track's ballast, or 0: one mass case)."},
      {"assess.ballast_lower_factor", T::number, "1.0", "-", "> 0", "Lower-bound mass: the ballast times this (EN 1991-2 6.4.6.3.2: minimum density, minimum depth)."},
      {"assess.ballast_upper_factor", T::number, "1.3", "-", "> 0", "Upper-bound mass: the ballast times this (saturated density and the +30 % depth allowance, 6.4.6.3.2)."},
      {"assess.ballast_width_m", T::number, "", "m", "> 0", "Width of the ballast bed the model carries (half the bed for a half-deck model): with it the mass bounds are EN 1991-2 6.4.6.3.2's, the bed's minimum density for the lower, its saturated density with the depth + assess.ballast_depth_increase for the upper (the factors above are then not used)."},
      {"assess.ballast_depth_m", T::number, "0.5", "m", "> 0", "Depth of the ballast bed (with assess.ballast_width_m; to confirm for the bridge)."},
      {"assess.ballast_density_kgpm3", T::number, "1800.0", "kg/m3", "> 0", "Nominal density of the ballast, that of the ballast included in bridge.mass_per_m when assess.ballast_mass_per_m is not given (to confirm)."},
      {"assess.ballast_density_min_kgpm3", T::number, "1700.0", "kg/m3", "> 0", "Minimum density of the ballast: the lower mass bound (EN 1991-2 6.4.6.3.2; to confirm)."},
      {"assess.ballast_density_saturated_kgpm3", T::number, "2100.0", "kg/m3", "> 0", "Saturated density of the ballast: the upper mass bound (EN 1991-2 6.4.6.3.2; to confirm)."},
      {"assess.ballast_depth_increase", T::number, "0.3", "-", ">= 0", "Increase of the ballast's depth in the upper mass bound (EN 1991-2 6.4.6.3.2: +30 % for later track lifts)."},
      {"assess.lm71_alpha", T::number, "1.0", "-", "> 0", "Classification factor alpha of Load Model 71 (EN 1991-2 6.3.2(3))."},
      {"assess.track_maintenance", T::string, "\"careful\"", "", "careful|standard", "Dynamic factor of LM71: careful maintenance Phi2, standard Phi3 (EN 1991-2 6.4.5.2)."},
      {"assess.deflection_limit_ratio", T::number, "600.0", "-", "> 0", "Vertical deflection limit as span / ratio (EN 1990 A2.4.4.2.3, to confirm)."},
      {"assess.end_rotation_limit_rad", T::number, "0.0065", "rad", "> 0", "Deck end rotation limit (ballasted track at an abutment, EN 1990 A2.4.4.2.3, to confirm)."},
      {"assess.comfort_level", T::string, "\"very-good\"", "", "very-good|good|acceptable", "With vehicle models: the level of passenger comfort whose limit b_v on the car bodies' vertical acceleration is checked, 1.0 / 1.3 / 2.0 m/s2 (EN 1990 A2.4.4.3.1, Table A2.9; to confirm)."},
      {"assess.comfort_limit_mps2", T::number, "", "m/s²", "> 0", "With vehicle models: the car-body acceleration limit b_v instead of assess.comfort_level's."},
      {"assess.comfort_deflection_ratio", T::number, "", "-", "> 0", "Passenger comfort by deck deflection (EN 1990 A2.4.4.3.2): L/delta read from Fig. A2.3 for the span and the line speed at b_v = 1 m/s2; viaduct applies the figure's factors (0.7 for one or two simply supported spans or two continuous spans, 0.9 for three or more continuous spans) and divides by b_v of assess.comfort_level. Unset: the check's rows say the limit is to be given (the figure is not carried; to confirm)."},
      {"assess.unloading_ratio_limit", T::number, "1.0", "-", "(0, 1]", "With vehicle models: the largest wheel unloading (P0 - Pmin)/P0 allowed; 1 (default): the wheels keep contact with the rail; a project's rule (e.g. 0.6) goes here."},
      {"assess.determinant_length_m", T::number, "", "m", "> 0", "Determinant length L_phi of Phi2/Phi3 and phi'' for every quantity (EN 1991-2 6.4.5.3, Table 6.2); unset: the quantity's span, or Table 6.2 for girders continuous over n spans on a continuous deck (to confirm)."},
      {"assess.hslm_b_n", T::integer, "", "-", ">= 1", "HSLM-B (spans under 7 m): number N of 170 kN forces, read from EN 1991-2 Fig. E.4 for the span."},
      {"assess.hslm_b_spacing_m", T::number, "", "m", "> 0", "HSLM-B: spacing d of the forces, read from EN 1991-2 Fig. E.4."},
  };
}

std::vector<KeySpec> fit_keys() {  // fit (viaduct fit; docs/fitting.md)
  return {
      {"fit.params[].key", T::string, "", "", "", "Numeric scenario key to fit, e.g. track.pad.k; its value in this scenario is the start (required)."},
      {"fit.params[].lower", T::number, "", "", "", "Lower bound, in the key's unit (required)."},
      {"fit.params[].upper", T::number, "", "", "", "Upper bound, > lower (required)."},
      {"fit.params[].scale", T::string, "\"auto\"", "", "auto|log|linear", "Solver coordinate: log (needs lower > 0; stiffness, mass, damping), linear, or auto = log when lower > 0."},
      {"fit.records[].file", T::string, "", "", "", "Measured record (CSV or UFF 58), relative to this file (required)."},
      {"fit.records[].map", T::string_list, "", "", "", "CHANNEL=STATION pairs: record channel fitted by a scenario station (required)."},
      {"fit.records[].speed_kmh", T::number, "", "km/h", "> 0", "The passage's speed (default: run.speed_kmh, which can then be fitted)."},
      {"fit.records[].train", T::string, "\"\"", "", "", "Train of the passage (default: the first of train.files)."},
      {"fit.modes", T::string, "", "", "", "modes.csv of viaduct modal-fit or viaduct oma (shapes.csv beside it), relative to this file: identified modes for the modal objective."},
      {"fit.modes_method", T::string, "\"lscf\"", "", "", "Which method's rows of modes.csv to fit (lscf, circle-fit, peak-picking; ssi-cov, fdd, efdd of viaduct oma)."},
      {"fit.weights.time", T::number, "", "-", ">= 0", "Weight of the filtered, aligned time-history misfit (default 1 with records, else 0)."},
      {"fit.weights.peak", T::number, "0.0", "-", ">= 0", "Weight of the peak and RMS misfit per channel."},
      {"fit.weights.envelope", T::number, "0.0", "-", ">= 0", "Weight of the windowed RMS envelope misfit."},
      {"fit.weights.spectrum", T::number, "0.0", "-", ">= 0", "Weight of the amplitude-spectrum misfit over the filter band."},
      {"fit.weights.modal", T::number, "", "-", ">= 0", "Weight of the frequency and mode-shape (MAC) misfit (default 1 with fit.modes, else 0)."},
      {"fit.weights.damping", T::number, "0.0", "-", ">= 0", "Weight of the damping misfit against identified damping ratios (fit.modes)."},
      {"fit.envelope_window_s", T::number, "0.25", "s", "> 0", "Envelope window."},
      {"fit.max_shift_s", T::number, "60.0", "s", "> 0", "Alignment of records and model: cross-correlation search range around the record start."},
      {"fit.starts", T::integer, "1", "-", ">= 1", "Solver starts: the scenario's values, then quasi-random points in the bounds."},
      {"fit.spectral_start", T::boolean, "true", "", "", "With the time or envelope objective, each start first fits the amplitude spectra (phase-free: converges from further away)."},
      {"fit.max_iterations", T::integer, "50", "-", ">= 1", "Iterations per start."},
      {"fit.max_time_s", T::number, "600.0", "s", "> 0", "Wall time per start; the solver stops with a reason."},
      {"fit.fd_step", T::number, "1e-4", "-", "> 0", "Forward-difference step in the normalised coordinates (at most 0.1)."},
  };
}

}  // namespace

const std::vector<KeySpec>& scenario_schema() {
  static const std::vector<KeySpec> schema = [] {
    std::vector<KeySpec> all;
    for (auto part : {general_keys(), bridge_keys(), track_keys(), train_keys(), irregularity_keys(), analysis_keys(), filter_keys(), station_keys(), run_keys(), sweep_keys(), assess_keys(), fit_keys()})
      all.insert(all.end(), part.begin(), part.end());
    return all;
  }();
  return schema;
}

}  // namespace viaduct::io
