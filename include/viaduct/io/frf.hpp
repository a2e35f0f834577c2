#pragma once
/// \file FRF and stepped-sine schedule files (docs/identification.md).
///
/// frf.csv: `frequency_hz`, then per response `<name>_re_<unit>_per_<force unit>`,
/// `<name>_im_…`, `<name>_mag_…`, `<name>_phase_deg` and, when estimated, `<name>_coherence`;
/// units: m, mps or mps2 per N or kN. The reader needs frequency, re and im columns (mag and
/// phase are for people and plots) and names file, line and column in every error.
/// steps.csv: `t_start_s,t_end_s,frequency_hz`, one dwell per row.

#include <string>
#include <vector>

#include "viaduct/ident/frf.hpp"
#include "viaduct/io/record.hpp"

namespace viaduct::io {

/// Throws InputError for an inconsistent FRF, SolverError on I/O failure.
void write_frf_csv(const std::string& path, const ident::Frf& frf);
ident::Frf read_frf_csv(const std::string& path);

void write_steps_csv(const std::string& path, const std::vector<ident::SineStep>& steps);
std::vector<ident::SineStep> read_steps_csv(const std::string& path);

/// The force and responses of a forced-vibration test, taken from records (viaduct frf RECORD).
struct FrfInputs {
  Vector force;                                ///< the force channel
  Matrix responses;                            ///< one column per response channel
  std::string force_channel, force_unit;       ///< its full name; "N" or "kN"
  std::vector<std::string> response_channels;  ///< full names
  std::vector<std::string> response_units;     ///< their unit suffixes
  double fs_hz = 0.0, t0_s = 0.0;              ///< rate and first sample of both
  std::vector<std::string> notes;              ///< what was cut for the channels' missing samples (valid_span)
};

/// The channel `force` (N or kN) of `force_record` (or of `record` when null) and the channels
/// `responses` of `record` (default: every m, mps and mps2 channel). InputError when a channel
/// is missing or in the wrong unit, when there is no response, or when the two records differ
/// in rate, start or length. In one record, the longest piece where force and responses all have
/// values is taken (notes); in two, a missing sample of a channel used is an InputError.
FrfInputs frf_inputs(const Record& record, const std::string& record_path, const Record* force_record,
                     const std::string& force, const std::vector<std::string>& responses);

/// Names an estimated FRF after its channels: "S1_mid_acc_mps2" gives the response "S1_mid"
/// (quantity tag _acc, _vel or _disp and unit dropped: station names) with the quantity its
/// unit says; the force unit from the force channel.
void label_frf(ident::Frf& frf, const FrfInputs& in);

}  // namespace viaduct::io
