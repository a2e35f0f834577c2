#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "viaduct/io/scenario.hpp"
#include "source_dir.hpp"

using namespace viaduct;

TEST_CASE("EN 1991-2 Annex D's fatigue train Type 1: its total load and length as REFERENCE.md gives them") {
  // REFERENCE.md §11: 6 axles of 225 kN, then 12 coaches of 4 axles of 110 kN; 6630 kN over
  // 262.10 m buffer to buffer, of which 1.4 m ahead of the first axle and 1.8 m behind the last.
  const load::Train t = io::read_train_file(std::string(VIADUCT_SOURCE_DIR) + "/data/trains/fatigue/type1.csv");
  REQUIRE(t.n_axles() == 54);
  CHECK(t.total_load() == Approx(6630e3).epsilon(1e-12));
  CHECK(t.length() + 1.4 + 1.8 == Approx(262.10).epsilon(1e-12));
  // The locomotive's bogies (2.2 m) and the coaches' (2.6 m), 20.3 m a coach.
  CHECK(t.offset[1] - t.offset[0] == Approx(2.2));
  CHECK(t.offset[4] - t.offset[3] == Approx(2.2));
  CHECK(t.offset[7] - t.offset[6] == Approx(2.6));
  CHECK(t.offset[10] - t.offset[6] == Approx(20.3));
  for (std::size_t a = 0; a < t.n_axles(); ++a) CHECK(t.load[a] == (a < 6 ? 225e3 : 110e3));
}
