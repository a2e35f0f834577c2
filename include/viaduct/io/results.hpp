#pragma once
/// \file Tidy CSV outputs and the run manifest.

#include <string>
#include <utility>
#include <vector>

#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/study/sweep.hpp"

namespace viaduct::io {

/// history.csv: t_s, then per station <name>_disp_m, <name>_acc_mps2, <name>_acc_filt_mps2
/// (when filtered), <name>_rail_disp_m (deck stations with track). Rail stations write
/// <name>_rail_disp_m, <name>_rail_acc_mps2, <name>_rail_acc_filt_mps2. Throws SolverError on I/O failure.
void write_history_csv(const std::string& path, const study::RunResult& r);

/// envelope.csv: variant,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m
void write_envelope_csv(const std::string& path, const std::vector<study::EnvelopeRow>& rows);
/// failures.csv: variant,train,speed_kmh,error (header only when nothing failed)
void write_failures_csv(const std::string& path, const std::vector<study::CaseFailure>& failures);

/// modes.csv: mode,frequency_hz, then per station <name>_deck (and <name>_rail) mode-shape
/// values (mass-normalised, so their scale is arbitrary but consistent).
void write_modes_csv(const std::string& path, const model::Modes& m,
                     const std::vector<study::ResolvedStation>& stations);

/// A table of equally long columns: a header `names[0],names[1],...` and one row per index.
/// Throws InputError for mismatched lengths, SolverError on I/O failure.
void write_columns_csv(const std::string& path, const std::vector<std::string>& names,
                       const std::vector<Vector>& columns);

/// A table of text cells (already formatted), one row per entry of `rows`.
void write_table_csv(const std::string& path, const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows);

/// manifest.toml: command, version, dependency versions, wall time, counts, resolved scenario.
struct Manifest {
  std::string command;                                      ///< e.g. "sweep"
  double wall_s = 0.0;                                      ///< [s]
  std::vector<std::pair<std::string, std::string>> extra;   ///< more [run] entries (already TOML values)
  std::vector<std::pair<std::string, std::string>> versions;///< more dependency versions (name, version)
};
void write_manifest(const std::string& path, const Manifest& m, const FlatScenario& flat);

/// "viaduct x.y.z" version string.
std::string version();

}  // namespace viaduct::io
