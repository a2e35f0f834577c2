#pragma once
/// \file The passages workflow (`viaduct passages`, `viaduct.passages`): recorded passages named by
/// folders or tables, their trains resolved, the mapped channels read, the model's envelope and
/// each passage's check (study::run_passages), the warnings a user must read, and the tables
/// written. The command binds options to a PassagesRequest and prints; Python calls the same.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/passages.hpp"

namespace viaduct::io {

/// What `viaduct passages` is given beside the scenario.
struct PassagesRequest {
  /// Folders of records (their record files in name order) or tables (CSV: file[,train][,speed_kmh];
  /// files relative to the table). At least one.
  std::vector<std::string> records;
  std::vector<std::string> maps;  ///< CHANNEL=STATION, at least one; the first identifies the speed
  std::optional<std::string> train;  ///< the train of records without one (a scenario train or a train file)
  std::optional<double> v_min_kmh, v_max_kmh;  ///< identification range; default: the sweep's speeds
  double speed_band = 3.0, noise_band = 4.0;   ///< study::PassageOptions
  std::string zero = "keep";  ///< deflection and strain channels' zero (study::parse_zero)
  int threads = 1;
  ReadOptions read;  ///< how the record files are read (docs/records.md)
  /// Told each record file and what reading it converted and repaired (the CLI prints it); may be empty.
  std::function<void(const std::string&, const ImportReport&)> on_read;
  /// Told what was cut of a record for another channel's missing samples (valid_span); may be empty.
  std::function<void(const std::string&)> on_cut;
  ProgressSink progress;  ///< after each envelope case and each passage; may be empty
  LogSink log;            ///< IDA's messages; may be empty
};

/// The check's outcome: the study (passages in input order, then those whose record could not be
/// read) and what the command reports.
struct PassagesOutcome {
  study::PassageStudy study;
  std::vector<std::string> inputs;    ///< the record files, in the order given
  std::vector<std::string> warnings;  ///< what the user must read (the manifest's and stderr's)
  study::RunSettings settings;        ///< the scenario's settings (the manifest's [analysis_as_run])
  double speed_band = 3.0, noise_band = 4.0;
  std::size_t n_failed = 0;      ///< passages that failed
  std::size_t n_input_errors = 0;  ///< of which for their input (a record that cannot be read, ...)
};

/// Runs the check. InputError (naming the option) for a request that cannot run: no records or
/// maps, an unknown station or train, a scenario without sweep speeds; a record that cannot be
/// read is a failed passage and the others go on.
PassagesOutcome run_passages(const FlatScenario& flat, const PassagesRequest& request);

/// The tables, as their files name and order them: passages.csv (one row per passage and
/// channel), model_envelope.csv, passages_summary.csv (per station and quantity) and failures.csv.
/// Numbers unrounded (NaN where the file's cell is empty).
std::vector<TableColumn> passage_columns(const PassagesOutcome& r);
std::vector<TableColumn> passage_envelope_columns(const PassagesOutcome& r);
std::vector<TableColumn> passage_summary_columns(const PassagesOutcome& r);
std::vector<TableColumn> passage_failure_columns(const PassagesOutcome& r);

/// Writes the four tables into `dir` (numbers to 8 significant digits, flags true/false).
void write_passages_tables(const std::string& dir, const PassagesOutcome& r);

}  // namespace viaduct::io
