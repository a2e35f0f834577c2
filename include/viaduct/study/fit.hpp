#pragma once
/// \file Model updating: scenario parameters fitted to measured records and identified modes by
/// bounded nonlinear least squares (docs/fitting.md).
///
/// The parameters are any numeric scenario keys; the caller supplies `FitProblem::scenario_at`,
/// which turns a set of values into a resolved Scenario (the CLI does it through io's flat
/// scenario, so every key the schema declares can be fitted). Each evaluation builds the model
/// at the trial values, simulates every record's passage and forms the residuals of the chosen
/// objectives; the solver (Ceres, Levenberg–Marquardt with bounds) works in normalised
/// coordinates z ∈ [0, 1] (logarithmic for positive parameters), with finite-difference
/// Jacobians whose columns are computed in parallel.
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>
#include "viaduct/core/types.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::study {

enum class ParameterScale {
  linear,  ///< z = (p − lower) / (upper − lower)
  log,     ///< z = ln(p / lower) / ln(upper / lower); needs lower > 0 (stiffness, mass, damping)
};

/// One fitted scenario key.
struct FitParameter {
  std::string key;      ///< scenario key, e.g. "track.pad.k" (for reports)
  std::string unit;     ///< SI unit of the key (for reports)
  double lower = 0.0;   ///< bound, < upper
  double upper = 0.0;   ///< bound
  double initial = 0.0; ///< start of the first run, within [lower, upper]
  ParameterScale scale = ParameterScale::log;
};

/// One record channel fitted by one model station.
struct FitChannel {
  std::string name;          ///< record channel (for reports)
  std::string station;       ///< scenario station name
  bool acceleration = true;  ///< true: the station's acceleration (filtered); false: its deflection (unfiltered)
  bool strain = false;       ///< the station's strain in microstrain (<station>_strain_ue: stations[].fibre_m), unfiltered
  bool velocity = false;     ///< with acceleration = true: the station's velocity (a geophone), filtered as accelerations are
  double scale = 1.0;        ///< model SI value → channel unit (1 for records read by io: they are in SI)
  Vector samples;            ///< as measured, in the channel unit, finite
};

/// One measured passage.
struct FitRecord {
  std::string name;       ///< e.g. the file (for reports)
  double fs_hz = 0.0;     ///< [Hz] sampling rate, > 0
  double t0_s = 0.0;      ///< [s] time of the first sample
  std::string train;      ///< scenario train name (empty: the first)
  double speed = 0.0;     ///< [m/s] the passage's speed; 0: the scenario's run speed (fittable as run.speed_kmh)
  std::vector<FitChannel> channels;  ///< at least one
};

/// Identified modes to fit (frequencies and real shapes at named sensors).
struct ModalTarget {
  std::vector<std::string> sensors;  ///< scenario station names of the shape entries
  struct Mode {
    double frequency_hz = 0.0;  ///< [Hz] > 0
    Vector shape;               ///< one real entry per sensor; empty: frequency only
    double damping_ratio = std::numeric_limits<double>::quiet_NaN();  ///< [-] identified; NaN: unknown
  };
  std::vector<Mode> modes;  ///< at least one
};

/// Weights of the objectives (0 leaves an objective out). Each objective is normalised to a
/// relative misfit, so weights of 1 make them comparable:
///   time      Σ(m − y)² / Σy² per channel, filtered, aligned
/// Every record objective compares on the record's grid after aligning the model by the shift
/// that maximises the cross-correlation of the record's channels (re-aligned at every trial point).
///   peak      (max|m| / max|y| − 1)² and (rms m / rms y − 1)² per channel
///   envelope  windowed RMS envelopes, Σ(e_m − e_y)² / Σe_y² per channel, aligned
///   spectrum  Hann amplitude spectra over the filter band, Σ(A_m − A_y)² / ΣA_y² per channel
///   modal     (f_model / f_id − 1)² and 1 − MAC per identified mode (paired by MAC, or by
///             frequency without shapes)
///   damping   (ζ_model / ζ_id − 1)² per identified mode with a damping ratio, ζ_model = φᵀCφ / (2ω)
///             of the paired undamped mode (mass-normalised φ: exact for proportional damping)
struct FitWeights {
  double time = 1.0, peak = 0.0, envelope = 0.0, spectrum = 0.0, modal = 0.0, damping = 0.0;
  bool any_record_term() const { return time > 0 || peak > 0 || envelope > 0 || spectrum > 0; }
  bool is_valid(std::string* why) const;
};

/// One iteration of one start (also the progress callback's argument).
struct FitTracePoint {
  int start = 0;           ///< 0: from the initial values; then the multi-start points
  int stage = 0;           ///< 0: the objectives asked for; 1: the spectral pre-stage (FitOptions::spectral_start)
  int iteration = 0;       ///< 0: the start point
  double cost = 0.0;       ///< ½ Σ r² of the stage's objectives (weighted, normalised residuals)
  std::vector<double> values;  ///< parameter values
};

struct FitOptions {
  FitWeights weights;
  double envelope_window_s = 0.25;  ///< [s] envelope window, > 0
  /// Deflection and strain channels' zero (comparison.hpp; keep: a warning when the record
  /// before the train's entry is offset).
  ZeroSpec zero;
  double max_shift_s = 60.0;        ///< [s] alignment search range (record time of the model's t = 0 from t0 − this to t0 + this), > 0
  int starts = 1;                   ///< 1: from the initial values only; more: plus quasi-random points (Halton) in the box
  /// With the time or envelope objective: each start first fits the amplitude spectra (plus the
  /// modal objective if weighted), which do not depend on phase and converge from further away
  /// (a train speed 5 % off, a stiffness 20 % off), then the objectives asked for from there.
  bool spectral_start = true;
  int max_iterations = 50;          ///< per start, >= 1
  double max_time_s = 600.0;        ///< [s] per start, > 0: the solver stops with a reason
  double function_tolerance = 1e-8; ///< relative cost change that ends a start, > 0
  double parameter_tolerance = 1e-8;///< relative step that ends a start, > 0
  double gradient_tolerance = 1e-10;///< > 0
  double fd_step = 1e-4;            ///< forward-difference step in normalised coordinates, (0, 0.1]
  int threads = 1;                  ///< Jacobian columns in parallel, >= 1
  double max_relative_std = 0.5;    ///< a parameter whose standard error exceeds this fraction of its value is flagged, > 0
  double max_correlation = 0.95;    ///< pairs correlated beyond this are flagged, (0, 1)
  std::function<void(const FitTracePoint&)> progress;  ///< after each iteration (optional)
  bool is_valid(std::string* why) const;
};

/// Builds the scenario for parameter values (same order as FitProblem::params). Called from
/// several threads at once; throws InputError for values the scenario rejects.
using ScenarioBuilder = std::function<Scenario(const std::vector<double>& values)>;

struct FitProblem {
  std::vector<FitParameter> params;     ///< at least one
  std::vector<FitRecord> records;       ///< needed by the record objectives
  std::optional<ModalTarget> modal;     ///< needed by the modal and damping objectives
  ScenarioBuilder scenario_at;
};

/// Residual sums of one objective for one record channel (or identified mode) before and after.
struct FitTerm {
  std::string objective;  ///< time | peak | envelope | spectrum | modal | damping
  std::string record;     ///< record name ("" for modal terms)
  std::string channel;    ///< channel or "mode k (f Hz)"
  double before = 0.0;    ///< weighted Σ r² at the initial values
  double after = 0.0;     ///< at the estimate
};

/// Record against model for the plots: filtered record and aligned model on the record grid.
struct FitOverlay {
  std::string record, channel;
  Vector t;                     ///< [s] record time
  Vector measured, initial, fitted;
};

/// Identified mode against the model's paired mode.
struct ModalPair {
  double frequency_hz = 0.0;                       ///< identified
  double model_before_hz = 0.0, model_after_hz = 0.0;
  double mac_before = 0.0, mac_after = 0.0;        ///< NaN without shapes
  double damping_ratio = 0.0;                      ///< identified (NaN: unknown)
  double model_damping_before = 0.0, model_damping_after = 0.0;  ///< φᵀCφ / (2ω) of the paired mode
};

struct FitResult {
  enum class Status { converged, no_convergence, failed };
  Status status = Status::failed;
  std::string message;               ///< the solver's reason (also why it did not converge)
  std::vector<double> initial;       ///< parameter values at the start
  std::vector<double> estimate;      ///< best values found
  std::vector<double> std_error;     ///< from the Jacobian at the estimate (inf: undetermined)
  Matrix correlation;                ///< n_params × n_params (NaN rows for undetermined parameters)
  std::vector<double> sensitivity;   ///< |∂r/∂z| column norms, relative to the largest
  std::vector<bool> at_bound;        ///< estimate on a bound
  std::vector<bool> determined;      ///< not flagged by any warning
  std::vector<std::string> warnings; ///< undetermined, correlated or bound-limited parameters
  std::vector<double> shift_s;       ///< per record at the estimate: record time of the model's t = 0
  double cost_initial = 0.0, cost_final = 0.0;  ///< ½ Σ r²
  int n_residuals = 0, iterations = 0, evaluations = 0, simulations = 0;
  int best_start = 0;
  std::vector<double> start_costs;   ///< final cost of each start
  double wall_s = 0.0;
  std::vector<FitTracePoint> trace;  ///< every iteration of every start
  std::vector<FitTerm> terms;
  std::vector<FitOverlay> overlays;  ///< one per record channel (time-history objectives)
  std::vector<ModalPair> modal_pairs;
};

const char* to_string(FitResult::Status s);

/// Fits problem.params. InputError for an inconsistent problem (bounds, initial values outside
/// them, log scale with lower <= 0, missing records or modal target for a weighted objective,
/// unknown stations or trains, records shorter than their filter allows); SolverError when the
/// initial values cannot be simulated. A start that fails later or reaches max_iterations /
/// max_time_s ends with status and message saying so.
FitResult fit(const FitProblem& problem, const FitOptions& options);

/// Normalised coordinate of `value` for `p` and back (exposed for tests).
double to_unit(const FitParameter& p, double value);
double from_unit(const FitParameter& p, double z);

}  // namespace viaduct::study
