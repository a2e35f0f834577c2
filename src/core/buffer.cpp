#include "viaduct/core/buffer.hpp"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <unordered_map>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace viaduct {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kKept = 3;  // large blocks kept for reuse while a BlockReuse lives
std::size_t huge_rounded(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }

// The large blocks: each live one's size as allocated (a reused block is larger than asked), the
// freed ones kept, and how many BlockReuse scopes live.
struct LargeBlocks {
  std::mutex m;
  std::unordered_map<void*, std::size_t> size;
  std::vector<std::pair<void*, std::size_t>> kept;
  int scopes = 0;
};
LargeBlocks& large_blocks() {
  static LargeBlocks b;
  return b;
}

void* new_large_block(std::size_t size) {
  void* p = std::aligned_alloc(kHugePage, size);
  if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  (void)madvise(p, size, MADV_HUGEPAGE);  // advice only: without huge pages the memory is the same
#endif
  return p;
}
}  // namespace

void* allocate_block(std::size_t bytes) {
  if (bytes < kLargeBlock) return ::operator new(bytes);
  if (bytes > static_cast<std::size_t>(-1) - kHugePage) throw std::bad_alloc();
  const std::size_t size = huge_rounded(bytes);
  LargeBlocks& b = large_blocks();
  std::lock_guard<std::mutex> lock(b.m);
  // The smallest kept block that holds the request without wasting more than half of it.
  std::size_t best = b.kept.size();
  for (std::size_t i = 0; i < b.kept.size(); ++i)
    if (b.kept[i].second >= size && b.kept[i].second - size <= size / 2 &&
        (best == b.kept.size() || b.kept[i].second < b.kept[best].second))
      best = i;
  if (best < b.kept.size()) {
    const auto k = b.kept[best];
    b.kept.erase(b.kept.begin() + static_cast<std::ptrdiff_t>(best));
    b.size[k.first] = k.second;
    return k.first;
  }
  void* p = new_large_block(size);
  try {
    b.size[p] = size;
  } catch (...) {
    std::free(p);
    throw;
  }
  return p;
}

void free_block(void* p, std::size_t bytes) noexcept {
  if (bytes < kLargeBlock) return ::operator delete(p);
  LargeBlocks& b = large_blocks();
  std::lock_guard<std::mutex> lock(b.m);
  const auto it = b.size.find(p);
  const std::size_t size = it != b.size.end() ? it->second : huge_rounded(bytes);
  if (it != b.size.end()) b.size.erase(it);
  if (b.scopes > 0) {
    // Kept, within the capacity reserved (no allocation); when kKept are kept already, in place
    // of the smallest of them if it is larger (a larger block serves more requests).
    if (b.kept.size() < kKept) {
      b.kept.emplace_back(p, size);
      return;
    }
    auto smallest = std::min_element(b.kept.begin(), b.kept.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
    if (smallest->second < size) std::swap(smallest->first, p), smallest->second = size;
  }
  std::free(p);
}

BlockReuse::BlockReuse() {
  LargeBlocks& b = large_blocks();
  std::lock_guard<std::mutex> lock(b.m);
  b.kept.reserve(kKept);  // free_block then keeps a block without allocating
  ++b.scopes;
}

BlockReuse::~BlockReuse() {
  LargeBlocks& b = large_blocks();
  std::lock_guard<std::mutex> lock(b.m);
  if (--b.scopes > 0) return;
  for (const auto& k : b.kept) std::free(k.first);
  b.kept.clear();
}

}  // namespace viaduct
