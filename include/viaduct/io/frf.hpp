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

namespace viaduct::io {

/// Throws InputError for an inconsistent FRF, SolverError on I/O failure.
void write_frf_csv(const std::string& path, const ident::Frf& frf);
ident::Frf read_frf_csv(const std::string& path);

void write_steps_csv(const std::string& path, const std::vector<ident::SineStep>& steps);
std::vector<ident::SineStep> read_steps_csv(const std::string& path);

}  // namespace viaduct::io
