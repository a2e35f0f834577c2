// The assessment's pieces that need no sweep (issue #38): f3 of each member, EN 1991-2 Fig. 6.9
// answered for a bridge, the resonance speeds the report lists, the unit column of checks.csv.
#include <catch2/catch.hpp>
#include <cmath>

#include "viaduct/load/train.hpp"
#include "viaduct/study/assess.hpp"
#include "viaduct/study/assessment.hpp"

using namespace viaduct;

namespace {

// [Hz] n-th bending frequency of a simply supported Bernoulli–Euler beam.
double ss_frequency(int n, double L, double EI, double m) { return n * n * M_PI / (2.0 * L * L) * std::sqrt(EI / m); }

model::BridgeParams rigid_chain(const std::vector<double>& lengths, bool continuous) {
  model::BridgeParams b;
  for (double L : lengths) b.spans.push_back({L, 2.0e10, 12000.0});
  b.element_size = 0.25;
  b.bearings.rigid = true;
  b.continuous = continuous;
  return b;
}

study::Scenario scenario_of(const model::BridgeParams& b) {
  study::Scenario sc;
  sc.bridge = b;
  return sc;
}

study::AssessPlan plan_of(const study::Scenario& sc, double line_speed_kmh) {
  study::AssessPlan p;
  p.config.line_speed = line_speed_kmh / 3.6;
  p.members = study::member_frequencies(sc.bridge, std::nullopt);
  return p;
}

}  // namespace

TEST_CASE("f3 of each member: every simply supported span its own third bending mode, a continuous deck one member") {
  // Spans of 12, 20 and 31 m on rigid bearings: each member's f1 and f3 are the closed form's
  // (0.25 m elements: the third mode of the 12 m span has 16 elements per half-wave, FE error
  // well under 0.1 %; 0.5 % allows for it).
  const std::vector<double> L = {12.0, 20.0, 31.0};
  const auto members = study::member_frequencies(rigid_chain(L, false), std::nullopt);
  REQUIRE(members.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    INFO("span " << k + 1);
    CHECK(members[k].span == static_cast<int>(k + 1));
    CHECK(members[k].f3_order == 3);
    CHECK(members[k].f1 == Approx(ss_frequency(1, L[k], 2.0e10, 12000.0)).epsilon(0.005));
    CHECK(members[k].f3 == Approx(ss_frequency(3, L[k], 2.0e10, 12000.0)).epsilon(0.005));
    CHECK(members[k].cutoff == Approx(std::max({30.0, 1.5 * members[k].f1, members[k].f3})));
  }
  // The same spans as one continuous deck: one member, the deck (span 0).
  const auto deck = study::member_frequencies(rigid_chain(L, true), std::nullopt);
  REQUIRE(deck.size() == 1);
  CHECK(deck.front().span == 0);
  CHECK(deck.front().f1 < members[2].f1 * 1.6);  // the deck's lowest mode is the long span's, stiffened by its neighbours
}

TEST_CASE("Fig. 6.9 answered: above 200 km/h, a continuous deck, long spans, n0 inside and outside Fig. 6.10") {
  SECTION("V > 200 km/h: required at the first box") {
    const study::Scenario sc = scenario_of(rigid_chain({20.0}, false));
    const auto d = study::dynamic_analysis_need(plan_of(sc, 300.0), sc);
    CHECK(d.required);
    CHECK(d.steps.size() == 1);
    CHECK(d.conclusion.find("200 km/h") != std::string::npos);
  }
  SECTION("V <= 200 km/h on a continuous deck: not required (note 5)") {
    const study::Scenario sc = scenario_of(rigid_chain({20.0, 20.0}, true));
    const auto d = study::dynamic_analysis_need(plan_of(sc, 160.0), sc);
    CHECK_FALSE(d.required);
    CHECK(d.steps.size() == 2);
  }
  SECTION("spans of 40 m and more: not required") {
    const study::Scenario sc = scenario_of(rigid_chain({45.0, 40.0}, false));
    const auto d = study::dynamic_analysis_need(plan_of(sc, 160.0), sc);
    CHECK_FALSE(d.required);
    CHECK(d.steps.back().answer == "yes: every span");
  }
  SECTION("n0 within Fig. 6.10: the torsion and Annex F boxes are said to be unanswered") {
    // 20 m, EI 2e10, 12 t/m: n0 = 5.07 Hz within [4.0, 10.3] Hz.
    const study::Scenario sc = scenario_of(rigid_chain({20.0}, false));
    const auto d = study::dynamic_analysis_need(plan_of(sc, 160.0), sc);
    REQUIRE(d.members.size() == 1);
    CHECK(d.members[0].lower == Approx(4.0));
    CHECK(d.members[0].upper == Approx(94.76 * std::pow(20.0, -0.748)));
    CHECK(d.members[0].within());
    CHECK(d.required);
    CHECK(d.steps.back().answer.find("not answered") != std::string::npos);
  }
  SECTION("n0 below Fig. 6.10's lower limit: required") {
    study::Scenario sc = scenario_of(rigid_chain({20.0}, false));
    sc.bridge.spans[0].EI = 0.5e10;  // n0 = 2.5 Hz < 4 Hz
    const auto d = study::dynamic_analysis_need(plan_of(sc, 160.0), sc);
    CHECK_FALSE(d.members[0].within());
    CHECK(d.required);
    CHECK(d.conclusion.find("Fig. 6.10") != std::string::npos);
  }
}

TEST_CASE("resonance speeds f d / j: every one in the speed range, none outside, per train") {
  study::AssessPlan p;
  p.config.v_min = 100 / 3.6, p.config.v_max = 360 / 3.6, p.config.harmonics = 3;
  p.f_cut = 30.0;
  model::DeckMode m1, m2, m3;
  m1.frequency_hz = 5.0, m2.frequency_hz = 20.0, m3.frequency_hz = 40.0;  // the third above the cut-off
  p.deck_modes = {m1, m2, m3};
  study::Variant v;
  v.scenario.trains = {load::regular_train("R18", 20, 18.0, 170e3)};
  p.variants = {v};
  const double d = load::characteristic_distance(v.scenario.trains[0]);
  REQUIRE(d == Approx(18.0));
  CHECK_THROWS_WITH(study::resonance_speeds(p), Catch::Contains("0 characteristic distances for 1 trains"));
  p.train_distance = {d};
  const auto rs = study::resonance_speeds(p);
  // mode 1: 5·18/j = 90, 45, 30 m/s = 324, 162, 108 km/h, all in range; mode 2: 1296, 648, 432 km/h, none.
  std::vector<double> expected;
  for (double f : {5.0, 20.0})
    for (int j = 1; j <= 3; ++j)
      if (f * d / j >= p.config.v_min && f * d / j <= p.config.v_max) expected.push_back(f * d / j);
  REQUIRE(rs.size() == expected.size());
  for (std::size_t i = 0; i < rs.size(); ++i) {
    CHECK(rs[i].speed == Approx(expected[i]));
    CHECK(rs[i].speed == Approx(rs[i].frequency_hz * rs[i].distance / rs[i].harmonic));
    CHECK(rs[i].frequency_hz <= p.f_cut);
  }
  CHECK(rs.size() == 3);
}

TEST_CASE("checks.csv's unit column follows the quantity's suffix") {
  CHECK(study::quantity_unit("S1_mid_acc_mps2") == "m/s2");
  CHECK(study::quantity_unit("S1_mid_disp_m") == "m");
  CHECK(study::quantity_unit("S1_mid_moment_Nm") == "N m");
  CHECK(study::quantity_unit("span1_start_reaction_N") == "N");
  CHECK(study::quantity_unit("span1_start_rot_rad") == "rad");
  CHECK(study::quantity_unit("lateral_f1_hz") == "Hz");
  CHECK(study::quantity_unit("unloading_ratio") == "-");
}

TEST_CASE("clauses of both editions: 2003 in full, 2023 where known, else the 2003 clause named to confirm") {
  using study::Clause;
  using study::Edition;
  // Every enumerator from the first to the last has its reference (a new one without it throws).
  for (int k = static_cast<int>(Clause::trains); k <= static_cast<int>(Clause::lateral); ++k) {
    const auto c = static_cast<Clause>(k);
    const std::string old = study::cite(Edition::en2003, c), now = study::cite(Edition::en2023, c);
    INFO(old << " / " << now);
    CHECK((old.rfind("EN 1991-2 ", 0) == 0 || old.rfind("EN 1990 ", 0) == 0));
    CHECK(study::clause_known(Edition::en2003, c));
    CHECK(now.find("2023") != std::string::npos);
    if (study::clause_known(Edition::en2023, c)) {
      CHECK(now.find("Section 8") != std::string::npos);
      CHECK(now.find("to confirm") == std::string::npos);
    } else {
      // the 2003 clause, without its document's name, inside the 2023 reference
      const std::string clause = old.substr(old.find(' ', old.find(' ') + 1) + 1);
      CHECK(now.find("[20") != std::string::npos);
      CHECK(now.find(clause + "; to confirm]") != std::string::npos);
      CHECK(study::cite_brief(Edition::en2023, c).find("to confirm]") != std::string::npos);
    }
  }
  CHECK(study::cite(Edition::en2003, Clause::design_effect) == "EN 1991-2 6.4.6.5(3)");
  CHECK(study::cite_brief(Edition::en2003, Clause::damping) == "Table 6.6");
  CHECK(study::cite(Edition::en2023, Clause::trains) == "EN 1991-2:2023 Section 8, Fig. 8.12 and Table 8.4 (HSLM-A)");
  CHECK(study::cite(Edition::en2023, Clause::determinant_length) == "EN 1991-2:2023 Section 8, Table 8.2");
  CHECK(study::cite(Edition::en2023, Clause::speeds) == "EN 1991-2:2023 Section 8 [2003: 6.4.6.2; to confirm]");
  CHECK(study::cite(Edition::en2023, Clause::deck_acceleration) == "EN 1990:2023 Annex A.2 [2002/A1: A2.4.4.2.1(4); to confirm]");
  CHECK(study::edition_of("2023") == Edition::en2023);
  CHECK(std::string(study::edition_name(study::edition_of("2003"))) == "2003");
  CHECK_THROWS_WITH(study::edition_of("2024"), Catch::Contains("2003") && Catch::Contains("2023"));
}

TEST_CASE("the flow chart cites the edition chosen") {
  study::Scenario sc = scenario_of(rigid_chain({20.0}, false));
  sc.bridge.spans[0].EI = 0.5e10;  // n0 = 2.5 Hz < 4 Hz: the frequency limits decide
  study::AssessPlan p = plan_of(sc, 160.0);
  p.config.edition = study::Edition::en2023;
  const auto d = study::dynamic_analysis_need(p, sc);
  CHECK(d.conclusion.find("EN 1991-2:2023 Section 8 [2003: Fig. 6.10; to confirm]") != std::string::npos);
  for (const auto& s : d.steps) CHECK(s.question.find("of Fig. 6.10?") == std::string::npos);
}
