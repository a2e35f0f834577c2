#pragma once
/// \file Measured or simulated multi-channel records as CSV.
///
/// Format (docs/records.md): '#' comment lines; optional comment `# sampling_rate_hz = F`;
/// a header whose first column may be `t_s` (time, seconds) and whose channels are named
/// `<name>_<unit>` with a known unit suffix; one sample per row. Either a time column or a
/// declared sampling rate is required (both must agree). Errors name file, line and column:
/// NaN or empty cells, wrong column counts, non-increasing or irregular time, duplicated or
/// unit-less channels. Nothing is repaired silently.

#include <optional>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::io {

struct Record {
  double fs_hz = 0.0;                  ///< [Hz] sampling rate, > 0
  double t0_s = 0.0;                   ///< [s] time of the first sample
  std::vector<std::string> channels;   ///< full names, e.g. "S1_mid_acc_mps2"
  std::vector<std::string> units;      ///< unit suffix of each channel, e.g. "mps2"
  Matrix data;                         ///< n_samples × n_channels
  Index n_samples() const { return data.rows(); }
  /// Index of channel `name` (full name, or the name without its unit); InputError if absent.
  std::size_t channel(const std::string& name) const;
};

/// Unit suffixes a channel name may end with.
const std::vector<std::string>& known_units();

/// The samples of `r` with start_s <= t <= end_s (either may be absent), t0_s moved to the first
/// kept one. InputError naming `what` when the window is reversed or holds fewer than 2 samples.
Record time_window(const Record& r, std::optional<double> start_s, std::optional<double> end_s, const std::string& what);

/// Reads a record CSV (streaming, about 1 s per 100 MB). Throws InputError with file:line.
Record read_record_csv(const std::string& path);

/// Reads the real, evenly sampled datasets 58 (function at nodal DOF) of an ASCII Universal
/// File, one channel each: name from ID line 1 (spaces and commas become '_') plus a unit
/// suffix from the ordinate's unit label (m/s^2, g, m, mm, m/s, N, kN, Pa, V). All datasets
/// must share rate, start and length. Binary (58b), complex (FRF) or uneven data, and unknown
/// units, are InputErrors naming file and line. A `.uff` or `.unv` path selects this reader in
/// read_record().
Record read_uff58(const std::string& path);

/// What a record channel's unit says it holds, for comparing with the model: deck acceleration
/// (mps2, g) or deflection (m, mm), and the factor from the model's SI value to the unit.
struct ChannelQuantity {
  bool acceleration = true;
  double scale = 1.0;
};
/// InputError naming `who` and the channel for other units.
ChannelQuantity channel_quantity(const std::string& unit, const std::string& channel, const std::string& who);

/// read_uff58 for .uff/.unv files, read_record_csv otherwise.
Record read_record(const std::string& path);

/// Writes `r` with a t_s column (t0 + k/fs), atomically. Throws SolverError on I/O failure and
/// for a non-finite sample (named by channel), which is never written.
void write_record_csv(const std::string& path, const Record& r, int significant_digits = 10);

}  // namespace viaduct::io
