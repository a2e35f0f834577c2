// The scenario schema: every key with type, default, unit, constraint and doc (DESIGN.md §3.9).
#include "viaduct/io/scenario.hpp"

namespace viaduct::io {

const std::vector<KeySpec>& scenario_schema() {
  using T = ValueType;
  static const std::vector<KeySpec> schema = {
      {"title", T::string, "\"\"", "", "", "Free text shown in outputs."},
      {"description", T::string, "\"\"", "", "", "Free text: what the scenario studies and where its numbers come from."},
      // bridge
      {"bridge.file", T::string, "", "", "", "Bridge component file; its keys are read under bridge. (path relative to the referencing file)."},
      {"bridge.notes", T::string, "\"\"", "", "", "Free text: sources and readings of the parameters."},
      {"bridge.span_lengths", T::number_list, "", "m", "> 0", "Length of each simply supported span, in order along the line (required)."},
      {"bridge.EI", T::number_or_list, "", "N·m²", "> 0", "Bending stiffness: one value for all spans or one per span (required)."},
      {"bridge.mass_per_m", T::number_or_list, "", "kg/m", "> 0", "Mass per metre: one value or one per span (required)."},
      {"bridge.mass_includes_track", T::boolean, "false", "", "", "true: mass_per_m includes the track on the deck; a modelled track's mass per metre is then taken off the deck."},
      {"bridge.added_mass_per_m", T::number, "0.0", "kg/m", ">= 0", "Non-structural mass added to every span."},
      {"bridge.element_size", T::number, "0.5", "m", "> 0", "Target deck element length (each span gets a whole number of equal elements)."},
      {"bridge.bearings.rigid", T::boolean, "true", "", "", "true: span ends fixed vertically; false: springs k and dashpots c."},
      {"bridge.bearings.k", T::number, "0.0", "N/m", ">= 0", "Vertical stiffness of each bearing (span end) when not rigid; must then be > 0."},
      {"bridge.bearings.c", T::number, "0.0", "N·s/m", ">= 0", "Vertical damping of each bearing when not rigid."},
      {"bridge.damping.kind", T::string, "\"modal\"", "", "none|modal|rayleigh", "Structural damping of the bridge: one ratio for every span mode, or Rayleigh through two (frequency, ratio) pairs."},
      {"bridge.damping.ratio", T::number, "0.0", "-", "[0, 1)", "modal: ratio of critical damping for every span mode (0.01565 = 1.565 %)."},
      {"bridge.damping.f1_hz", T::number, "0.0", "Hz", ">= 0", "rayleigh: first frequency."},
      {"bridge.damping.ratio1", T::number, "0.0", "-", "[0, 1)", "rayleigh: damping ratio at f1_hz."},
      {"bridge.damping.f2_hz", T::number, "0.0", "Hz", ">= 0", "rayleigh: second frequency (> f1_hz)."},
      {"bridge.damping.ratio2", T::number, "0.0", "-", "[0, 1)", "rayleigh: damping ratio at f2_hz."},
      // track
      {"track.file", T::string, "", "", "", "Track component file; its keys are read under track. Without any track key the model has no track."},
      {"track.notes", T::string, "\"\"", "", "", "Free text: sources and readings of the parameters."},
      {"track.approach_length", T::number, "20.0", "m", ">= 0", "Track before the bridge (axles enter at its start); rounded down to whole sleeper bays with exit_length."},
      {"track.exit_length", T::number, "20.0", "m", ">= 0", "Track after the bridge."},
      {"track.sleeper_spacing", T::number, "0.6", "m", "> 0", "Distance between sleepers (rail seats)."},
      {"track.rail_elements_per_bay", T::integer, "1", "-", ">= 1", "Rail beam elements between two sleepers."},
      {"track.rail.E", T::number, "", "Pa", "> 0", "Rail Young's modulus (required)."},
      {"track.rail.I", T::number, "", "m⁴", "> 0", "Rail second moment of area (required)."},
      {"track.rail.A", T::number, "", "m²", "> 0", "Rail cross-section area (required)."},
      {"track.rail.density", T::number, "7850.0", "kg/m³", "> 0", "Rail density."},
      {"track.sleeper_mass", T::number, "", "kg", "> 0", "Sleeper mass per rail seat (required)."},
      {"track.ballast_mass", T::number, "", "kg", "> 0", "Vibrating ballast mass per rail seat (required)."},
      {"track.pad.k", T::number, "", "N/m", "> 0", "Rail pad stiffness per rail seat (required)."},
      {"track.pad.c", T::number, "0.0", "N·s/m", ">= 0", "Rail pad damping per rail seat."},
      {"track.ballast.k", T::number, "", "N/m", "> 0", "Ballast stiffness per rail seat, sleeper to ballast mass (required)."},
      {"track.ballast.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast damping per rail seat."},
      {"track.shear.k", T::number, "0.0", "N/m", ">= 0", "Ballast shear stiffness between neighbouring ballast masses."},
      {"track.shear.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast shear damping between neighbouring ballast masses."},
      {"track.subgrade.k", T::number, "", "N/m", "> 0", "Subgrade stiffness per rail seat off the bridge, ballast mass to ground (required)."},
      {"track.subgrade.c", T::number, "0.0", "N·s/m", ">= 0", "Subgrade damping per rail seat off the bridge."},
      {"track.subgrade_on_bridge.k", T::number, "", "N/m", "> 0", "Ballast mass to deck stiffness per rail seat on the bridge (required)."},
      {"track.subgrade_on_bridge.c", T::number, "0.0", "N·s/m", ">= 0", "Ballast mass to deck damping per rail seat on the bridge."},
      // trains
      {"train.files", T::string_list, "", "", "", "Train files (.toml: hslm, regular or axles; .csv: position_m,load_kN), relative to the referencing file (required)."},
      {"train.load_factor", T::number, "1.0", "-", "> 0", "Multiplies every axle load (0.5: one rail of a half-deck model carries half of each axle)."},
      // analysis
      {"analysis.dt", T::number, "0.001", "s", "> 0", "Newmark time step (also the recording interval)."},
      {"analysis.beta", T::number, "0.25", "-", "> 0", "Newmark β (0.25: constant average acceleration)."},
      {"analysis.gamma", T::number, "0.5", "-", ">= 0.5", "Newmark γ."},
      {"analysis.alpha", T::number, "0.0", "-", "[-1/3, 0]", "HHT-α (0: plain Newmark); with alpha use beta = (1-alpha)²/4, gamma = (1-2 alpha)/2."},
      {"analysis.preset", T::string, "\"\"", "", "|fast|default|reference", "Named speed/accuracy setting (docs/accuracy.md): sets analysis.method, analysis.dt and modal.* from the band edge f_c (filter.high_hz, or 30 Hz); keys given explicitly override it."},
      {"analysis.method", T::string, "\"newmark\"", "", "newmark|modal|ida", "newmark: fixed-step integration of the whole model; modal: superposition of its modes up to modal.max_frequency_hz / modal.n_modes, solved exactly per step; ida: adaptive BDF of the whole model (SUNDIALS IDA, ida.* tolerances), sampled every analysis.dt (docs/accuracy.md)."},
      {"ida.rtol", T::number, "1e-6", "-", "[1e-12, 0.1]", "ida: relative tolerance."},
      {"ida.atol_disp_m", T::number, "1e-10", "m", "> 0", "ida: absolute tolerance of displacements."},
      {"ida.atol_vel_mps", T::number, "1e-8", "m/s", "> 0", "ida: absolute tolerance of velocities."},
      {"ida.max_order", T::integer, "5", "-", "[1, 5]", "ida: highest BDF order."},
      {"analysis.superposition", T::string, "\"direct\"", "", "direct|unit-response", "direct: one run per train and speed; unit-response: one run of a unit axle per speed, superposed over every train's axles (linear models only; same answer, much less work with several trains)."},
      {"modal.n_modes", T::integer, "0", "-", ">= 0", "modal: keep at most this many of the lowest modes (0: no count limit)."},
      {"modal.max_frequency_hz", T::number, "0.0", "Hz", ">= 0", "modal: keep the modes up to this frequency (0: no frequency limit)."},
      {"modal.static_correction", T::boolean, "true", "", "", "modal: add the quasi-static response of the dropped modes to displacements (mode-acceleration method)."},
      {"analysis.free_vibration_s", T::number, "1.0", "s", ">= 0", "Time simulated after the last axle has left the model."},
      // filter
      {"filter.enabled", T::boolean, "true", "", "", "Filter accelerations before taking maxima."},
      {"filter.band", T::string, "\"bandpass\"", "", "lowpass|highpass|bandpass", "Filter band."},
      {"filter.order", T::integer, "3", "-", ">= 1", "Chebyshev I order N (band-pass: 2N poles), SciPy's convention."},
      {"filter.ripple_db", T::number, "0.5", "dB", "> 0", "Passband ripple; edges are where one pass drops below -ripple_db (zero-phase: -2·ripple_db)."},
      {"filter.low_hz", T::number, "1.0", "Hz", "> 0", "Lower band edge (highpass, bandpass)."},
      {"filter.high_hz", T::number, "30.0", "Hz", "> 0", "Upper band edge (lowpass, bandpass); must be below 1/(2·dt)."},
      // stations
      {"stations[].name", T::string, "", "", "", "Station name, unique; used in column names (required)."},
      {"stations[].span", T::integer, "", "-", ">= 1", "Span number (1-based) of a deck station; give at or x with it."},
      {"stations[].at", T::number, "", "-", "[0, 1]", "Deck station position as a fraction of the span length."},
      {"stations[].x", T::number, "", "m", ">= 0", "Deck station position from the span's left end (instead of at)."},
      {"stations[].track_x", T::number, "", "m", "", "Rail station at this global x (x = 0 at the bridge start), instead of span."},
      // run
      {"run.speed_kmh", T::number, "", "km/h", "> 0", "Default speed of `viaduct run` (--speed-kmh overrides)."},
      // sweep
      {"sweep.speeds_kmh", T::number_list, "", "km/h", "> 0", "Explicit list of speeds."},
      {"sweep.speed_min_kmh", T::number, "", "km/h", "> 0", "Range of speeds with speed_max_kmh and speed_step_kmh."},
      {"sweep.speed_max_kmh", T::number, "", "km/h", "> 0", "Last speed of the range (included when on the step grid)."},
      {"sweep.speed_step_kmh", T::number, "", "km/h", "> 0", "Step of the range."},
      {"sweep.speed_min_mps", T::number, "", "m/s", "> 0", "Evenly spaced speeds with speed_max_mps and n_speeds (both ends included)."},
      {"sweep.speed_max_mps", T::number, "", "m/s", "> 0", "Last speed of the evenly spaced set."},
      {"sweep.n_speeds", T::integer, "", "-", ">= 1", "Number of evenly spaced speeds."},
      {"sweep.mode", T::string, "\"one-at-a-time\"", "", "one-at-a-time|grid|reference", "one-at-a-time: each variant key alone with the others at reference; grid: every combination; reference: ignore the variants."},
      {"sweep.variants[].key", T::string, "", "", "", "Numeric scenario key to vary, e.g. track.pad.k (required)."},
      {"sweep.variants[].label", T::string, "\"\"", "", "", "Short name in outputs, e.g. Kp (default: the key)."},
      {"sweep.variants[].factors", T::number_list, "", "-", ">= 0", "Multipliers of the reference value (required)."},
  };
  return schema;
}

}  // namespace viaduct::io
