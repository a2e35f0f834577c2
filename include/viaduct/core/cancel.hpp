#pragma once
/// \file A process-wide request to stop long computations: the Python package sets it on Ctrl-C
/// (the CLI never does: its Ctrl-C ends the process). The time-stepping loops of src/solve look
/// at it every kCancelStride steps and throw Cancelled; a sweep records its running cases as
/// failed ("cancelled") and skips the rest. Looking costs one relaxed atomic load per stride.

#include "viaduct/core/error.hpp"
#include "viaduct/core/types.hpp"

namespace viaduct {

/// The computation saw a cancellation request.
class Cancelled : public SolverError {
 public:
  Cancelled() : SolverError("cancelled") {}
};

/// Sets or clears the request (every thread sees it).
void request_cancel(bool on) noexcept;
bool cancel_requested() noexcept;

constexpr Index kCancelStride = 256;
/// In a loop over steps: throws Cancelled when the request is set (looked at every kCancelStride steps).
inline void check_cancel(Index step) {
  if (step % kCancelStride == 0 && cancel_requested()) throw Cancelled();
}

}  // namespace viaduct
