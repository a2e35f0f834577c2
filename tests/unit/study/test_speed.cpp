#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "viaduct/core/error.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/study/speed.hpp"

using namespace viaduct;
using namespace viaduct::study;

TEST_CASE("a simulated train's speed is recovered within 0.5 % (spectral lines and axle peaks)") {
  // A 20 m span under 12 axles 13.14 m apart (a Talgo-like rake) at 43.0 m/s, 2 % damping.
  model::BridgeParams b;
  b.spans = {{20.0, 2e10, 15000.0}};
  b.element_size = 0.5;
  b.damping.ratio = 0.02;
  const model::Structure s = model::build_structure(b, std::nullopt);
  const auto st = resolve_stations(s, {{"mid", true, 0, 10.0, 0.0}});
  RunSettings rs;
  rs.dt = 2e-3;
  rs.filter.enabled = false;
  rs.free_vibration_s = 1.0;
  const double v = 43.0, d = 13.14;
  const RunResult r = simulate(s, st, load::regular_train("rake", 12, d, 140e3), v, rs);
  const SpeedEstimate sp = speed_from_spectrum(r.stations[0].acc, 500.0, d, 20.0, 80.0, 4);
  std::printf("speed from spectrum: %.3f m/s (true %.1f, %+.2f %%, resolution %.2f m/s)\n", sp.speed, v,
              100 * (sp.speed / v - 1), sp.uncertainty);
  REQUIRE(sp.speed == Approx(v).epsilon(0.005));  // issue #3: within 0.5 % (measured +0.37 %)
  // Axle peaks need a channel that sees each axle: on this 4.5 Hz span the vibration period
  // (0.22 s) rivals the axle interval (0.31 s), so use a stiff 10 m span (f1 = 22 Hz) whose
  // deflection follows the axles quasi-statically.
  model::BridgeParams stiff;
  stiff.spans = {{10.0, 2e10, 10000.0}};
  stiff.element_size = 0.5;
  stiff.damping.ratio = 0.02;
  const model::Structure s2 = model::build_structure(stiff, std::nullopt);
  const RunResult r2 = simulate(s2, resolve_stations(s2, {{"mid", true, 0, 5.0, 0.0}}),
                                load::regular_train("rake", 12, d, 140e3), v, rs);
  const SpeedEstimate pk = speed_from_peaks(r2.stations[0].disp, 500.0, d, 0.2);
  std::printf("speed from axle peaks: %.3f m/s (%+.2f %%, +- %.3f m/s from %d intervals)\n", pk.speed,
              100 * (pk.speed / v - 1), pk.uncertainty, pk.n_used);
  REQUIRE(pk.speed == Approx(v).epsilon(0.005));
  REQUIRE(pk.n_used >= 10);
  REQUIRE_THROWS_WITH(speed_from_spectrum(r.stations[0].acc, 500.0, d, 20.0, 900.0, 4), Catch::Contains("Nyquist"));
  REQUIRE_THROWS_AS(speed_from_spectrum(r.stations[0].acc, 500.0, 0.0, 20.0, 80.0), InputError);
  REQUIRE_THROWS_WITH(speed_from_peaks(Vector::Zero(100), 500.0, d, 0.2), Catch::Contains("fewer than 3 peaks"));
}
