#include "viaduct/core/cancel.hpp"

#include <atomic>

namespace viaduct {

namespace {
std::atomic<bool> g_cancel{false};
}

void request_cancel(bool on) noexcept { g_cancel.store(on, std::memory_order_relaxed); }
bool cancel_requested() noexcept { return g_cancel.load(std::memory_order_relaxed); }

}  // namespace viaduct
