#pragma once
/// \file Output-only (operational) modal identification, REFERENCE.md §10: covariance-driven
/// stochastic subspace identification (SSI-COV) with reference channels over a range of model
/// orders, the stabilization diagram, automatic clustering of stable poles into modes with
/// jackknife standard deviations, frequency domain decomposition (FDD, EFDD) as the quick look,
/// and the tracking of modes over many windows or records.
///
/// Model: y_t = C x_t + v_t, x_{t+1} = A x_t + w_t with white w, v. The output correlations
/// R_k = E[y_{t+k} y_ref,tᵀ] = C A^{k−1} G factor the block Toeplitz matrix of lags 1..2i−1 into
/// observability O_i (C, CA, …, CA^{i−1}) times controllability; O_i comes from its SVD truncated
/// to the model order n, A from O_i's shift invariance (least squares), C from its first block
/// row. A pole μ of A is λ = fs·ln μ: f = |λ|/2π, ζ = −Re λ/|λ| (viscous); its shape is C ψ.

#include <limits>
#include <string>
#include <vector>

#include "viaduct/ident/frf.hpp"

namespace viaduct::ident {

/// [-] A window whose loudest tenth has more than this times the RMS of its quietest is not
/// ambient: a train passage (10 to 100 times the ambient level) or another burst.
constexpr double kMaxStationaryRmsRatio = 10.0;

/// A warning, or "": y (n × channels at fs_hz, first sample at t0_s) cut in ten equal pieces,
/// each piece's RMS about its own mean relative to the channel's over the whole (so that
/// no unit dominates), averaged over the channels: when the loudest piece's exceeds
/// kMaxStationaryRmsRatio times the quietest's, the window is a burst and not ambient — SSI-COV
/// and FDD assume stationary broadband excitation, and a passage's forced response (the axles'
/// passing harmonics) can pass as modes. Fewer than 640 samples: not judged.
std::string stationarity_warning(const Matrix& y, double fs_hz, double t0_s);

/// Checks a record for output-only identification; InputError naming the channel: NaN or
/// infinite samples, a constant channel, a clipped one (1 % of its samples or more at its
/// extreme value, on either side), fewer than `min_channels` channels, a band above the Nyquist
/// frequency, or fewer than `min_periods` periods of `f_low_hz` (the lowest frequency of
/// interest; 0: not checked) in the record.
void check_oma_record(const Matrix& y, double fs_hz, const std::vector<std::string>& names, Index min_channels, double f_low_hz,
                      double f_high_hz, double min_periods);

/// Output correlations R_k = Σ_t y_{t+k} y_ref,tᵀ / d_k (n_channels × n_refs), k = 0..n_lags−1,
/// by FFT, mean removed; d_k = N − k (unbiased, for stationary records) or 1 (sums, for a free
/// decay, whose correlations are C A^k Σ_t x_t x_tᵀ … exactly only as sums). Records are split
/// into `blocks` pieces and the sums taken per piece (SsiOptions::uncertainty_blocks): lags
/// across a piece's end are left out, n_lags·(blocks−1) of N·n_lags products.
struct Correlations {
  std::vector<Matrix> lag;                 ///< the whole record's R_k
  std::vector<std::vector<Matrix>> block;  ///< per piece: its sums Σ_t (not divided)
  std::vector<Vector> block_count;         ///< per piece: the number of products of each lag
  bool unbiased = true;
};
Correlations output_correlations(const Matrix& y, const std::vector<Index>& refs, Index n_lags, Index blocks, bool unbiased);

struct SsiOptions {
  double f_min_hz = 0.0;                                       ///< [Hz] band of the reported modes, >= 0
  double f_max_hz = std::numeric_limits<double>::infinity();   ///< [Hz] (clipped to 0.99 × Nyquist)
  std::vector<Index> references;  ///< reference channels (columns of y); empty: every channel
  /// i, the Toeplitz matrix's block rows (lags 1 … 2i−1); 0: max(⌈max_order / n_refs⌉ + 1,
  /// ⌈fs / (2·f_low)⌉) with f_low the band's lower edge (or fs/100 without one), at most
  /// 1200 / n_refs
  Index block_rows = 0;
  int min_order = 2;    ///< [-] smallest model order (states), even, >= 2
  int max_order = 60;   ///< [-] largest, even, <= 400
  int order_step = 2;   ///< [-] even, >= 2
  bool free_decay = false;  ///< the record is a free decay (correlations as sums; no jackknife)
  double tol_frequency = 0.01;  ///< [-] stable: |Δf|/f against the previous order below this
  double tol_damping = 0.05;    ///< [-] and |Δζ|/ζ below this
  double tol_mac = 0.98;        ///< [-] and the MAC of the shapes above this
  double max_damping = 0.10;    ///< [-] poles with ζ outside (0, max_damping] are spurious
  double min_mpc = 0.0;         ///< [-] poles whose shape has a lower modal phase collinearity are spurious (0: none)
  double max_mpd_deg = 90.0;    ///< [deg] or a higher mean phase deviation (90: none)
  /// [-] clusterable poles i, j join one cluster when |f_i − f_j|/max(f) + 1 − MAC_ij is below this
  /// (single linkage)
  double cluster_distance = 0.02;
  /// [-] a cluster is a mode when it holds poles of at least this fraction of the orders
  double min_cluster_fraction = 0.3;
  /// [-] pieces of the record for the jackknife standard deviations of f and ζ (each left out
  /// in turn; 0: none), 0 or >= 4
  Index uncertainty_blocks = 10;
  bool is_valid(Index n_channels, double fs_hz, std::string* why) const;
};

struct SsiPole {
  int order = 0;
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
  double mpc = 0.0;      ///< [-] modal phase collinearity (1: a real shape)
  double mpd_deg = 0.0;  ///< [deg] mean phase deviation from the shape's best straight line
  ComplexVector shape;   ///< C ψ, rotated to its principal direction, largest entry 1
  bool physical = false;  ///< in the band, ζ in (0, max_damping], MPC and MPD within bounds
  /// against the nearest pole of the previous order: f, ζ, MAC within tolerance
  bool stable_frequency = false, stable_damping = false, stable_shape = false;
  int cluster = -1;  ///< mode (index in SsiResult::modes) it was counted for, or -1
  bool stable() const { return physical && stable_frequency && stable_damping && stable_shape; }
  /// What clustering takes: physical, stable in frequency and shape. Damping, the noisiest
  /// estimate (its order-to-order changes on a 10-minute record reach 10 %), is shown in the
  /// diagram (stable()) but not required.
  bool clusterable() const { return physical && stable_frequency && stable_shape; }
};

/// The pole's status in the stabilization diagram, as stabilization.csv and viaduct.oma() name
/// it: "spurious" (not physical), "stable" (f, ζ, shape), "shape" (f and shape: clustered),
/// "damping" (f and ζ), "frequency", "new".
const char* pole_status(const SsiPole& p);

struct OmaMode {
  double frequency_hz = 0.0;   ///< [Hz] undamped natural frequency
  double damping_ratio = 0.0;  ///< [-]
  /// [Hz], [-]: jackknife standard deviations over the record's pieces (NaN without them): the
  /// scatter of the estimate from the record's randomness, not its bias
  double frequency_std_hz = std::numeric_limits<double>::quiet_NaN();
  double damping_std = std::numeric_limits<double>::quiet_NaN();
  double frequency_spread_hz = 0.0;  ///< [Hz] standard deviation over the cluster's poles (the orders)
  double damping_spread = 0.0;       ///< [-]
  ComplexVector shape;  ///< per channel, rotated to real as far as it goes, largest entry 1
  double mpc = 0.0, mpd_deg = 0.0;
  int order = 0;        ///< model order of the representative pole (the shape's; f and ζ are the cluster's medians)
  std::vector<int> orders;  ///< model orders of the cluster's poles
  Index n_poles = 0;    ///< poles in the cluster
  std::string note;     ///< a warning (at the band's edge; few periods in the record); empty when none
};

struct SsiResult {
  std::vector<SsiPole> poles;  ///< every pole with f > 0 of every order
  std::vector<int> orders;
  std::vector<OmaMode> modes;  ///< by frequency
  Index block_rows = 0;
  Vector singular_values;      ///< of the Toeplitz matrix (the order's choice can be read from it)
  double f_min_hz = 0.0, f_max_hz = 0.0;  ///< band used
};

/// SSI-COV of the records y (n_samples × n_channels, sampled at fs_hz). InputError for invalid
/// options or a record check_oma_record refuses (with channel numbers; the CLI names them).
SsiResult ssi_cov(const Matrix& y, double fs_hz, const SsiOptions& o = {});

/// The poles of one model order from the Toeplitz matrix's SVD (U·S): what ssi_cov does per order.
std::vector<SsiPole> ssi_poles(const Matrix& us_sqrt, Index n_channels, int order, double fs_hz);

/// Modal phase collinearity and mean phase deviation [deg] of a complex shape; the shape
/// rotated to its principal direction and scaled to a largest entry of 1.
struct ShapeQuality {
  double mpc = 0.0, mpd_deg = 0.0;
  ComplexVector normalised;
};
ShapeQuality shape_quality(const ComplexVector& phi);

// ---------------------------------------------------------------------------------------------
// FDD / EFDD

struct FddOptions {
  double f_min_hz = 0.0;                                      ///< [Hz] band searched
  double f_max_hz = std::numeric_limits<double>::infinity();  ///< [Hz]
  Index nperseg = 0;  ///< Welch segment (Hann, 50 % overlap); 0: the power of 2 nearest N/16, 256..16384
  double min_prominence_db = 6.0;  ///< [dB] peaks of the first singular value less prominent are ignored, >= 0
  std::size_t max_modes = 0;       ///< the most prominent ones (0: all)
  double efdd_mac = 0.8;  ///< [-] the SDOF bell: lines around the peak whose singular vector has MAC above this
  bool is_valid(Index n_samples, double fs_hz, std::string* why) const;
};

struct FddMode {
  double frequency_hz = 0.0;        ///< [Hz] FDD: the peak of the first singular value (interpolated)
  double efdd_frequency_hz = std::numeric_limits<double>::quiet_NaN();  ///< [Hz] EFDD, from the bell's correlation function
  double efdd_damping_ratio = std::numeric_limits<double>::quiet_NaN();  ///< [-] EFDD
  ComplexVector shape;              ///< first singular vector at the peak, normalised as OmaMode::shape
  double bell_low_hz = 0.0, bell_high_hz = 0.0;  ///< [Hz] the SDOF bell's lines
  std::string note;
};

struct FddResult {
  Vector frequency_hz;
  Matrix singular_values;  ///< n_frequencies × n_channels, largest first (unit²/Hz)
  std::vector<FddMode> modes;
  Index nperseg = 0;
};

/// Singular values of the Welch cross-spectral density matrix (SciPy's scaling, one-sided) line
/// by line; peaks of the first; EFDD damping and frequency from each peak's bell back in time
/// (zero crossings and log decrement of its correlation function between 0.9 and 0.3 of its
/// start). A quick look: the Hann window widens the bell, so EFDD's ζ is biased high when the
/// half-power bandwidth 2ζf spans few lines (docs/identification.md gives the measured error).
FddResult fdd(const Matrix& y, double fs_hz, const FddOptions& o = {});

// ---------------------------------------------------------------------------------------------
// Free decay and tracking

/// [sample] where the free vibration after a passage starts: the first sample after the largest
/// running rms (window `window` samples, summed over channels) from which the running rms only
/// falls (a rise of more than 2 % ends the search) until it reaches twice the record's noise
/// floor (the running rms's 5th percentile).
Index free_decay_start(const Matrix& y, Index window);

struct TrackingOptions {
  double tol_frequency = 0.05;  ///< [-] a mode joins a track whose last frequency is within this (relative)
  double min_mac = 0.8;         ///< [-] and whose last shape has a MAC above this (when both have shapes)
  bool is_valid(std::string* why) const;
};

/// Modes of successive windows matched into tracks: each window's modes in order of frequency
/// join the best free track (least |Δf|/f + 1 − MAC among those within tolerance), else start a
/// new one. Returns, per window, the track of each mode.
std::vector<std::vector<int>> track_modes(const std::vector<std::vector<OmaMode>>& windows, const TrackingOptions& o = {});

}  // namespace viaduct::ident

namespace viaduct::ident {

// ---------------------------------------------------------------------------------------------
// The workflow of `viaduct oma` and viaduct.oma(): one record cut into windows, each identified.

struct OmaPlan {
  SsiOptions ssi;          ///< ssi.free_decay: each window is the free vibration after a passage
  FddOptions fdd;          ///< its band is taken from ssi
  int decimate = 1;        ///< [-] signal::decimate every channel by this first (1: not), 1..50
  double start_s = std::numeric_limits<double>::quiet_NaN();  ///< [s] record time to start at (NaN: its start)
  double end_s = std::numeric_limits<double>::quiet_NaN();    ///< [s] and to end at (NaN: its end)
  double window_s = 0.0;   ///< [s] windows of this length, each identified (0: one window), >= 0
  /// [-] a stationary window must hold this many periods of the band's lower edge (or of each
  /// mode found, which is noted otherwise)
  double min_periods = 200.0;
  /// [s] free decay: running rms window of free_decay_start (0: 2 periods of the band's lower
  /// edge, or 0.5 s without one)
  double decay_rms_s = 0.0;
  bool is_valid(std::string* why) const;
};

struct OmaWindow {
  double t_start_s = 0.0, t_end_s = 0.0;  ///< [s] record time identified
  SsiResult ssi;
  FddResult fdd;
  std::string error;  ///< why this window gave nothing (the others stand); empty when it went well
  /// Not stationary (stationarity_warning; ambient windows only): said here and in each SSI mode's note.
  std::string warning;
};

/// Identifies y (n_samples × channels at fs_hz, first sample at t0_s; `names` for messages)
/// window by window; each window's failure is kept in its `error`. InputError for an invalid
/// plan or a record that check_oma_record refuses as a whole.
std::vector<OmaWindow> identify_output_only(const Matrix& y, double fs_hz, double t0_s, const std::vector<std::string>& names,
                                            const OmaPlan& plan);

}  // namespace viaduct::ident
