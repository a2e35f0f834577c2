#pragma once
/// \file Simulated against measured: the same filter on both, time alignment, overlays and
/// metrics (the Old Guadiana paper's comparison, REFERENCE.md §1).

#include <string>

#include "viaduct/core/types.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::study {

struct ComparisonOptions {
  FilterSpec filter;           ///< applied to record and model alike (at their own rates)
  double max_shift_s = 60.0;   ///< [s] alignment search range, > 0
  double spectrum_max_hz = 0;  ///< [Hz] upper end of the spectral metrics (0: filter high edge, or fs/2)
};

/// One record channel against one model quantity, both in the same unit.
struct ChannelComparison {
  double shift_s = 0.0;               ///< [s] record time of the model's t = 0 (t_rec = t_model + shift)
  double peak_record = 0, peak_model = 0;  ///< max |filtered| over the overlap
  double peak_ratio = 0;              ///< model / record
  double rms_ratio = 0;               ///< model / record, over the overlap
  double correlation = 0;             ///< Pearson coefficient over the overlap, aligned
  double f_peak_record_hz = 0, f_peak_model_hz = 0;  ///< main peak of each amplitude spectrum (Hann)
  double spectral_correlation = 0;    ///< Pearson coefficient of the amplitude spectra up to spectrum_max_hz
  Vector t;                           ///< [s] record time grid
  Vector record, model;               ///< filtered; model aligned onto the record grid (0 outside it)
  Vector frequency_hz, record_amplitude, model_amplitude;  ///< spectra of the two aligned signals
};

/// `record` sampled at fs_record from t0_record; `model` at fs_model from 0. Throws InputError
/// for non-finite samples, too short signals or an invalid filter.
ChannelComparison compare_channel(const Vector& record, double fs_record, double t0_record, const Vector& model,
                                  double fs_model, const ComparisonOptions& o);

}  // namespace viaduct::study
