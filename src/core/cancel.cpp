#include "viaduct/core/cancel.hpp"

namespace viaduct {

namespace {
thread_local const std::atomic<bool>* t_flag = nullptr;
}

CancelScope::CancelScope(const std::atomic<bool>* flag) noexcept : previous_(t_flag) { t_flag = flag; }
CancelScope::~CancelScope() { t_flag = previous_; }

const std::atomic<bool>* cancel_flag() noexcept { return t_flag; }
bool cancel_requested() noexcept { return t_flag && t_flag->load(std::memory_order_relaxed); }

}  // namespace viaduct
