#include "viaduct/core/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "viaduct/core/cancel.hpp"
#include "viaduct/core/error.hpp"

namespace viaduct {

void parallel_for(std::size_t n, int n_threads,
                  const std::function<void(std::size_t i, int worker)>& body) {
  if (n_threads < 1) throw InputError("thread count must be >= 1");
  if (n_threads == 1 || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i, 0);
    return;
  }
  std::atomic<std::size_t> next{0};
  const std::atomic<bool>* flag = cancel_flag();  // the caller's cancellation, for every worker
  auto work = [&](int worker) {
    const CancelScope scope(flag);
    for (std::size_t i = next++; i < n; i = next++) body(i, worker);
  };
  std::vector<std::thread> threads;
  const int n_extra = static_cast<int>(std::min<std::size_t>(n, static_cast<std::size_t>(n_threads))) - 1;
  threads.reserve(static_cast<std::size_t>(n_extra));
  for (int w = 1; w <= n_extra; ++w) threads.emplace_back(work, w);
  work(0);
  for (auto& t : threads) t.join();
}

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

}  // namespace viaduct
