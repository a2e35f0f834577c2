#pragma once
// Large tables written in full after they are allocated: an allocator that does not zero them.

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

namespace viaduct {

/// Memory for `bytes` (blocks of kLargeBlock bytes and more: aligned to 2 MB and advised as
/// transparent huge pages on Linux, so that writing them first faults once per 2 MB instead of
/// once per 4 KB). Throws std::bad_alloc.
void* allocate_block(std::size_t bytes);
/// Frees what allocate_block(bytes) gave, with the same `bytes`.
void free_block(void* p, std::size_t bytes) noexcept;
constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

/// While one of these lives (in any thread), large blocks that are freed are kept, up to three, and
/// given again to an allocation they hold: a sweep's folded trains, allocated and freed train after
/// train, then fault their pages in once (on Old Guadiana the faults and the kernel's zeroing of
/// 51 MB per train were 2 % of the run). The last scope to end frees what is kept.
class BlockReuse {
 public:
  BlockReuse();
  ~BlockReuse();
  BlockReuse(const BlockReuse&) = delete;
  BlockReuse& operator=(const BlockReuse&) = delete;
};

/// A std::vector allocator whose construction without a value leaves the element uninitialised:
/// resize() does not zero what the caller writes in full anyway (MovingChannels::coef, 51 MB per
/// train on Old Guadiana, filled in parts by the threads that need it). Memory from allocate_block.
template <class T>
struct UninitAllocator {
  using value_type = T;
  UninitAllocator() = default;
  template <class U>
  UninitAllocator(const UninitAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(allocate_block(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { free_block(p, n * sizeof(T)); }
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  template <class U>
  bool operator==(const UninitAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const UninitAllocator<U>&) const noexcept { return false; }
};

}  // namespace viaduct
