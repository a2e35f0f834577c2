// Rainflow counting, ASTM E1049 §5.4.4 and the four-point method (rainflow.hpp).
#include "viaduct/signal/rainflow.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "viaduct/core/error.hpp"

namespace viaduct::signal {

RainflowMethod rainflow_method(const std::string& name, const std::string& key) {
  if (name == "three-point") return RainflowMethod::three_point;
  if (name == "four-point") return RainflowMethod::four_point;
  throw InputError(key + " must be three-point or four-point, got '" + name + "'");
}

Rainflow::Rainflow(Sink sink, RainflowMethod method, double hysteresis)
    : sink_(std::move(sink)), method_(method), hysteresis_(hysteresis) {
  if (!sink_) throw std::logic_error("Rainflow: no sink");
  if (!(hysteresis >= 0.0) || !std::isfinite(hysteresis))
    throw InputError("rainflow: hysteresis = " + format_number(hysteresis, 6) + ": violated constraint hysteresis >= 0");
}

void Rainflow::emit(double a, double b, double count) { sink_(Cycle{std::abs(a - b), 0.5 * (a + b), count}); }

// A turning point into the counter; the cycles it closes go out.
void Rainflow::turning_point(double x) {
  stack_.push_back(x);
  if (method_ == RainflowMethod::three_point) {
    // X: the most recent range, Y: the one before it. X >= Y closes Y: a whole cycle, or half
    // of one when Y holds the history's starting point (the stack's first).
    while (stack_.size() >= 3) {
      const std::size_t n = stack_.size();
      const double X = std::abs(stack_[n - 1] - stack_[n - 2]), Y = std::abs(stack_[n - 2] - stack_[n - 3]);
      if (X < Y) break;
      if (n == 3) {
        emit(stack_[0], stack_[1], 0.5);
        stack_.erase(stack_.begin());
      } else {
        emit(stack_[n - 3], stack_[n - 2], 1.0);
        stack_.erase(stack_.end() - 3, stack_.end() - 1);
      }
    }
  } else {
    // Four points p1..p4: the inner range p2–p3 within both outer ones is a whole cycle.
    while (stack_.size() >= 4) {
      const std::size_t n = stack_.size();
      const double inner = std::abs(stack_[n - 2] - stack_[n - 3]);
      if (inner > std::abs(stack_[n - 3] - stack_[n - 4]) || inner > std::abs(stack_[n - 1] - stack_[n - 2])) break;
      emit(stack_[n - 3], stack_[n - 2], 1.0);
      stack_.erase(stack_.end() - 3, stack_.end() - 1);
    }
  }
}

void Rainflow::push(double x) {
  if (finished_) throw std::logic_error("Rainflow: push() after finish()");
  if (!std::isfinite(x))
    throw InputError("rainflow: sample " + std::to_string(n_samples_) + " is not finite (" + format_number(x, 6) +
                     "): cut the record or mark its gaps before counting");
  ++n_samples_;
  if (!have_last_) {  // the history's first sample is its first turning point
    have_last_ = true;
    last_tp_ = x;
    turning_point(x);
    return;
  }
  if (direction_ == 0) {
    if (std::abs(x - last_tp_) > hysteresis_) {
      direction_ = x > last_tp_ ? 1 : -1;
      candidate_ = x;
      have_candidate_ = true;
    }
    return;
  }
  const double d = static_cast<double>(direction_);
  if ((x - candidate_) * d >= 0.0) {  // the rise or fall goes on (or stays flat)
    candidate_ = x;
  } else if ((candidate_ - x) * d > hysteresis_) {  // a reversal: the running extreme was a turning point
    turning_point(candidate_);
    last_tp_ = candidate_;
    direction_ = -direction_;
    candidate_ = x;
  }
}

void Rainflow::push(const Vector& x) {
  for (Index i = 0; i < x.size(); ++i) push(x[i]);
}

void Rainflow::finish() {
  if (finished_) return;
  finished_ = true;
  if (have_candidate_) turning_point(candidate_);
  for (std::size_t i = 0; i + 1 < stack_.size(); ++i) emit(stack_[i], stack_[i + 1], 0.5);
  stack_.clear();
}

std::vector<Cycle> rainflow(const Vector& x, RainflowMethod method, double hysteresis) {
  std::vector<Cycle> out;
  Rainflow r([&](const Cycle& c) { out.push_back(c); }, method, hysteresis);
  r.push(x);
  r.finish();
  return out;
}

namespace {

void check_edges(const std::vector<double>& e, const char* what, bool non_negative) {
  if (e.size() < 2) throw InputError(std::string("rainflow histogram: ") + what + " edges: at least two are needed");
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (!std::isfinite(e[i])) throw InputError(std::string("rainflow histogram: ") + what + " edge " + std::to_string(i + 1) + " is not finite");
    if (non_negative && e[i] < 0.0)
      throw InputError(std::string("rainflow histogram: ") + what + " edge " + std::to_string(i + 1) + " = " + format_number(e[i], 6) +
                       ": violated constraint range edges >= 0");
    if (i > 0 && !(e[i] > e[i - 1]))
      throw InputError(std::string("rainflow histogram: ") + what + " edges must ascend (edge " + std::to_string(i + 1) + " = " +
                       format_number(e[i], 6) + " after " + format_number(e[i - 1], 6) + ")");
  }
}

// The bin of v in edges ([e_i, e_{i+1}), the last closed), or -1 outside.
Index bin_of(const std::vector<double>& e, double v) {
  if (v < e.front() || v > e.back()) return -1;
  if (v == e.back()) return static_cast<Index>(e.size()) - 2;
  return static_cast<Index>(std::upper_bound(e.begin(), e.end(), v) - e.begin()) - 1;
}

}  // namespace

CycleHistogram::CycleHistogram(std::vector<double> r, std::vector<double> m) : range_edges(std::move(r)), mean_edges(std::move(m)) {
  check_edges(range_edges, "range", true);
  if (!mean_edges.empty()) check_edges(mean_edges, "mean", false);
  counts = Matrix::Zero(static_cast<Index>(range_edges.size()) - 1, mean_edges.empty() ? 1 : static_cast<Index>(mean_edges.size()) - 1);
}

void CycleHistogram::add(const Cycle& c) {
  const Index i = bin_of(range_edges, c.range);
  const Index j = mean_edges.empty() ? 0 : bin_of(mean_edges, c.mean);
  if (i < 0 || j < 0) outside += c.count;
  else counts(i, j) += c.count;
}

}  // namespace viaduct::signal
