#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"

using namespace viaduct;

TEST_CASE("parallel_for visits every index exactly once for any thread count") {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> hits(1000);
    parallel_for(hits.size(), threads, [&](std::size_t i, int worker) {
      REQUIRE(worker >= 0);
      REQUIRE(worker < threads);
      hits[i]++;
    });
    for (auto& h : hits) REQUIRE(h.load() == 1);
  }
  REQUIRE_THROWS_AS(parallel_for(3, 0, [](std::size_t, int) {}), InputError);
}

TEST_CASE("input checks name the value and the violated constraint") {
  REQUIRE_NOTHROW(require_positive(1.0, "k"));
  REQUIRE_THROWS_WITH(require_positive(0.0, "pad k"), Catch::Contains("pad k must be > 0"));
  REQUIRE_THROWS_WITH(require_positive(-1.0, "pad k"), Catch::Contains("> 0"));
  REQUIRE_THROWS_WITH(require_positive(std::nan(""), "dt"), Catch::Contains("dt must be finite"));
  REQUIRE_NOTHROW(require_non_negative(0.0, "c"));
  REQUIRE_THROWS_AS(require_non_negative(-1e-30, "c"), InputError);
  const InputError e(SourceLocation{"a.toml", 12, "track.pad.k"}, "must be > 0");
  REQUIRE(std::string(e.what()) == "a.toml:12: key 'track.pad.k': must be > 0");
}
