#pragma once
/// \file Minimal fork-join parallel loop.

#include <cstddef>
#include <functional>

namespace viaduct {

/// Calls `body(i, worker)` for every i in [0, n) on `n_threads` threads (worker in
/// [0, n_threads)). Work is handed out one index at a time in increasing order, so long cases
/// listed first balance well. `body` must not throw: wrap failures per item. n_threads >= 1;
/// n_threads == 1 runs on the calling thread. The workers see the caller's cancellation flag
/// (core/cancel.hpp).
void parallel_for(std::size_t n, int n_threads,
                  const std::function<void(std::size_t i, int worker)>& body);

/// Number of hardware threads, at least 1.
int hardware_threads();

}  // namespace viaduct
