#pragma once
/// \file The FRF of a forced-vibration test from its force and response records, by one of three
/// methods (viaduct frf RECORD): Welch H1/H2, stepped sine (a schedule given or detected from
/// the force), or swept sine. The record-level work (channels, units, names) is io's
/// (io/frf.hpp: frf_inputs); this is the numerics, on arrays.

#include <optional>
#include <vector>

#include "viaduct/ident/frf.hpp"

namespace viaduct::ident {

enum class FrfMethod { welch, stepped, swept };

/// "welch", "stepped" or "swept"; InputError naming `what` otherwise.
FrfMethod frf_method(const std::string& name, const std::string& what);

struct FrfEstimateOptions {
  FrfMethod method = FrfMethod::welch;
  bool h2 = false;                  ///< welch: H2 instead of H1
  signal::WelchOptions welch;       ///< welch: segment length and window
  std::optional<double> f_min_hz;   ///< [Hz] band kept: welch (default above 0 Hz), swept (required)
  std::optional<double> f_max_hz;   ///< [Hz] band kept: welch (default fs/2), swept (required)
  std::vector<SineStep> steps;      ///< stepped: the schedule; empty: detected from the force
  SteppedSineOptions stepped;       ///< stepped: settling and fit
};

/// What estimate_frf found: the FRF (responses unnamed; coherence for Welch only) and, per
/// method, what a user checks it by.
struct FrfEstimate {
  Frf frf;                               ///< frequencies ascending
  Index n_segments = 0;                  ///< welch: segments averaged
  std::vector<SineStep> steps;           ///< stepped: the schedule used
  bool steps_detected = false;           ///< stepped: the schedule was detected from the force
  std::vector<SteppedSinePoint> points;  ///< stepped: one per step, in schedule order
  std::vector<std::size_t> order;        ///< stepped: indices of points by ascending frequency (the FRF's rows)
  double worst_settle_change = 0.0;      ///< stepped: largest settle_change of any step and response
  double worst_distortion = 0.0;         ///< stepped: largest THD+N of force or response
};

/// The FRF of every column of `responses` to `force` (same length, rate fs_hz, first sample at
/// t0_s). InputError for an empty band, fewer than two lines kept, or what the method's own
/// function refuses (welch_frf, detect_steps, stepped_sine, swept_sine).
FrfEstimate estimate_frf(const Vector& force, const Matrix& responses, double fs_hz, double t0_s,
                         const FrfEstimateOptions& o);

}  // namespace viaduct::ident
