#pragma once
/// \file Model updating from files: fitted scenario keys, the scenario's [fit] section,
/// identified modes (modal-fit's modes.csv / shapes.csv) and the fitted scenario written back.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>
#include "viaduct/io/record.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/fit.hpp"

namespace viaduct::io {

/// A fitted parameter from its key, bounds and scale ("auto", "log" or "linear"); the start is the
/// key's value in `flat`. InputError naming `where` (and the key) when the key is unknown, not a
/// single number, the bounds are empty or the start lies outside them.
study::FitParameter fit_parameter(const FlatScenario& flat, const std::string& key, double lower, double upper,
                                  const std::string& scale, const SourceLocation& where);

/// Parses a command-line parameter "KEY=LO:HI" or "KEY=LO:HI:log|linear".
study::FitParameter parse_fit_parameter(const FlatScenario& flat, const std::string& text);

/// The scenario's [fit] section.
struct FitDeclaration {
  std::vector<study::FitParameter> params;
  struct RecordSpec {
    std::string file;
    std::vector<std::string> map;  ///< CHANNEL=STATION
    double speed_kmh = 0.0;        ///< 0: run.speed_kmh
    std::string train;
    SourceLocation where;          ///< of the file key
  };
  std::vector<RecordSpec> records;
  std::string modes;                ///< "" when not declared
  std::string modes_method = "lscf";
  study::FitOptions options;        ///< weights left at -1 when not given (the CLI picks the defaults)
};
FitDeclaration fit_declaration(const FlatScenario& flat);

/// Builds scenarios with the parameter keys set (thread-safe: copies `flat`).
study::ScenarioBuilder scenario_builder(const FlatScenario& flat, const std::vector<study::FitParameter>& params);

/// Identified modes read from modal-fit's modes.csv (`path`: the file or its directory) for one
/// method, with damping ratios and the real parts of the shapes from shapes.csv beside it when
/// present (sensor names: the FRF response names); or one mode (mean frequency, envelope-fit
/// damping, no shape) from viaduct decay's decay_summary.csv (`path`: the file, or a directory
/// holding it and no modes.csv; `method` is then unused). InputError with file and line.
study::ModalTarget read_identified_modes(const std::string& path, const std::string& method);

/// Writes `flat` as a scenario file loadable on its own (component files merged, paths absolute,
/// defaults left out), with `comment` lines at the top. SolverError on I/O failure.
void write_scenario_toml(const std::string& path, const FlatScenario& flat, const std::string& comment);

/// What `viaduct fit` is given beside the scenario: each present item replaces the [fit]
/// section's (DESIGN.md §3.10: the CLI only fills this).
struct FitRequest {
  std::vector<std::string> params;      ///< "KEY=LO:HI[:log|linear]"; empty: [[fit.params]]
  std::vector<std::string> records;     ///< record files; empty: [[fit.records]]
  std::vector<std::string> maps;        ///< CHANNEL=STATION for every record, RESPONSE=STATION for modes
  std::vector<double> speeds_kmh;       ///< [km/h] one for all records or one per record
  std::string train;                    ///< "": the first of train.files
  std::optional<std::string> modes;     ///< identified modes (read_identified_modes)
  std::optional<std::string> modes_method;
  std::vector<std::string> weights;     ///< OBJECTIVE=W; empty: declared, else time = 1 with records, modal = 1 with modes
  std::optional<int> starts, max_iterations;
  std::optional<double> max_time_s;     ///< [s]
  bool no_spectral_start = false;
  std::string zero = "keep";            ///< deflection and strain channels' zero: keep, pre-entry or START:END (study::parse_zero)
  int threads = 1;
  ReadOptions read;                     ///< how the record files are read (docs/records.md)
  /// Told each record file and what reading it converted and repaired (the CLI prints it); may be empty.
  std::function<void(const std::string&, const ImportReport&)> on_read;
};

/// The problem and options of a fit: the request merged with the scenario's [fit] section, the
/// records read (channel units checked), the identified modes' responses mapped onto stations,
/// default weights, every rule checked (FitOptions::is_valid included). problem.scenario_at is
/// set. InputError naming the option or key.
std::pair<study::FitProblem, study::FitOptions> fit_setup(const FlatScenario& flat, const FitRequest& request);

/// The outputs of a fit into `dir`: fit.csv (estimates, standard errors, flags),
/// fit_correlation.csv, fit_trace.csv, fit_residuals.csv, fit_time.csv, fit_modes.csv, fit.toml
/// (the summary) and fitted.toml (the scenario `flat` from `scenario_path` with the estimates).
/// SolverError on I/O failure.
void write_fit_outputs(const std::string& dir, const std::string& scenario_path, const FlatScenario& flat,
                       const study::FitProblem& problem, const study::FitOptions& options, const study::FitResult& r);

}  // namespace viaduct::io
