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
/// Then the load effects, when recorded (study::load_effects: <station>_moment_Nm,
/// <station>_strain_ue, span<k>_start_rot_rad, span<k>_end_rot_rad).
void write_history_csv(const std::string& path, const study::RunResult& r);
/// history.csv's columns in its order, with its names (t_s first), pointing into `r`.
std::vector<std::pair<std::string, const Vector*>> history_columns(const study::RunResult& r);

/// envelope.csv: variant,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m; with the sweep's
/// `variants` when they vary keys, one column KEY_factor per varied key after `variant` (the
/// factor of that row's variant on KEY, 1 where it leaves KEY alone).
void write_envelope_csv(const std::string& path, const std::vector<study::EnvelopeRow>& rows,
                        const std::vector<study::Variant>& variants = {});
/// One column of a table in memory (the Python package's tables): text cells, numbers or flags.
struct TableColumn {
  enum class Kind { text, number, flag };
  std::string name;
  Kind kind = Kind::number;
  std::vector<std::string> cells;  ///< text
  std::vector<double> values;      ///< number
  std::vector<char> flags;         ///< flag (0 or 1)
};
/// envelope.csv's columns, in its order and with its names (write_envelope_csv), the numbers
/// unrounded (speed_kmh = speed × 3.6).
std::vector<TableColumn> envelope_columns(const std::vector<study::EnvelopeRow>& rows,
                                         const std::vector<study::Variant>& variants = {});
/// load_effects.csv's columns (write_quantities_csv): phi_dyn NaN where it is empty there.
std::vector<TableColumn> quantity_columns(const std::vector<study::QuantityRow>& rows, const std::vector<study::Variant>& variants);
/// vehicles.csv's columns of a sweep (write_vehicle_envelope_csv); contact_lost a flag.
std::vector<TableColumn> vehicle_envelope_columns(const std::vector<study::VehicleRow>& rows,
                                                 const std::vector<study::Variant>& variants);
/// load_effects.csv of a sweep with load effects: variant (KEY_factor columns as envelope.csv),
/// train, speed_kmh, quantity (its unit in its name), max, min, max_abs over the run,
/// quasi_static_max/min (the train crawling), phi_dyn (empty when the quasi-static is 0). The rows
/// are formatted on n_threads threads (the same file for any count).
void write_quantities_csv(const std::string& path, const std::vector<study::QuantityRow>& rows,
                          const std::vector<study::Variant>& variants, int n_threads = 1);
/// vehicles.csv of a sweep with vehicle models: variant (KEY_factor columns as envelope.csv),
/// train, speed_kmh, min_contact_N, max_contact_N, max_unloading_ratio, contact_lost (a wheel
/// left the rail, or its linear contact force went below zero), max_airborne_s,
/// max_body_acc_mps2 (unfiltered), body (the coach or axle where it occurs).
void write_vehicle_envelope_csv(const std::string& path, const std::vector<study::VehicleRow>& rows,
                                const std::vector<study::Variant>& variants);
/// failures.csv: variant,train,speed_kmh,error (header only when nothing failed)
void write_failures_csv(const std::string& path, const std::vector<study::CaseFailure>& failures);

/// governing.csv: per station the governing acceleration and deflection with the variant, train
/// and speed where each occurs (study::governing).
void write_governing_csv(const std::string& path, const std::vector<study::GoverningRow>& rows);

/// modes.csv: mode,frequency_hz,kind (deck, track or coupled),deck_mass_share (of the modal
/// mass, model::deck_mass_share), then per station <name>_deck (and <name>_rail) mode-shape
/// values (mass-normalised, so their scale is arbitrary but consistent).
void write_modes_csv(const std::string& path, const model::Modes& m, const model::Structure& s,
                     const std::vector<study::ResolvedStation>& stations);

/// A table of equally long columns: a header `names[0],names[1],...` and one row per index.
/// Throws InputError for mismatched lengths, SolverError on I/O failure and for a non-finite
/// value (named by column), which is never written. Written atomically.
void write_columns_csv(const std::string& path, const std::vector<std::string>& names,
                       const std::vector<Vector>& columns);

/// A table of text cells (already formatted), one row per entry of `rows`. A cell that reads as a
/// non-finite number (nan, inf) is refused with SolverError naming its column and row: a value
/// that is not known is an empty cell (table_cell), which pandas reads as NaN.
void write_table_csv(const std::string& path, const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows);

/// A table of columns (TableColumn: the Python package's tables) as write_table_csv writes it:
/// numbers by table_cell(value, significant) (NaN an empty cell), flags true/false, text as is.
void write_table_columns_csv(const std::string& path, const std::vector<TableColumn>& columns, int significant);

/// A number as a table cell: `significant` digits, or "" when it is NaN (not known: a damping a
/// method could not tell, a standard error not determined). An infinity stays one, and
/// write_table_csv refuses it.
std::string table_cell(double value, int significant = 10);

/// manifest.toml, what a result needs to be reproduced: [run] the command, the command line and
/// counts; [versions] viaduct, the git commit it was built from (when built from a checkout) and
/// the dependencies; [analysis_as_run] the settings that ran (after analysis.preset; a preset run's
/// [scenario] table still reads the keys' defaults); [[inputs]] every file read with its SHA-256;
/// [scenario] every resolved key.
struct Manifest {
  std::string command;                                      ///< e.g. "sweep"
  std::string command_line;                                 ///< the invocation as given (arguments quoted where needed)
  double wall_s = 0.0;                                      ///< [s]
  std::vector<std::pair<std::string, std::string>> extra;   ///< more [run] entries (already TOML values)
  std::vector<std::string> warnings;                         ///< [run] warnings = [...] when any (accuracy guards)
  std::vector<std::pair<std::string, std::string>> versions;///< more dependency versions (name, version)
  std::vector<std::pair<std::string, std::string>> as_run;  ///< [analysis_as_run] entries (TOML values)
  std::vector<std::string> inputs;  ///< files read besides the scenario's own (records, mode files)
  /// What `viaduct replay` runs again ([run] positional, arguments): the first positional as given
  /// (a scenario is replaced by the manifest itself), the options and further positionals but
  /// --set/--unset (folded into [scenario]), --out, --threads and --quiet.
  std::string positional;
  std::vector<std::string> arguments;
};
/// Writes the manifest; the scenario's files (the scenario, its components and train files) are
/// checksummed with `inputs`. `flat` may be null for commands without a scenario. SolverError on
/// I/O failure.
void write_manifest(const std::string& path, const Manifest& m, const FlatScenario* flat);
void write_manifest(const std::string& path, const Manifest& m, const FlatScenario& flat);
/// The [analysis_as_run] entries of `s` under their scenario keys (analysis.method, analysis.dt,
/// the method's options, the modal basis,
/// superposition, free vibration, load factor, filter.
std::vector<std::pair<std::string, std::string>> settings_as_run(const study::RunSettings& s);

/// SHA-256 of a file's bytes, 64 hex digits; InputError when it cannot be read.
std::string sha256_file(const std::string& path);
/// SHA-256 of bytes in memory.
std::string sha256_hex(const std::string& bytes);

/// The git commit viaduct was built from ("unknown" outside a checkout; "-dirty" appended when
/// tracked files had uncommitted changes at build time).
std::string git_commit();

/// `text` as the whole content of `path`, written atomically (report.md); SolverError on failure.
void write_text_file(const std::string& path, const std::string& text);

/// "viaduct x.y.z" version string.
std::string version();

}  // namespace viaduct::io
