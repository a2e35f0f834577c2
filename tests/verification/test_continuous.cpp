// Continuous decks over intermediate supports (issue #20 part 3): frequencies against the
// frequency equation of a two-span continuous beam, the permanent reactions against the
// three-moment equation, the static influence lines of a force against the closed forms, and the
// modal path against Newmark on the support's reaction and hogging moment.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/influence.hpp"

using namespace viaduct;

namespace {
const double kEI = 7.694e9, kMass = 15000.0;  // the shipped HSLM deck's

model::BridgeParams continuous_spans(double L1, double L2, double element_size) {
  model::BridgeParams b = vt::span(L1, kEI, kMass, element_size);
  b.spans.push_back({L2, kEI, kMass});
  b.continuous = true;
  return b;
}

// Two continuous spans L1, L2 (same EI, m), pinned at the three supports. Each span, pinned at its
// far end, answers a rotation θ of the middle support with the curvature 2βθ / (coth βL − cot βL)
// (w = A sin βx + B sinh βx from the far end); the moment is continuous over the support, so
// c(βL1) + c(βL2) = 0 with c = coth − cot, or, free of the poles of cot,
// h(β) = (coth βL1 sin βL1 − cos βL1) sin βL2 + (coth βL2 sin βL2 − cos βL2) sin βL1 = 0
// (it holds the modes with the support at rest, sin βL1 = sin βL2 = 0, too). Roots by a scan
// and bisection, as frequencies [Hz].
std::vector<double> two_span_frequencies(double L1, double L2, std::size_t n) {
  auto h = [&](double beta) {
    auto part = [&](double len) { return std::sin(beta * len) / std::tanh(beta * len) - std::cos(beta * len); };
    return part(L1) * std::sin(beta * L2) + part(L2) * std::sin(beta * L1);
  };
  std::vector<double> out;
  const double d_beta = 1e-3 / std::max(L1, L2);
  for (double b0 = d_beta; out.size() < n; b0 += d_beta) {
    double lo = b0, hi = b0 + d_beta;
    if (h(lo) * h(hi) > 0.0) continue;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (h(lo) * h(mid) <= 0.0 ? hi : lo) = mid;
    }
    const double beta = 0.5 * (lo + hi);
    out.push_back(beta * beta / (2 * M_PI) * std::sqrt(kEI / kMass));
  }
  return out;
}

std::size_t quantity_index(const std::vector<std::string>& names, const std::string& n) {
  const auto it = std::find(names.begin(), names.end(), n);
  if (it == names.end()) FAIL("no quantity " << n);
  return static_cast<std::size_t>(it - names.begin());
}
}  // namespace

TEST_CASE("continuous deck: frequencies of two spans against the frequency equation") {
  for (const auto& [L1, L2] : std::vector<std::pair<double, double>>{{20.0, 20.0}, {20.0, 15.0}}) {
    const model::Structure s = model::build_structure(continuous_spans(L1, L2, 0.25), std::nullopt);
    REQUIRE(s.bearings.size() == 3);
    const auto modes = model::deck_bending_modes(s, 4);
    const auto ref = two_span_frequencies(L1, L2, 4);
    REQUIRE(modes.size() == 4);
    for (std::size_t j = 0; j < 4; ++j) {
      std::printf("continuous %g + %g m: mode %zu %.6f Hz (frequency equation %.6f)\n", L1, L2, j + 1, modes[j].frequency_hz, ref[j]);
      // 60 to 80 elements per span: Hermite elements' frequencies converge as h⁴ (the simply
      // supported span is within 1e-7 at this size); 1e-6.
      CHECK(modes[j].frequency_hz == Approx(ref[j]).epsilon(1e-6));
    }
    if (L1 == L2) {  // the antisymmetric first mode is a simply supported span's; the second βL = 3.9266
      CHECK(modes[0].frequency_hz == Approx(vt::closed_form_f(1, L1, kEI, kMass)).epsilon(1e-6));
      CHECK(modes[1].frequency_hz / modes[0].frequency_hz == Approx(3.926602 * 3.926602 / (M_PI * M_PI)).epsilon(1e-6));
    }
  }
}

TEST_CASE("continuous deck: the permanent reactions under the deck's weight by the three-moment equation") {
  // Uniform q on spans L1, L2 (same EI): M_B = −q (L1³ + L2³) / (8 (L1 + L2)); the end reactions
  // q L/2 + M_B/L, the middle one the rest. The static solve is exact for a uniform load with
  // consistent nodal loads (the Hermite cubic is the exact deflection between nodes up to the
  // quartic's nodal values, which are exact): 1e-9.
  for (const bool rigid : {true, false}) {
    model::BridgeParams b = continuous_spans(20.0, 15.0, 0.5);
    b.added_mass_per_m = 2000.0;
    if (!rigid) b.bearings = {false, 1e13, 0.0};  // k L³/EI = 1e7: nearly rigid
    const model::Structure s = model::build_structure(b, std::nullopt);
    REQUIRE(s.bearings.size() == 3);
    const double q = 9.80665 * (kMass + 2000.0), L1 = 20.0, L2 = 15.0;
    const double MB = -q * (L1 * L1 * L1 + L2 * L2 * L2) / (8 * (L1 + L2));
    const double RA = q * L1 / 2 + MB / L1, RC = q * L2 / 2 + MB / L2, RB = q * (L1 + L2) - RA - RC;
    std::printf("continuous 20 + 15 m %s: permanent %.6g %.6g %.6g N (three-moment %.6g %.6g %.6g)\n", rigid ? "rigid" : "elastic",
                s.bearings[0].permanent, s.bearings[1].permanent, s.bearings[2].permanent, RA, RB, RC);
    // Elastic: the springs settle by R/k ≈ 4e-7 m, which moves the reactions by about 1e-5
    // (measured 7.5e-6 on the end one): 1e-4.
    const double tol = rigid ? 1e-9 : 1e-4;
    CHECK(s.bearings[0].permanent == Approx(RA).epsilon(tol));
    CHECK(s.bearings[1].permanent == Approx(RB).epsilon(tol));
    CHECK(s.bearings[2].permanent == Approx(RC).epsilon(tol));
    CHECK(s.bearings[1].name == "support2");
    CHECK(s.bearings[1].elements.size() == 2);
  }
}

TEST_CASE("continuous deck: the static influence lines of support moment, span moment and reactions") {
  // A unit force at a in span 1 (b = L1 − a): M_B = −a (L1² − a²) / (2 L1 (L1 + L2)) (rotation
  // compatibility over the middle support); M(x) in span 1 = the simply supported span's moment +
  // M_B x / L1; R_A = b/L1 + M_B/L1, R_C = M_B/L2, R_B = 1 − R_A − R_C. In span 2 by symmetry of
  // the argument (a measured from C).
  const double L1 = 20.0, L2 = 15.0;
  study::RunSettings rs;
  const std::vector<study::StationSpec> st = {{"B", true, 0, L1, 0.0}, {"mid1", true, 0, L1 / 2, 0.0}, {"mid2", true, 1, L2 / 2, 0.0}};
  const study::PreparedModel pm = study::prepare_model(model::build_structure(continuous_spans(L1, L2, 0.25), std::nullopt), st, rs, false, true);
  const study::InfluenceLines il = study::influence_lines(pm);
  const std::size_t qB = quantity_index(il.names, "B_moment_Nm"), q1 = quantity_index(il.names, "mid1_moment_Nm"),
                    q2 = quantity_index(il.names, "mid2_moment_Nm"), rA = quantity_index(il.names, "support1_reaction_N"),
                    rB = quantity_index(il.names, "support2_reaction_N"), rC = quantity_index(il.names, "support3_reaction_N");
  double e_m = 0.0, e_r = 0.0;
  for (double x = 0.25; x < L1 + L2; x += 0.25) {  // the force on nodes: the lines are exact there
    if (std::abs(x - L1) < 1e-9) continue;        // on the support: the reaction takes it all (below)
    double MB, RA, RC, M1, M2;
    if (x < L1) {
      const double a = x, b = L1 - a;
      MB = -a * (L1 * L1 - a * a) / (2 * L1 * (L1 + L2));
      RA = b / L1 + MB / L1;
      RC = MB / L2;
      M1 = (a <= L1 / 2 ? a / 2 : b / 2) + MB / 2;
      M2 = MB / 2;
    } else {
      const double c = L1 + L2 - x, d = L2 - c;  // c from C, d from B
      MB = -c * (L2 * L2 - c * c) / (2 * L2 * (L1 + L2));
      RC = d / L2 + MB / L2;
      RA = MB / L1;
      M1 = MB / 2;
      M2 = (d <= L2 / 2 ? d / 2 : c / 2) + MB / 2;
    }
    const double RB = 1.0 - RA - RC;
    e_m = std::max({e_m, std::abs(il.at(qB, x) - MB), std::abs(il.at(q1, x) - M1), std::abs(il.at(q2, x) - M2)});
    e_r = std::max({e_r, std::abs(il.at(rA, x) - RA), std::abs(il.at(rB, x) - RB), std::abs(il.at(rC, x) - RC)});
  }
  CHECK(il.at(rB, L1) == Approx(1.0).margin(1e-9));  // a force on the support goes straight into it
  std::printf("continuous 20 + 15 m, unit force: moments within %.2e of L1/4, reactions within %.2e\n", e_m / (L1 / 4), e_r);
  // Forces on nodes, stations on nodes: the Hermite elements' moments are exact (rounding: 1e-9).
  CHECK(e_m / (L1 / 4) < 1e-8);
  CHECK(e_r < 1e-8);
}

TEST_CASE("continuous deck: modal superposition with static correction agrees with Newmark on reaction and hogging moment") {
  // Two 15 m spans of the shipped HSLM deck, continuous, HSLM-A1 at 250 km/h (near the first
  // mode's resonance, d = 18 m). Reference: Newmark at 0.1 ms.
  study::Scenario sc = vt::shipped("hslm-simply-supported", {"filter.enabled=false", "bridge.continuous=true"});
  sc.bridge.spans.push_back(sc.bridge.spans.front());
  sc.stations = {{"B", true, 0, sc.bridge.spans.front().length, 0.0}, {"mid", true, 0, sc.bridge.spans.front().length / 2, 0.0}};
  const load::Train& a1 = sc.trains.front();
  const double v = 250 / 3.6;
  study::RunSettings ref = sc.settings;
  ref.method = study::Method::newmark;
  ref.dt = 1e-4;
  const study::RunResult rn = study::simulate(study::prepare_model(sc, true, true), a1, v, ref);
  study::Scenario md = sc;
  md.settings.method = study::Method::modal;
  md.settings.modal.static_correction = true;
  md.settings.dt = 1e-3;
  const study::RunResult rm = study::simulate(study::prepare_model(md, true, true), a1, v, md.settings);
  for (const char* name : {"B_moment_Nm", "mid_moment_Nm", "support2_reaction_N", "support1_rot_rad"}) {
    const study::EffectHistory* a = nullptr;
    const study::EffectHistory* b = nullptr;
    for (const auto& e : rn.effects)
      if (e.name == name) a = &e;
    for (const auto& e : rm.effects)
      if (e.name == name) b = &e;
    REQUIRE(a);
    REQUIRE(b);
    const double peak = a->value.cwiseAbs().maxCoeff();
    const double peak_modal = b->value.cwiseAbs().maxCoeff();
    std::printf("continuous 2 x 15 m, HSLM-A1 250 km/h, %s: modal peak %.6g, Newmark 0.1 ms %.6g (%.2e)\n", name, peak_modal, peak,
                peak_modal / peak - 1);
    // Measured (2026-12-02): the four peaks within 6.7e-5 to 2.6e-4 of Newmark's; 2e-3 leaves room
    // for another compiler's rounding and stays well inside the assessment's 1 % target.
    CHECK(peak_modal == Approx(peak).epsilon(2e-3));
  }
}

// 16 s under the sanitizers: [long], run in the optimised tier.
TEST_CASE("continuous deck: rigid bearings' forces match very stiff elastic ones (k w), with and without track", "[long]") {
  // The middle support's force is recovered from both deck elements' rows, the whole deck's modal
  // damping and, with a track, the sleeper links near it; an elastic bearing's force is k·w
  // exactly. k = 1e12 N/m (1e5 times the deck's EI/L³): the same bridge.
  auto run = [](study::Scenario sc, bool rigid, double alpha, const load::Train& train, double v) {
    sc.bridge.continuous = true;
    return vt::run_on_bearings(sc, rigid, alpha, train, v);
  };
  auto history = [](const study::RunResult& r, const std::string& name) -> const Vector& {
    for (const auto& e : r.effects)
      if (e.name == name) return e.value;
    FAIL("no load effect " << name);
    return r.effects.front().value;
  };
  // Old Guadiana's two spans made continuous, its track and the Talgo: the axles reach the deck
  // through the track (the simply supported deck's test measured 6e-4 to 7.5e-4 of the peak).
  study::Scenario og = vt::shipped("old-guadiana-talgo");
  REQUIRE(og.bridge.spans.size() == 2);
  const study::RunResult a = run(og, true, 0.0, og.trains.front(), *og.run_speed);
  const study::RunResult b = run(og, false, 0.0, og.trains.front(), *og.run_speed);
  for (const char* name : {"support1_reaction_N", "support2_reaction_N", "support3_reaction_N"}) {
    const Vector& ra = history(a, name);
    const Vector& rb = history(b, name);
    const double err = (ra - rb).cwiseAbs().maxCoeff() / rb.cwiseAbs().maxCoeff();
    std::printf("Old Guadiana continuous, with track, %s: rigid against k = 1e12 N/m: worst %.2e of the peak\n", name, err);
    CHECK(err < 2e-3);
  }
  // Axles straight on the deck (two 15 m HSLM spans): HHT damps the stiff springs' ringing at
  // each axle's step onto a bearing; their peaks are the reference.
  study::Scenario hs = vt::shipped("hslm-simply-supported");
  hs.bridge.spans.push_back(hs.bridge.spans.front());
  const study::RunResult c = run(hs, true, -0.3, hs.trains.front(), 300 / 3.6);
  const study::RunResult d = run(hs, false, -0.3, hs.trains.front(), 300 / 3.6);
  for (const char* name : {"support1_reaction_N", "support2_reaction_N"}) {
    const Vector& rc = history(c, name);
    const Vector& rd = history(d, name);
    std::printf("continuous 2 x 15 m, HSLM-A1 300 km/h on the deck, %s: max %.6g (k w %.6g), min %.6g (k w %.6g)\n", name,
                rc.maxCoeff(), rd.maxCoeff(), rc.minCoeff(), rd.minCoeff());
    CHECK(rc.maxCoeff() == Approx(rd.maxCoeff()).epsilon(2e-3));
    CHECK(rc.minCoeff() == Approx(rd.minCoeff()).epsilon(6e-3));
  }
}
