#pragma once
// Shared command-line plumbing of the viaduct tool: common options, exit codes, progress.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <boost/program_options.hpp>

#include "viaduct/core/error.hpp"
#include "viaduct/core/log.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/sweep.hpp"

namespace viaduct::cli {

namespace po = boost::program_options;

enum Exit { ok = 0, runtime_failure = 1, usage_error = 2 };

/// Options every subcommand takes.
struct Common {
  std::string scenario;
  std::vector<std::string> more;  ///< further positional arguments (Command::many_positionals)
  std::vector<std::string> set;
  std::vector<std::string> unset;  ///< --unset KEY: keys (or tables) removed from the scenario
  std::string out = "out";
  int threads = 1;
  bool quiet = false;
  std::string command_line;  ///< the invocation, for manifests ("viaduct sweep ... --threads 2")
  /// The invocation's options and further positionals without --set, --unset, --out, --threads,
  /// --quiet and the first positional: what `viaduct replay` passes again (manifest [run] arguments).
  std::vector<std::string> replay_arguments;
  io::ReadOptions read;      ///< how to read record files (Command::reads_records)
  std::string command;       ///< the subcommand's name
};

/// A subcommand: name, one-line summary, help text with sample runs, and its body.
struct Command {
  std::string name;
  std::string summary;
  std::string usage_and_samples;  ///< printed after the options; lines "  viaduct ..." are tested
  std::function<void(po::options_description&)> add_options;
  std::function<int(const Common&)> run;
  bool needs_scenario = true;
  std::string positional = "SCENARIO";  ///< what the positional argument is (Common::scenario holds it)
  bool many_positionals = false;        ///< accept more positionals (Common::more)
  bool reads_records = false;           ///< takes the options of reading logger files (Common::read)
};

/// Binds a command's options to a struct of its own: `declare` adds each option writing into a
/// field of `Options` (value(), optional_value(), po::bool_switch(&field)), `body` runs with the
/// filled struct. After parsing, no option is looked up by name.
template <class Options, class Result>
void bind(Command& c, void (*declare)(po::options_description&, Options&), Result (*body)(const Common&, const Options&)) {
  auto opts = std::make_shared<Options>();
  c.add_options = [opts, declare](po::options_description& d) { declare(d, *opts); };
  c.run = [opts, body](const Common& o) { return body(o, *opts); };
}

/// bind(), then the command: the last line of every X_command().
template <class Options, class Result>
Command bound(Command c, void (*declare)(po::options_description&, Options&), Result (*body)(const Common&, const Options&)) {
  bind(c, declare, body);
  return c;
}

/// What every command sets first: its name, what its positional argument is, its summary.
Command command(std::string name, std::string positional, std::string summary);
/// The same for a command that reads logger files (Command::reads_records).
Command record_command(std::string name, std::string positional, std::string summary);

/// Channels named by --channel (every channel when none).
std::vector<std::size_t> selected(const io::Record& r, const std::vector<std::string>& channels);
using io::record_files_in;  // io/record.hpp
/// --channel for the record commands (repeatable).
void add_channel_option(po::options_description& d, std::vector<std::string>& channels);

/// --zero, the zero of deflection and strain channels (study::parse_zero): compare, fit,
/// passages, speed --model (`prefix` says when it applies).
void add_zero_option(po::options_description& d, std::string& zero, const std::string& prefix = "");

/// An option writing into `field`, whose initial value is the default shown by --help (numbers
/// as written: 0.15, not 0.14999999999999999).
template <class T>
po::typed_value<T>* value(T& field) {
  if constexpr (std::is_floating_point_v<T>) return po::value<T>(&field)->default_value(field, format_number(field));
  else return po::value<T>(&field)->default_value(field);
}

/// An option without a default: `field` holds a value only when the option was given.
template <class T>
po::typed_value<T>* optional_value(std::optional<T>& field) {
  return po::value<T>()->notifier([&field](const T& v) { field = v; });
}

/// A repeatable option collecting its values into `field`.
inline po::typed_value<std::vector<std::string>>* list_value(std::vector<std::string>& field) {
  return po::value<std::vector<std::string>>(&field)->composing();
}

/// Parses argv for `cmd`, handles --help, and maps exceptions to exit codes (2 input/usage,
/// 1 runtime). Prints errors on stderr as "viaduct <cmd>: error: ...".
int dispatch(const Command& cmd, int argc, char** argv);

/// The record at `path` read with the command's --time-column, --rate-hz, --unit, --fill-max-s
/// and --long-gaps; what was converted or repaired is printed on stderr (notes unless --quiet,
/// repairs always, as warnings).
io::Record read_record(const std::string& path, const Common& o);
/// The record cut to the longest piece where the channels `used` have values (io::valid_span),
/// what was cut printed as a warning.
io::Record usable(const io::Record& r, const std::vector<std::size_t>& used, const Common& o);
/// What reading `path` converted and repaired, printed as read_record prints it.
void print_import_report(const std::string& path, const io::ImportReport& report, const Common& o);

/// The command's scenario with --set and --unset applied (io::load_flat).
io::FlatScenario load_scenario(const Common& o);

using study::require_strain_fibre;  // the stations of --map and --channel (study/simulation.hpp)
using study::station_index;

/// Creates the output directory (throws SolverError when it cannot).
void make_out_dir(const std::string& dir);

/// The speed of a one-speed command [m/s]: --speed-kmh, else run.speed_kmh; InputError otherwise.
double speed_of(const study::Scenario& sc, const std::optional<double>& speed_kmh);
/// The train named by --train, else the scenario's first; InputError listing the names.
const load::Train& train_of(const study::Scenario& sc, const std::optional<std::string>& name);

/// Progress printer on stderr: a live line on a terminal, every 10 % otherwise, from 2 s on (short
/// work prints none); silent if quiet.
ProgressSink progress_printer(const std::string& what, bool quiet, const std::string& unit = "cases");

/// Versions of the libraries only the tool links (for manifests).
std::vector<std::pair<std::string, std::string>> tool_versions();

/// The manifest every command writes into --out (io::write_manifest): the command, its command
/// line and the tool's versions filled in.
io::Manifest start_manifest(const Common& o, const std::string& command, std::vector<std::string> inputs = {});
/// A record command's outputs: OUT/file (a record, or a table with its header), then the
/// manifest naming the record read (with the command's warnings, for a table).
void write_record_outputs(const Common& o, const std::string& file, const io::Record& out);
void write_table_outputs(const Common& o, const std::string& file, const std::vector<std::string>& header,
                         const std::vector<std::vector<std::string>>& rows, const std::vector<std::string>& warnings = {});

/// Prints each warning on stderr ("viaduct COMMAND: warning: ..."), also with --quiet.
void print_warnings(const std::string& command, const std::vector<std::string>& warnings);

/// The first `n` modes, one line each: frequency, kind (deck, track, coupled), deck mass share.
void print_first_modes(const model::Structure& s, const model::Modes& m, Index n, const char* prefix = "  ");

/// "f1 = 10.011 Hz (span 1, first bending)": the deck's first bending frequency, or why it is
/// not known. The deck modes found go to `modes` when given.
std::string describe_f1(const model::Structure& s, std::vector<model::DeckMode>* modes = nullptr);

/// The resonance speeds v = f1·d/j (j = 1, 2, ...) of each train within [v_min, v_max] [m/s],
/// one line per train with its characteristic distance d (load::characteristic_distance).
void print_resonance_speeds(double f1_hz, const std::vector<load::Train>& trains, double v_min, double v_max);

/// After a sweep (viaduct sweep, assess): prints each failed case on stderr and returns the exit
/// code — 0 without failures, 2 when every case failed on its input (as `run` exits with the
/// same value), 1 otherwise (a partial result, failures.csv).
int sweep_exit_code(const std::string& command, const std::string& scenario, const study::SweepResult& r);

/// The governing case of each station, at a glance (viaduct sweep, merge).
void print_governing(const std::vector<study::GoverningRow>& gov, bool with_variant);

/// Message printer for the library's log sink (stderr, "viaduct: warning: ...").
LogSink log_printer(bool quiet);

/// Options of sampled studies (viaduct sweep with sweep.mode = "sample").
struct SampleCliOptions {
  std::string shard;    ///< "K/N" or empty
  bool resume = false;
};
/// viaduct sweep on a sampled study (cmd_sample.cpp).
int run_sampled_sweep(const Common& o, const io::FlatScenario& flat, const SampleCliOptions& opts);

Command check_command();
Command modes_command();
Command run_command();
Command ladder_command();
Command sweep_command();
Command schema_command();
Command filter_command();
Command spectrum_command();
Command peaks_command();
Command compare_command();
Command speed_command();
Command resample_command();
Command envelope_command();
Command fatigue_command();
Command inspect_command();
Command tradeoff_command();
Command frf_command();
Command shaker_command();
Command modal_fit_command();
Command decay_command();
Command oma_command();
Command fit_command();
Command assess_command();
Command passages_command();
Command irregularity_command();
Command merge_command();
/// viaduct replay needs the other commands (the one a manifest names).
Command replay_command(const std::vector<Command>* commands);

}  // namespace viaduct::cli
