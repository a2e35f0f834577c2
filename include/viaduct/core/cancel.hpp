#pragma once
/// \file Cancellation of long computations, per call: a caller that can be interrupted (the
/// Python package, on Ctrl-C) installs its own flag for the thread that computes (CancelScope);
/// parallel_for hands the flag on to its worker threads, so every time-stepping loop of that call,
/// and of no other, sees it. The loops of src/solve look every kCancelStride steps and throw
/// Cancelled; a sweep records its running cases as failed ("cancelled"), skips the rest, and says
/// it was cut (SweepSummary::cancelled). A thread without a scope is never cancelled (the CLI: its
/// Ctrl-C ends the process). Looking costs one thread-local read and, with a flag, one relaxed
/// atomic load per stride.

#include <atomic>

#include "viaduct/core/error.hpp"
#include "viaduct/core/types.hpp"

namespace viaduct {

/// The computation saw its cancellation flag set.
class Cancelled : public SolverError {
 public:
  Cancelled() : SolverError("cancelled") {}
};

/// Installs `flag` (may be null: none) as this thread's cancellation flag for the scope's life,
/// and restores the previous one after. The flag must outlive the scope.
class CancelScope {
 public:
  explicit CancelScope(const std::atomic<bool>* flag) noexcept;
  ~CancelScope();
  CancelScope(const CancelScope&) = delete;
  CancelScope& operator=(const CancelScope&) = delete;

 private:
  const std::atomic<bool>* previous_;
};

/// This thread's flag (null: none): what parallel_for passes on to its workers.
const std::atomic<bool>* cancel_flag() noexcept;
/// True when this thread's flag is set.
bool cancel_requested() noexcept;

constexpr Index kCancelStride = 256;
/// In a loop over steps: throws Cancelled when this thread's flag is set (looked at every
/// kCancelStride steps).
inline void check_cancel(Index step) {
  if (step % kCancelStride == 0 && cancel_requested()) throw Cancelled();
}

}  // namespace viaduct
