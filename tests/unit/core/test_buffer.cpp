#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "viaduct/core/buffer.hpp"

using namespace viaduct;

TEST_CASE("UninitAllocator: large blocks aligned to 2 MB, kept and given again inside a BlockReuse") {
  using Buf = std::vector<double, UninitAllocator<double>>;
  const std::size_t big = kLargeBlock / sizeof(double) + 1000;
  {
    Buf b(big);
    REQUIRE(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t{2} << 20) == 0);
    b.assign(big, 1.5);
    REQUIRE(b[big - 1] == 1.5);
  }
  const BlockReuse reuse;
  const double* first = nullptr;
  {
    Buf b(3 * big);
    first = b.data();
  }
  {
    const BlockReuse nested;  // scopes nest: the inner one's end frees nothing kept
  }
  {
    Buf third(big);  // would leave more than half of the kept block unused: a block of its own
    REQUIRE(third.data() != first);
    Buf smaller(3 * big - 100);  // held by the kept block
    REQUIRE(smaller.data() == first);
  }
  {
    std::vector<Buf> many;  // more than are kept (3): the others are freed
    for (int i = 0; i < 5; ++i) many.emplace_back(big);
  }
  std::vector<Buf> again;  // the kept ones given once each, never two vectors one block
  for (int i = 0; i < 5; ++i) again.emplace_back(big);
  for (std::size_t i = 0; i < again.size(); ++i)
    for (std::size_t j = i + 1; j < again.size(); ++j) REQUIRE(again[i].data() != again[j].data());
  // Small vectors take operator new as any vector does.
  Buf s(10, 2.0);
  REQUIRE(s[9] == 2.0);
}
