#include <catch2/catch.hpp>
#include <cstdio>

#include "helpers.hpp"

using namespace viaduct;

TEST_CASE("single moving force on an undamped simply supported beam (Frýba)") {
  // REFERENCE.md §4: δ = max mid-span deflection / (P L³/48 EI) against α = v / (2 f1 L), many
  // modes. The maximum is taken over the whole run (it is reached during the crossing; at
  // α = 1 at the exit), checked independently with a 200-mode analytical solution.
  const double L = 20.0, EI = 1e10, m = 1e4, P = 1e5;
  const model::Structure s = model::build_structure(vt::span(L, EI, m, 0.5), std::nullopt);
  const auto stations = study::resolve_stations(s, {{"mid", true, 0, L / 2, 0.0}});
  const double f1 = vt::closed_form_f(1, L, EI, m);
  const double d_static = P * L * L * L / (48 * EI);
  const std::vector<std::pair<double, double>> cases = {
      {0.1, 1.0965}, {0.25, 1.2576}, {0.5, 1.7054}, {0.618, 1.7317}, {1.0, 1.5481}};
  for (const auto& [alpha, delta] : cases) {
    const double v = alpha * 2 * f1 * L;
    study::RunSettings rs;
    rs.filter.enabled = false;
    rs.free_vibration_s = 1.0 / f1;
    rs.dt = 1.0 / (f1 * 2000);  // 2000 steps per fundamental period
    const auto r = study::simulate(s, stations, load::regular_train("P", 1, 0.0, P), v, rs);
    const double got = r.stations[0].disp.maxCoeff() / d_static;
    const double err = got / delta - 1.0;
    std::printf("Fryba alpha = %.3f: delta = %.5f, reference %.4f, error %+.3f %%\n", alpha, got, delta, 100 * err);
    // Issue #2 asks for 0.5 %; the reference values carry 4-5 digits.
    REQUIRE(std::abs(err) < 0.005);
  }
}
