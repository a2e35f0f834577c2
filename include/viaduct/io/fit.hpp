#pragma once
/// \file Model updating from files: fitted scenario keys, the scenario's [fit] section,
/// identified modes (modal-fit's modes.csv / shapes.csv) and the fitted scenario written back.
#include <string>
#include <vector>
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

}  // namespace viaduct::io
