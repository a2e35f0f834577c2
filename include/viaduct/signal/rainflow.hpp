#pragma once
/// \file Rainflow cycle counting (issue #42; REFERENCE.md §11): ASTM E1049-85 (2017) §5.4.4, the
/// three-point method with its starting-point rule, or the four-point method, streaming: samples
/// go in one at a time (or in blocks) and cycles come out as they close, so a month of strain at
/// 1 kHz is counted holding only the turning points not yet closed (the residue).
///
/// Residue (the turning points left open when the history ends):
/// - three-point (ASTM): every range of the residue is a half cycle (§5.4.4 step 6); the
///   starting-point rule has already counted the ranges through the history's first point as
///   half cycles.
/// - four-point: every range of the residue is a half cycle too (the usual reading; closing
///   the residue by repeating it, which counts some of them as whole cycles, is not done).
/// Both methods count the same whole cycles in the interior of a history; they differ only in
/// where half cycles come from.

#include <functional>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::signal {

/// One counted cycle: its range (peak − valley, > 0), mean ((peak + valley) / 2) and count (1
/// for a closed cycle, 0.5 for a half cycle).
struct Cycle {
  double range = 0.0;
  double mean = 0.0;
  double count = 1.0;
};

enum class RainflowMethod { three_point, four_point };
/// "three-point" or "four-point" (the CLI's --method and Python's method=); InputError naming
/// `key` for any other.
RainflowMethod rainflow_method(const std::string& name, const std::string& key = "method");

/// Streaming counter. Turning points are taken from the samples (a run of equal values is one
/// point; a sample that continues the current rise or fall extends it); `hysteresis` >= 0 drops
/// reversals smaller than it (0: none). Non-finite samples are an InputError naming the sample.
class Rainflow {
 public:
  using Sink = std::function<void(const Cycle&)>;
  explicit Rainflow(Sink sink, RainflowMethod method = RainflowMethod::three_point, double hysteresis = 0.0);
  void push(double x);
  void push(const Vector& x);
  /// Ends the history: the pending extreme becomes a turning point and the residue is counted
  /// as half cycles. push() after finish() is an error (a logic error of the caller).
  void finish();
  std::size_t n_samples() const { return n_samples_; }
  /// Turning points held now (the residue so far): what the counter's memory grows with.
  std::size_t n_open() const { return stack_.size(); }

 private:
  void turning_point(double x);
  void emit(double a, double b, double count);
  Sink sink_;
  RainflowMethod method_;
  double hysteresis_;
  std::vector<double> stack_;  ///< open turning points
  bool start_open_ = true;     ///< three-point: the stack's first point is still the history's start S
  bool have_last_ = false, have_candidate_ = false, finished_ = false;
  double last_tp_ = 0.0;       ///< the last turning point confirmed
  double candidate_ = 0.0;     ///< the running extreme since it
  int direction_ = 0;          ///< +1 rising, −1 falling, 0 not yet known
  std::size_t n_samples_ = 0;
};

/// The cycles of a whole history, in the order they close (residue last).
std::vector<Cycle> rainflow(const Vector& x, RainflowMethod method = RainflowMethod::three_point, double hysteresis = 0.0);

/// Counts binned by range (and mean): edges ascending, at least two, range bins [e_i, e_{i+1})
/// with the last closed. A cycle outside the edges is counted in `outside` (never dropped
/// silently). InputError for edges that are not ascending or not finite, or negative range edges.
struct CycleHistogram {
  std::vector<double> range_edges;
  std::vector<double> mean_edges;  ///< empty: ranges only (one mean bin over everything)
  Matrix counts;                   ///< range bins × mean bins
  double outside = 0.0;            ///< counts of cycles outside the edges
  CycleHistogram(std::vector<double> range_edges, std::vector<double> mean_edges = {});
  void add(const Cycle& c);
};

}  // namespace viaduct::signal
