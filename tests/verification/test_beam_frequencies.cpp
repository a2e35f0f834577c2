#include <catch2/catch.hpp>
#include <cstdio>

#include "helpers.hpp"

using namespace viaduct;

TEST_CASE("simply supported beam frequencies match f_n = (n² π / 2L²) √(EI/m)") {
  const double L = 20.0, EI = 1e10, m = 1e4;
  const model::Structure s = model::build_structure(vt::span(L, EI, m, 0.5), std::nullopt);
  const model::Modes modes = model::compute_modes(s, 5);
  for (int n = 1; n <= 5; ++n) {
    const double exact = vt::closed_form_f(n, L, EI, m);
    const double err = modes.frequency_hz[n - 1] / exact - 1.0;
    std::printf("beam mode %d: %.6f Hz, closed form %.6f Hz, error %.2e\n", n, modes.frequency_hz[n - 1], exact, err);
    // Cubic Hermite elements converge as h⁴ (error grows as n⁴): with 40 elements mode 1 is
    // within 3e-8 and mode 5 (8 elements per half wave) within 2e-5; the bound is 5e-5.
    REQUIRE(std::abs(err) < 5e-5);
  }
}

TEST_CASE("elastic bearings lower the frequency and tend to the rigid case") {
  const double L = 11.93, EI = 7.09e9, m = 8727;
  double previous = 0.0;
  for (double k : {1e8, 1e9, 1e10, 1e12}) {
    model::BridgeParams b = vt::span(L, EI, m, 0.5);
    b.bearings = {false, k, 0.0};
    const double f1 = model::compute_modes(model::build_structure(b, std::nullopt), 1).frequency_hz[0];
    REQUIRE(f1 > previous);
    REQUIRE(f1 < vt::closed_form_f(1, L, EI, m));
    previous = f1;
  }
  // k = 1e12 N/m is 5000 times the beam's 48EI/L³: within 0.1 % of rigid.
  REQUIRE(previous == Approx(vt::closed_form_f(1, L, EI, m)).epsilon(1e-3));
}
