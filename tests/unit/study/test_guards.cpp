// Accuracy guards: the shipped scenarios lie in the measured region (no warning); a step too
// coarse for the filter's band edge or for the crossing of a span warns with the risked error.
#include <catch2/catch.hpp>

#include "viaduct/io/scenario.hpp"
#include "viaduct/study/guards.hpp"

using namespace viaduct;

namespace {
const std::string src = VIADUCT_SOURCE_DIR;
study::Scenario shipped(const std::string& name, const std::vector<std::string>& set = {}) {
  return io::to_scenario(io::load_flat(src + "/scenarios/" + name + ".toml", set));
}
}  // namespace

TEST_CASE("accuracy guards: silent on the shipped scenarios, a warning with the risk outside") {
  for (const char* name : {"old-guadiana-sensitivity", "hslm-simply-supported", "old-guadiana-talgo"}) {
    INFO(name);
    const study::Scenario sc = shipped(name);
    std::vector<double> speeds = sc.sweep_speeds;
    if (sc.run_speed) speeds.push_back(*sc.run_speed);
    CHECK(study::accuracy_warnings(sc, speeds).empty());
  }
  // 4 ms against the 60 Hz band edge: f_c·dt = 0.24.
  const study::Scenario coarse = shipped("old-guadiana-sensitivity", {"analysis.dt=0.004"});
  const auto w = study::accuracy_warnings(coarse, coarse.sweep_speeds);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Catch::Contains("analysis.dt = 0.004 s samples the filter's band edge 60 Hz 4.2 times per period (f_c·dt = 0.24)") &&
                       Catch::Contains("15 % at 0.24") && Catch::Contains("take analysis.dt <= 0.001 s"));
  // Without the filter the band edge does not apply; a train at 10⁶ km/h crosses 15 m in a step.
  const study::Scenario raw = shipped("hslm-simply-supported", {"filter.enabled=false"});
  CHECK(study::accuracy_warnings(raw, raw.sweep_speeds).empty());
  const auto fast = study::accuracy_warnings(raw, {1e6 / 3.6});
  REQUIRE(fast.size() == 1);
  CHECK_THAT(fast[0], Catch::Contains("at 1e+06 km/h the axles cross the shortest span (15 m) in") &&
                          Catch::Contains("52 % at 2.5"));
}
