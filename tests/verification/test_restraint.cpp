// Spans with rotational restraint at their ends (issue #20 part 3: integral or frame abutments):
// frequencies against the clamped–clamped closed form and the transcendental equation of a beam
// with rotational springs, and the static moments of a clamped span under a crawling force.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/influence.hpp"

using namespace viaduct;

namespace {
const double L = 15.0, EI = 7.694e9, m = 15000.0;

double first_frequency(double k_rot) {
  model::BridgeParams b = vt::span(L, EI, m, 0.25);
  b.bearings.rotational_k = k_rot;
  const auto modes = model::deck_bending_modes(model::build_structure(b, std::nullopt), 1);
  REQUIRE(!modes.empty());
  return modes.front().frequency_hz;
}

// First (symmetric) mode of a pinned beam with rotational springs k at both ends: with x from
// mid-span, w = cos βx + C cosh βx, w(L/2) = 0 and the end moment balancing the spring,
// EI w''(L/2) + k w'(L/2) = 0 (k = 0: pinned, βL = π; k → ∞: clamped, βL = 4.7300). Bisection on
// βL in (π, 4.7300).
double spring_frequency(double k) {
  auto f = [&](double bl) {
    const double beta = bl / L, a = L / 2;
    const double C = -std::cos(beta * a) / std::cosh(beta * a);
    const double w1 = -beta * std::sin(beta * a) + C * beta * std::sinh(beta * a);
    const double w2 = -beta * beta * std::cos(beta * a) + C * beta * beta * std::cosh(beta * a);
    return EI * w2 + k * w1;
  };
  double lo = M_PI + 1e-9, hi = 4.7300407448627;
  REQUIRE(f(lo) * f(hi) < 0.0);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(lo) * f(mid) <= 0.0 ? hi : lo) = mid;
  }
  const double bl = 0.5 * (lo + hi);
  return bl * bl / (2 * M_PI * L * L) * std::sqrt(EI / m);
}
}  // namespace

TEST_CASE("rotational restraint: first frequency from pinned to clamped against closed forms") {
  const double f_pinned = vt::closed_form_f(1, L, EI, m);
  const double f_clamped = 4.7300407448627 * 4.7300407448627 / (2 * M_PI * L * L) * std::sqrt(EI / m);
  const double f0 = first_frequency(0.0), f_inf = first_frequency(1e16);
  std::printf("restraint: pinned %.6f Hz (closed form %.6f), clamped %.6f (%.6f)\n", f0, f_pinned, f_inf, f_clamped);
  // 60 elements: the FE frequencies within 1e-6 of the beam's (Hermite elements converge as h⁴).
  CHECK(f0 == Approx(f_pinned).epsilon(1e-6));
  CHECK(f_inf == Approx(f_clamped).epsilon(1e-5));  // k L / EI = 2e7: the spring's compliance 1e-7
  for (const double kappa : {1.0, 4.0, 20.0}) {  // k = κ EI / L
    const double k = kappa * EI / L, fe = first_frequency(k), ref = spring_frequency(k);
    std::printf("restraint: k = %g EI/L: %.6f Hz (transcendental %.6f)\n", kappa, fe, ref);
    CHECK(fe == Approx(ref).epsilon(1e-5));
    CHECK(fe > f0);
    CHECK(fe < f_inf);
  }
}

TEST_CASE("rotational restraint: a clamped span's static moments under a crawling force") {
  // Influence lines of a clamped–clamped beam (unit force at a, b = L − a, sagging positive):
  // the fixed-end moments M_A = −a b² / L², M_B = −a² b / L², and at mid-span the simply
  // supported span's moment (a/2 or b/2) plus the mean of the two; with the force at mid-span
  // M(L/2) = L/8 and M_A = −L/8.
  model::BridgeParams b = vt::span(L, EI, m, 0.25);
  b.bearings.rotational_k = 1e16;
  study::RunSettings rs;
  const study::PreparedModel pm = study::prepare_model(model::build_structure(b, std::nullopt),
                                                       {{"mid", true, 0, L / 2, 0.0}, {"end", true, 0, 0.0, 0.0}}, rs, false, true);
  const study::InfluenceLines il = study::influence_lines(pm);
  auto at = [&](const std::string& n) {
    for (std::size_t q = 0; q < il.names.size(); ++q)
      if (il.names[q] == n) return q;
    FAIL("no " << n);
    return std::size_t{0};
  };
  double worst_mid = 0.0, worst_end = 0.0;
  for (double a = 0.25; a < L; a += 0.25) {  // the force on nodes: the lines are exact there
    const double bb = L - a;
    const double MA = -a * bb * bb / (L * L), MB = -a * a * bb / (L * L);
    const double simple = a <= L / 2 ? a / 2 : bb / 2;
    const double mid_ref = simple + 0.5 * (MA + MB);
    worst_mid = std::max(worst_mid, std::abs(il.at(at("mid_moment_Nm"), a) - mid_ref));
    worst_end = std::max(worst_end, std::abs(il.at(at("end_moment_Nm"), a) - MA));
  }
  std::printf("clamped span, unit force: mid-span moment error %.2e, end moment error %.2e of L/8\n", worst_mid / (L / 8),
              worst_end / (L / 8));
  // Forces on nodes and stations on nodes: no element next to a station carries a force inside
  // it, so the Hermite elements' moments are exact; the clamping spring (k L/EI = 2e7) leaves
  // 1e-7 (measured): 1e-5.
  CHECK(worst_mid / (L / 8) < 1e-5);
  CHECK(worst_end / (L / 8) < 1e-5);
  CHECK(il.at(at("mid_moment_Nm"), L / 2) == Approx(L / 8).epsilon(1e-5));
}
