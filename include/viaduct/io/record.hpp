#pragma once
/// \file Measured or simulated multi-channel records: CSV as loggers write it, ASCII UFF 58.
///
/// Reading (docs/records.md): comma, semicolon or tab separated, decimal point or comma,
/// preamble and '#' comment lines above the header, a time column (found by name, or given) or
/// a declared rate, units in channel names (`acc_mps2`, `Acc1 [g]`, `Acc2 (m/s^2)`,
/// `Strain1 [µε]`) converted to viaduct's units (SI; strain in microstrain), time stamps
/// rounded to the rate accepted within half a sample, short NaN runs and gaps interpolated and
/// long ones cut or refused. Every change is reported; every problem of a file is listed in one
/// InputError naming file and line.

#include <optional>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::io {

struct Record {
  double fs_hz = 0.0;                  ///< [Hz] sampling rate, > 0
  double t0_s = 0.0;                   ///< [s] time of the first sample
  std::vector<std::string> channels;   ///< full names, e.g. "S1_mid_acc_mps2"
  std::vector<std::string> units;      ///< unit suffix of each channel, e.g. "mps2"
  Matrix data;                         ///< n_samples × n_channels
  std::vector<std::string> sources;    ///< the file's header text of each channel ("Acc1 [g]"), or empty
  Index n_samples() const { return data.rows(); }
  /// Index of channel `name` (full name, the name without its unit, or the file's header text);
  /// InputError if absent.
  std::size_t channel(const std::string& name) const;
};

/// Unit suffixes of viaduct's records: what a read channel ends with (m, mps, mps2, N, Nm, ue,
/// Pa, V, rad, 1, degC), and the scaled ones a file may also use (mm, g, kN, kNm).
const std::vector<std::string>& known_units();

/// A unit as a logger writes it ("g", "m/s^2", "m/s²", "µε", "microstrain", "mm", "kN", "MPa",
/// "mV", "°C", or a viaduct suffix): the unit viaduct keeps (mps2, mps, m, N, Nm, ue, Pa, V, rad,
/// 1, degC) and the factor to it. Nothing when the text is not a unit viaduct knows.
struct UnitConversion {
  std::string unit;
  double factor = 1.0;
};
std::optional<UnitConversion> parse_unit(const std::string& text);

/// How to read a record file that is not in viaduct's own layout (CLI: --time-column,
/// --rate-hz, --unit, --fill-max-s, --long-gaps).
struct ReadOptions {
  std::string time_column;               ///< header text, name or 1-based index; "" finds it by name; "none": there is none
  std::optional<double> fs_hz;           ///< [Hz] the rate, when the file does not say it (or to check the time column)
  std::vector<std::pair<std::string, std::string>> units;  ///< channel (header text or name) → unit, for names without one
  double fill_max_s = 0.005;             ///< [s] NaN runs and gaps up to this long are interpolated linearly
  bool split_long_gaps = true;           ///< longer ones stay missing in their own channel (valid_span); false: refused
  int header_line = 0;                   ///< > 0: the header's line (1-based), instead of finding it
  int skip_lines = 0;                    ///< lines at the top not read at all (a preamble the finder misreads)
};

/// What reading a record understood and changed (printed by the CLI; `viaduct inspect`).
struct ImportReport {
  struct Channel {
    std::string header;       ///< as in the file
    std::string channel;      ///< viaduct's name
    std::string unit_given;   ///< unit text as found ("g", "[m/s^2]", suffix "mm")
    double factor = 1.0;      ///< file value × factor = viaduct's value
    Index missing = 0;        ///< NaN, empty or non-finite cells, and samples of time gaps
    Index interpolated = 0;   ///< of those, filled by linear interpolation
    Index clipped = 0;        ///< samples in runs at the channel's max or min (summarise_channel's rule), made missing
  };
  std::string layout;                  ///< separator, decimal mark, header line, preamble lines
  std::string time;                    ///< where time and rate come from
  std::vector<Channel> channels;
  double max_time_offset = 0.0;        ///< [samples] largest distance of a time stamp from the uniform grid
  Index gap_samples = 0;               ///< samples absent from the time column
  std::vector<std::string> repairs;    ///< each interpolation, cut and conversion of a file, in words
  std::vector<std::string> notes;      ///< assumptions made (seconds assumed, rate from the preamble)
  bool plain = true;                   ///< viaduct's own layout, nothing converted or repaired
};

/// The report in lines for people: layout, time, each renamed or scaled channel, notes, repairs.
std::vector<std::string> describe(const ImportReport& report);

/// The samples of `r` with start_s <= t <= end_s (either may be absent), t0_s moved to the first
/// kept one. InputError naming `what` when the window is reversed or holds fewer than 2 samples.
Record time_window(const Record& r, std::optional<double> start_s, std::optional<double> end_s, const std::string& what);

/// The runs [first, end) of samples of channel `c` that are missing (NaN). A run too long to
/// interpolate stays missing in its own channel only: the other channels keep their samples.
std::vector<std::pair<Index, Index>> missing_runs(const Record& r, std::size_t c);

/// The record cut to the longest piece in which every channel of `used` has all its samples
/// (channels keep their indices; another channel's missing run cuts nothing). What was cut goes
/// to `notes` in words, naming channel and times. InputError naming `who` and the channel when
/// fewer than 2 samples remain. Every command calls it with the channels it uses.
Record valid_span(const Record& r, const std::vector<std::size_t>& used, const std::string& who, std::vector<std::string>* notes);

/// Reads a record CSV (streaming; every problem listed in one InputError with file:line).
Record read_record_csv(const std::string& path, const ReadOptions& options = {}, ImportReport* report = nullptr);

/// A MATLAB .mat file (v4, v5 or v7.3, read with libmatio) as a record: every real numeric
/// vector of the record's length is a channel named by its variable (units as in CSV headers:
/// `acc_mid_g`, or --unit), a matrix with a sample per row gives a channel per column (named by a
/// cell array `names`/`channels` (or VAR_names) and `units`, else VAR_1, VAR_2, ...), a vector
/// named t, time, t_s... is the time column, a scalar fs, sample_rate, sampling_rate_hz... (or dt)
/// the rate. The record's length is the time vector's, else the most common length; other
/// variables are listed as not read. Then as read_record_csv: time grid, conversions, repairs,
/// every problem in one InputError (its line is the sample's row).
Record read_record_mat(const std::string& path, const ReadOptions& options = {}, ImportReport* report = nullptr);

/// Reads the real, evenly sampled datasets 58 (function at nodal DOF) of an ASCII Universal
/// File, one channel each: name from ID line 1 (spaces and commas become '_') plus a unit
/// suffix from the ordinate's unit label (m/s^2, g, m, mm, m/s, N, kN, Pa, V). All datasets
/// must share rate, start and length. Binary (58b), complex (FRF) or uneven data, and unknown
/// units, are InputErrors naming file and line. A `.uff` or `.unv` path selects this reader in
/// read_record().
Record read_uff58(const std::string& path);

/// What `viaduct inspect` says of a channel: range, offset, drift and signs of clipping.
struct ChannelSummary {
  double min = 0, max = 0, mean = 0;
  double rms_ac = 0;          ///< RMS about the mean
  double drift = 0;           ///< mean of the last tenth minus mean of the first tenth
  Index at_limits = 0;        ///< samples at the channel's max or min in runs of 3 or more
  Index longest_flat = 0;     ///< longest run of one repeated value, in samples (a stuck sensor?)
  /// A run at the max or min of 3 samples or more and at least twice as long as any run of one
  /// value elsewhere: the signal went past the range (an oversampled smooth peak repeats its
  /// quantised top about as often as its other quantised values).
  bool clipped = false;
};
ChannelSummary summarise_channel(const Vector& x);

/// What a record channel's unit says it holds, for comparing with the model (channels are read
/// in viaduct's units, so the model's values compare as they are): deck acceleration (mps2),
/// deflection (m) or strain (ue: the model's <station>_strain_ue).
using ChannelQuantity = study::ResponseKind;
/// InputError naming `who` and the channel for other units.
ChannelQuantity channel_quantity(const std::string& unit, const std::string& channel, const std::string& who);

/// read_uff58 for .uff/.unv files, read_record_mat for .mat, read_record_csv otherwise; channels in viaduct's units.
Record read_record(const std::string& path, const ReadOptions& options = {}, ImportReport* report = nullptr);

/// One row of a table of recorded passages (viaduct passages): a record file, its train and,
/// when known, its speed.
struct PassageEntry {
  std::string file;       ///< as written, resolved against the table's folder when relative
  std::string train;      ///< a train name or train file; empty: the command's default
  double speed_kmh = 0;   ///< [km/h] > 0; 0 (empty cell): identify
  int line = 0;           ///< the table's line
};
/// A CSV table with a header naming `file` (or `record`), optionally `train` and `speed_kmh`;
/// other columns are ignored, '#' lines skipped. InputError naming file, line and column for a
/// missing file column, an empty file cell or a speed that is not a number > 0.
std::vector<PassageEntry> read_passage_table(const std::string& path);

/// The record files (.csv, .txt, .tsv, .dat, .uff, .unv, .mat; not hidden) of `folder`, in name
/// order; InputError when there are none.
std::vector<std::string> record_files_in(const std::string& folder);

/// Writes `r` with a t_s column (t0 + k/fs) as header and rows only (pandas.read_csv reads it
/// as is; the reader takes the rate from the time column), atomically. Throws SolverError on
/// I/O failure and for a non-finite sample (named by channel), which is never written.
void write_record_csv(const std::string& path, const Record& r, int significant_digits = 10);

}  // namespace viaduct::io
