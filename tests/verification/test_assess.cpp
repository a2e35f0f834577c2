// The EN 1991-2 assessment's ingredients (issue #20 part 2): influence lines and the static
// extremes of trains and LM71 against closed forms for a simply supported span, the numbers of
// the standard (Table 6.6, Eq. 6.13, Φ2, Φ3, φ″, the cut-off) against values worked by hand, the
// assessment's speeds, and a sweep with load effects against run's quasi-static and histories.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "helpers.hpp"
#include "viaduct/io/assessment.hpp"
#include "viaduct/study/assess.hpp"
#include "viaduct/study/assessment.hpp"
#include "viaduct/study/influence.hpp"
#include "viaduct/study/quasi_static.hpp"
#include "viaduct/study/sweep.hpp"

using namespace viaduct;

namespace {
std::size_t index_of(const std::vector<std::string>& names, const std::string& n) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == n) return i;
  FAIL("no quantity " << n);
  return 0;
}
}  // namespace

TEST_CASE("LM71 on a simply supported span: mid-span moment, end reaction and deflection in closed form") {
  // L = 15 m, rigid bearings, 0.25 m elements. Mid-span moment: the closed-form influence line
  // (x/2, then (L − x)/2) under the four axles and 80 kN/m beyond 0.8 m from the outer ones, its
  // area integrated exactly, the group placed every 0.5 mm: the worst is not symmetric about
  // mid-span (an axle on it, 0.7 % above the symmetric placement). Reaction at the start: the last
  // axle on the bearing, IL 1 − x/L: R = 250e3 Σ (1 − a_k/L) + 80e3 ∫_{5.6}^{L} (1 − x/L) dx.
  const double L = 15.0, EI = 7.694e9, m = 15000.0;
  const model::Structure s = model::build_structure(vt::span(L, EI, m, 0.25), std::nullopt);
  study::RunSettings rs;
  const study::PreparedModel pm = study::prepare_model(s, {{"mid", true, 0, L / 2, 0.0}}, rs, false, true);
  const study::InfluenceLines il = study::influence_lines(pm);
  const auto lm = study::lm71_extremes(il, 1.0, 1.0);
  auto il_m = [&](double x) { return x <= 0 || x >= L ? 0.0 : (x <= L / 2 ? x / 2 : (L - x) / 2); };
  auto area_to = [&](double y) {  // ∫_0^y of the moment's influence line
    y = std::clamp(y, 0.0, L);
    return y <= L / 2 ? y * y / 4 : L * L / 8 - (L - y) * (L - y) / 4;
  };
  double M_ref = 0.0;
  for (double x1 = 0.0; x1 <= L + 4.8; x1 += 5e-4) {
    double Mx = 80e3 * (L * L / 8 - (area_to(x1 + 0.8) - area_to(x1 - 5.6)));
    for (int j = 0; j < 4; ++j) Mx += 250e3 * il_m(x1 - 1.6 * j);
    M_ref = std::max(M_ref, Mx);
  }
  double R_ref = 0.0;
  for (double a : {0.0, 1.6, 3.2, 4.8}) R_ref += 250e3 * (1 - a / L);
  R_ref += 80e3 * ((L - 5.6) - (L * L - 5.6 * 5.6) / (2 * L));
  const double M = lm[index_of(il.names, "mid_moment_Nm")].max;
  const double R = lm[index_of(il.names, "span1_start_reaction_N")].max;
  // Deflection at mid-span: the axles by the beam's closed-form influence line and the UDL by
  // integrating it (Simpson, 2000 panels per side).
  auto w = [&](double x) {  // deflection at L/2 under a unit force at x
    const double a = std::min(x, L - x);
    return a * (3 * L * L - 4 * a * a) / (48 * EI);
  };
  double w_ref = 0.0;
  for (double a : {-2.4, -0.8, 0.8, 2.4}) w_ref += 250e3 * w(L / 2 + a);
  const int n = 2000;
  const double b = L / 2 - 3.2, h = b / n;
  double area = 0.0;
  for (int i = 0; i <= n; ++i) area += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * w(i * h);
  w_ref += 2 * 80e3 * area * h / 3;
  const double wd = lm[index_of(il.names, "mid_disp_m")].max;
  std::printf("LM71, 15 m span: moment %.6g (closed form %.6g), reaction %.6g (%.6g), deflection %.6g (%.6g)\n", M, M_ref, R,
              R_ref, wd, w_ref);
  // The moment's influence line is exact at the node station except next to a loaded element
  // (0.5 % of P·L/4 per axle there, test_load_effects; one axle of four): 2e-3. Reactions and
  // deflections at nodes are exact, the placement has an axle on every sample: 1e-3.
  CHECK(M == Approx(M_ref).epsilon(2e-3));
  CHECK(R == Approx(R_ref).epsilon(1e-3));
  CHECK(wd == Approx(w_ref).epsilon(1e-3));
  CHECK(lm[index_of(il.names, "mid_moment_Nm")].min == Approx(0.0).margin(1e-6 * M));  // no hogging on a simple span
  // α and the load factor scale everything.
  CHECK(study::lm71_extremes(il, 1.21, 0.5)[index_of(il.names, "mid_moment_Nm")].max == Approx(0.605 * M).epsilon(1e-12));
}

TEST_CASE("static extremes of a crawling train equal the quasi-static response of a run at its samples") {
  const double L = 12.0, EI = 5e9, m = 12000.0;
  const model::Structure s = model::build_structure(vt::span(L, EI, m, 0.25), std::nullopt);
  study::RunSettings rs;
  rs.filter.enabled = false;
  rs.dt = 1e-3;
  const study::PreparedModel pm = study::prepare_model(s, {{"mid", true, 0, L / 2, 0.0}, {"q", true, 0, 3.1, 0.0}}, rs, false, true);
  const load::Train t = load::hslm_a("HSLM-A1", load::hslm_a_row(1));
  const double v = 20.0;  // m/s: the run's samples every 2 cm, finer than the lines' h/8 = 3 cm
  const study::RunResult r = study::simulate(pm, t, v, rs);
  const study::QuasiStaticResult qs = study::quasi_static(pm, t, v, 1.0, r);
  const auto ex = study::static_extremes(study::influence_lines(pm), t, 1.0);
  const auto names = study::quantity_names(pm);
  REQUIRE(names == qs.names);
  for (std::size_t q = 0; q < names.size(); ++q) {
    const double ref = qs.value[q].cwiseAbs().maxCoeff();
    INFO(names[q]);
    // Two samplings of the same exact static response (linear interpolation of the cubic lines
    // between h/8 samples; the run's 2 cm grid): within 2e-3 of the peak.
    CHECK(std::max(ex[q].max, -ex[q].min) == Approx(ref).epsilon(2e-3));
  }
}

TEST_CASE("static extremes: all quantities in one crawl give each quantity's own crawl exactly") {
  // static_extremes takes each head position's axles and samples once for all quantities; the
  // reference crawls quantity by quantity through InfluenceLines::at, as it did before, every axle
  // (off the lines too: their terms are zeros) and the same refinement around each extreme. The
  // same operations in the same order: equal to the last bit. Two spans (a line that changes sign),
  // stations and load effects, a train longer than the bridge, a load factor that is not 1.
  model::BridgeParams b = vt::span(10.0, 4e9, 11000.0, 0.5);
  b.spans.push_back(b.spans.front());
  b.continuous = true;
  const model::Structure s = model::build_structure(b, std::nullopt);
  study::RunSettings rs;
  rs.filter.enabled = false;
  const study::PreparedModel pm =
      study::prepare_model(s, {{"m1", true, 0, 5.0, 0.0}, {"q2", true, 1, 2.7, 0.0}}, rs, false, true);
  const study::InfluenceLines il = study::influence_lines(pm);
  REQUIRE(il.value.size() > 4);
  // HSLM's axles are 0.5 m apart or more, on the lines' samples (h = 1/16 m here); a train of
  // irregular spacings puts its axles between samples (interpolated values) as real trains do.
  load::Train irregular;
  irregular.name = "irregular";
  irregular.offset = {0.0, 2.3137, 4.9711, 13.1003, 15.4297, 18.0231, 26.517, 28.7719, 41.03};
  irregular.load = {171e3, 165e3, 158e3, 162e3, 170e3, 149e3, 155e3, 160e3, 172e3};
  for (const load::Train& t : {load::hslm_a("HSLM-A4", load::hslm_a_row(4)), irregular}) {
    const double factor = 0.5;
    const auto ex = study::static_extremes(il, t, factor);
    const double x_end = il.x0 + il.h * static_cast<double>(il.value.front().size() - 1);
    const auto n_pos = static_cast<Index>(std::ceil((x_end - il.x0 + t.length()) / il.h)) + 1;
    for (std::size_t q = 0; q < il.value.size(); ++q) {
      auto at_head = [&](double head) {
        double y = 0.0;
        for (std::size_t k = 0; k < t.n_axles(); ++k) y += t.load[k] * il.at(q, head - t.offset[k]);
        return y * factor;
      };
      study::EffectPeak ref;
      double x_max = il.x0, x_min = il.x0;
      for (Index i = 0; i < n_pos; ++i) {
        const double head = il.x0 + static_cast<double>(i) * il.h, y = at_head(head);
        if (y > ref.max) ref.max = y, x_max = head;
        if (y < ref.min) ref.min = y, x_min = head;
      }
      for (const double around : {x_max, x_min})
        for (std::size_t k = 0; k < t.n_axles(); ++k)
          for (const double side : {-1.0, 0.0, 1.0}) {
            const double u = std::round((around - t.offset[k] - il.x0) / il.h) + side;
            const double head = il.x0 + u * il.h + t.offset[k];
            if (std::abs(head - around) > il.h) continue;
            const double y = at_head(head);
            ref.max = std::max(ref.max, y);
            ref.min = std::min(ref.min, y);
          }
      INFO(t.name << " " << il.names[q]);
      CHECK(ex[q].max == ref.max);
      CHECK(ex[q].min == ref.min);
      CHECK(ref.max > ref.min);
    }
  }
}

TEST_CASE("EN 1991-2 numbers: Table 6.6, Eq. 6.13, Phi2, Phi3, phi'' and the cut-off, worked by hand") {
  using study::DeckType;
  // Table 6.6: prestressed 1.0 + 0.07 (20 − 11.93) = 1.5649 %; steel 0.5 + 0.125 × 5 = 1.125 %;
  // reinforced 1.5 + 0.07 × 15 = 2.55 %; from 20 m on the constants.
  CHECK(study::damping_lower_bound(DeckType::prestressed, 11.93) == Approx(0.015649).epsilon(1e-12));
  CHECK(study::damping_lower_bound(DeckType::steel, 15.0) == Approx(0.01125).epsilon(1e-12));
  CHECK(study::damping_lower_bound(DeckType::composite, 15.0) == Approx(0.01125).epsilon(1e-12));
  CHECK(study::damping_lower_bound(DeckType::reinforced, 5.0) == Approx(0.0255).epsilon(1e-12));
  CHECK(study::damping_lower_bound(DeckType::filler_beam, 25.0) == Approx(0.015).epsilon(1e-12));
  CHECK(study::damping_lower_bound(DeckType::prestressed, 40.0) == Approx(0.010).epsilon(1e-12));
  // Eq. 6.13 at L = 10 m: (0.187 − 0.064) / (1 − 0.441 − 0.44 + 0.255) = 0.123 / 0.374 % = 0.32888 %.
  CHECK(study::additional_damping(10.0) == Approx(0.00328877).epsilon(1e-5));
  CHECK(study::additional_damping(30.0) == 0.0);
  // Φ2 at 16 m: 1.44 / 3.8 + 0.82 = 1.198947; Φ3: 2.16 / 3.8 + 0.73 = 1.298421; bounds at 1 m and 400 m.
  CHECK(study::phi2(16.0) == Approx(1.198947).epsilon(1e-6));
  CHECK(study::phi3(16.0) == Approx(1.298421).epsilon(1e-6));
  CHECK(study::phi2(1.0) == 1.67);
  CHECK(study::phi3(1.0) == 2.0);
  CHECK(study::phi2(400.0) == 1.0);
  // φ″ at Lφ = 10 m, n0 = 10 Hz, v > 22 m/s: (56 e^−1 + 50 (1.25 − 1) e^−0.25) / 100 = 0.303354.
  CHECK(study::phi_irregularities(10.0, 50.0, 10.0) == Approx(0.01 * (56 * std::exp(-1.0) + 12.5 * std::exp(-0.25))).epsilon(1e-12));
  CHECK(study::phi_irregularities(10.0, 11.0, 10.0) == Approx(0.5 * study::phi_irregularities(10.0, 50.0, 10.0)).epsilon(1e-12));
  CHECK(study::phi_irregularities(100.0, 50.0, 0.5) == 0.0);  // negative terms floor at 0
  CHECK(study::cutoff_frequency(5.0, 45.0) == 45.0);
  CHECK(study::cutoff_frequency(25.0, 35.0) == 37.5);
  CHECK(study::cutoff_frequency(5.0, 20.0) == 30.0);
  CHECK_THROWS_AS(study::deck_type_of("timber"), InputError);
  CHECK(study::deck_type_of("filler-beam") == DeckType::filler_beam);
  // Lφ of continuous decks (Table 6.2, continuous over n spans): 1.2 × 20 = 24 m; 1.3 × mean(10, 30, 10) =
  // 21.67 m but not below the longest, 30 m; 1.5 × 12 = 18 m for six spans; one span: itself.
  CHECK(study::continuous_determinant_length({20.0, 20.0}) == Approx(24.0).epsilon(1e-12));
  CHECK(study::continuous_determinant_length({10.0, 30.0, 10.0}) == 30.0);
  CHECK(study::continuous_determinant_length({12.0, 14.0, 12.0}) == Approx(1.3 * 38.0 / 3).epsilon(1e-12));
  CHECK(study::continuous_determinant_length({10.0, 10.0, 10.0, 10.0}) == Approx(14.0).epsilon(1e-12));
  CHECK(study::continuous_determinant_length(std::vector<double>(6, 12.0)) == Approx(18.0).epsilon(1e-12));
  CHECK(study::continuous_determinant_length({17.0}) == 17.0);
  CHECK_THROWS_AS(study::continuous_determinant_length({}), InputError);
  CHECK_THROWS_AS(study::continuous_determinant_length({10.0, -1.0}), InputError);
}

TEST_CASE("assessment speeds: the grid, refined through each resonance speed") {
  const auto v = study::assessment_speeds(40.0, 100.0, 5.0, 0.25, {70.1, 300.0}, 0.02);
  CHECK(v.front() == 40.0);
  CHECK(v.back() == Approx(100.0));
  CHECK(std::is_sorted(v.begin(), v.end()));
  CHECK(std::find(v.begin(), v.end(), 70.1) != v.end());  // the resonance itself is a speed
  std::size_t fine = 0;
  for (double x : v) fine += std::abs(x - 70.1) <= 0.02 * 70.1 + 1e-9;
  // 70.1 ± 1.402 every 0.25: 5 below, itself, 5 above; and 70 of the coarse grid, 0.1 away.
  CHECK(fine == 12);
  for (std::size_t i = 1; i < v.size(); ++i) CHECK(v[i] - v[i - 1] > 0.0025 - 1e-12);
  CHECK(study::assessment_speeds(40.0, 40.0, 5.0, 1.0, {}, 0.0) == std::vector<double>{40.0});
  CHECK_THROWS_AS(study::assessment_speeds(0.0, 10.0, 1.0, 1.0, {}, 0.0), InputError);
  CHECK_THROWS_AS(study::assessment_speeds(10.0, 5.0, 1.0, 1.0, {}, 0.0), InputError);
}

TEST_CASE("a sweep with load effects keeps each case's extremes and quasi-static extremes, as run gives them") {
  const double L = 15.0, EI = 7.694e9, m = 15000.0;
  study::Scenario sc;
  sc.bridge = vt::span(L, EI, m, 0.5);
  sc.bridge.damping.ratio = 0.0135;
  sc.trains = {load::hslm_a("HSLM-A1", load::hslm_a_row(1)), load::hslm_a("HSLM-A4", load::hslm_a_row(4))};
  sc.stations = {{"mid", true, 0, L / 2, 0.0}};
  sc.settings.filter.enabled = false;
  sc.settings.method = study::Method::modal;
  sc.sweep_speeds = {70.0, 80.0, 90.0};
  study::Variant v{"reference", sc};
  v.train_speeds = {{70.0, 80.0}, {90.0}};  // per train
  study::SweepOptions so;
  so.load_effects = true;
  const study::SweepResult r = study::run_sweep({v}, so);
  REQUIRE(r.failures.empty());
  REQUIRE(r.rows.size() == 3);
  const study::PreparedModel pm = study::prepare_model(sc, false, true);
  const auto names = study::quantity_names(pm);
  REQUIRE(r.quantities.size() == 3 * names.size());
  for (const auto& q : r.quantities) {
    const load::Train& t = q.train == "HSLM-A1" ? sc.trains[0] : sc.trains[1];
    CHECK(((q.train == "HSLM-A1" && q.speed != 90.0) || (q.train == "HSLM-A4" && q.speed == 90.0)));
    const study::RunResult run = study::simulate(pm, t, q.speed, sc.settings);
    const study::QuasiStaticResult qs = study::quasi_static(pm, t, q.speed, 1.0, run);
    const std::size_t k = index_of(names, q.quantity);
    const Vector& y = k < 1 ? run.stations[0].disp : run.effects[k - 1].value;
    INFO(q.quantity << " " << q.speed);
    CHECK(q.dynamic.max == Approx(y.maxCoeff()).epsilon(1e-12));
    CHECK(q.dynamic.min == Approx(y.minCoeff()).epsilon(1e-12).margin(1e-12 * y.cwiseAbs().maxCoeff()));
    // The crawl's static maximum against run's quasi-static response at its samples, v·dt = 7 to
    // 9 cm apart: not below it but for the lines' linear interpolation between samples h = 6 cm
    // apart (about (h/L)² of a curved line's peak, measured 5e-5: 1e-4), and above by at most
    // what 9 cm of travel changes on lines whose slope is at most 2/L of their peak (the end
    // reactions' 1 − x/L; the moment's 2x/L).
    // A shear line jumps by P at its station, which the elements next to it smear over 2h: linear
    // interpolation there is further off (measured 8.5e-4): 2e-3.
    const double sampled = qs.value[k].cwiseAbs().maxCoeff();
    const bool shear = q.quantity.find("_shear_N") != std::string::npos;
    CHECK(q.quasi_static.max_abs() >= sampled * (1 - (shear ? 2e-3 : 1e-4)));
    CHECK(q.quasi_static.max_abs() <= sampled * (1 + 2 * q.speed * sc.settings.dt / L));
    CHECK(q.phi_dyn() == Approx(q.dynamic.max_abs() / q.quasi_static.max_abs() - 1.0));
  }
  // A speed list per train must match the trains.
  v.train_speeds = {{70.0}};
  CHECK_THROWS_AS(study::run_sweep({v}, so), InputError);
}

namespace {

// A load-effect sweep of `sc` (modal method) through the peaks kernel against the same sweep
// with a custom runner, which opts out of the kernel and takes each case's extremes from
// simulate()'s histories: the same model, step and load sampling, so rounding only (summation
// order), 1e-9 of the quantity's largest value. Returns the number of quantities compared.
std::size_t kernel_against_histories(const study::Scenario& sc) {
  const study::Variant v{"reference", sc};
  study::SweepOptions fast, slow;
  fast.load_effects = slow.load_effects = true;
  slow.runner = [](const study::PreparedModel& m, const load::Train& t, double speed, const study::RunSettings& rs) {
    return study::simulate(m, t, speed, rs);
  };
  const study::SweepResult a = study::run_sweep({v}, fast), b = study::run_sweep({v}, slow);
  REQUIRE(a.failures.empty());
  REQUIRE(b.failures.empty());
  REQUIRE(a.quantities.size() == b.quantities.size());
  for (std::size_t i = 0; i < a.quantities.size(); ++i) {
    const auto &x = a.quantities[i], &y = b.quantities[i];
    INFO(x.quantity << " at " << x.speed);
    REQUIRE(x.quantity == y.quantity);
    const double scale = y.dynamic.max_abs();
    CHECK(x.dynamic.max == Approx(y.dynamic.max).margin(1e-9 * scale));
    CHECK(x.dynamic.min == Approx(y.dynamic.min).margin(1e-9 * scale));
  }
  for (std::size_t i = 0; i < a.rows.size(); ++i) CHECK(a.rows[i].max_abs_acc == Approx(b.rows[i].max_abs_acc).epsilon(1e-8));
  return a.quantities.size();
}

// Two 12 m spans, HSLM-A2 at speeds not commensurate with the elements (an axle leaving the path
// exactly on a sample is a load jump that the two paths round to either side), modal method to
// 60 Hz, filtered accelerations, a strain station.
study::Scenario two_spans() {
  study::Scenario sc;
  sc.bridge = vt::span(12.0, 6e9, 9000.0, 0.5);
  sc.bridge.spans.push_back(sc.bridge.spans.front());
  sc.bridge.damping.ratio = 0.02;
  sc.trains = {load::hslm_a("HSLM-A2", load::hslm_a_row(2))};
  sc.stations = {{"S1", true, 0, 6.0, 0.0, 0.4}, {"S2", true, 1, 6.0, 0.0}};
  sc.settings.method = study::Method::modal;
  sc.settings.modal.max_frequency_hz = 60.0;
  sc.settings.filter.enabled = true;
  sc.settings.filter.cheby.band = signal::BandType::lowpass;
  sc.settings.filter.cheby.high_hz = 30.0;
  sc.sweep_speeds = {61.3, 67.7, 73.1, 80.9, 88.3};
  return sc;
}

}  // namespace

TEST_CASE("the modal peaks kernel keeps the signed extremes of load effects as the histories give them") {
  // Per speed: 2 deflections, 2 moments, 1 strain, 2 shears, 4 rotations, 4 bearings.
  constexpr std::size_t per_speed = 15;
  SECTION("elastic bearings without dashpots: every effect a functional of the deflections") {
    study::Scenario sc = two_spans();
    sc.bridge.bearings.rigid = false;
    sc.bridge.bearings.k = 2e9;
    CHECK(kernel_against_histories(sc) == 5 * per_speed);
  }
  SECTION("rigid bearings: each force a sum of its stiffness, inertia and damping parts and the axles on its elements") {
    study::Scenario sc = two_spans();
    CHECK(kernel_against_histories(sc) == 5 * per_speed);
  }
  SECTION("rigid bearings without the static correction and with Rayleigh damping") {
    study::Scenario sc = two_spans();
    sc.settings.modal.static_correction = false;
    sc.bridge.damping.kind = model::DampingKind::rayleigh;
    sc.bridge.damping.f1_hz = 5.0;
    sc.bridge.damping.ratio1 = 0.02;
    sc.bridge.damping.f2_hz = 40.0;
    sc.bridge.damping.ratio2 = 0.03;
    CHECK(kernel_against_histories(sc) == 5 * per_speed);
  }
  SECTION("elastic bearings with dashpots: damping that couples the modes (complex modes)") {
    study::Scenario sc = two_spans();
    sc.bridge.bearings.rigid = false;
    sc.bridge.bearings.k = 2e9;
    sc.bridge.bearings.c = 2e6;
    REQUIRE(study::prepare_model(sc, false, true).modal->complex_modes());
    CHECK(kernel_against_histories(sc) == 5 * per_speed);
  }
  SECTION("a station every metre of the first span: the outputs taken a block of steps at a time") {
    // 12 more stations (deflection, moment, shear each): 36 outputs beside the sums' bearings, which
    // the classical kernel takes in blocks of steps against bounds (BlockOutputs), on four lanes
    // or eight; a block it leaves out must hold no value beyond the extremes the histories give.
    for (const bool correction : {true, false}) {
      study::Scenario sc = two_spans();
      sc.settings.modal.static_correction = correction;
      for (int x = 0; x < 12; ++x)
        sc.stations.push_back({"A" + std::to_string(x), true, 0, 0.5 + x, 0.0});
      CHECK(kernel_against_histories(sc) == 5 * (per_speed + 36));
    }
  }
  SECTION("a continuous deck on rigid supports") {
    study::Scenario sc = two_spans();
    sc.bridge.continuous = true;
    // Per speed: 2 deflections, 2 moments, 1 strain, 2 shears, 3 support rotations, 3 supports.
    CHECK(kernel_against_histories(sc) == 5 * 13);
  }
}

// EN 1990 A2.4.4.2.1(4): f3 is the third mode of the member. A 25 m span on elastic bearings with
// the Old Guadiana track alone and the same span between two identical spans: the same member f3
// and the same cut-off, whereas the chain's third deck mode is another span's first bending
// (the unconservative reading this replaced, issue #38 item 1).
TEST_CASE("the cut-off takes f3 of the member: one span alone and among identical spans agree", "[long]") {
  const std::vector<std::string> common = {"bridge.EI=4.0e10", "bridge.mass_per_m=16000", "bridge.mass_includes_track=false",
                                           "assess.speed_min_kmh=300", "assess.speed_step_kmh=40"};
  // The shipped scenario's stations name span 2: a scenario of its own with one mid-span station.
  const std::string path = (std::filesystem::temp_directory_path() / "viaduct-member-f3.toml").string();
  {
    std::ofstream f(path);
    f << "[bridge]\nfile = \"" << vt::source("data/bridges/old-guadiana.toml") << "\"\n"
      << "[track]\nfile = \"" << vt::source("data/tracks/old-guadiana-ballasted.toml") << "\"\n"
      << "[train]\nfiles = [\"" << vt::source("data/trains/talgo-altaria.csv") << "\"]\nload_factor = 0.5\n[analysis]\npreset = \"default\"\n"
      << "[[stations]]\nname = \"S1_mid\"\nspan = 1\nat = 0.5\n"
      << "[assess]\nline_speed_kmh = 300.0\ndeck_type = \"prestressed\"\ntrack = \"ballasted\"\n";
  }
  auto plan_for = [&](const std::string& spans) {
    std::vector<std::string> set = common;
    set.push_back("bridge.span_lengths=" + spans);
    io::FlatScenario flat = io::load_flat(path, set);
    return io::plan_assessment(flat, "viaduct-member-f3.toml");
  };
  const study::AssessPlan one = plan_for("[25.0]");
  const study::AssessPlan chain = plan_for("[25.0, 25.0, 25.0]");
  REQUIRE(one.members.size() == 1);
  REQUIRE(chain.members.size() == 3);
  for (const auto& m : chain.members) {
    CHECK(m.f3_order == 3);
    // each member is modelled alone, with the same mesh and track: the same eigenproblem
    CHECK(m.f3 == Approx(one.members.front().f3).epsilon(1e-9));
    CHECK(m.f1 == Approx(one.members.front().f1).epsilon(1e-9));
  }
  CHECK(chain.f3 == Approx(one.f3).epsilon(1e-9));
  CHECK(chain.f_cut == Approx(one.f_cut).epsilon(1e-9));
  // The member's f3 is near 9 f1 of the span (on bearings and under a track: within 25 %),
  // the chain's third deck bending mode is the first of a neighbour (within 10 % of f1).
  const double f1 = one.members.front().f1;
  CHECK(one.f3 > 6.75 * f1);
  CHECK(one.f3 < 11.25 * f1);
  REQUIRE(chain.deck_modes.size() >= 3);
  CHECK(chain.deck_modes[2].frequency_hz < 1.1 * f1);
  CHECK(chain.f_cut > chain.deck_modes[2].frequency_hz);
}

// EN 1991-2 6.4.6.3.2's mass bounds from the ballast bed (issue #38 item 5): with the bed's width,
// the lower bound's ballast is the minimum density's, the upper bound's the saturated density's
// with the depth +30 %, each replacing the ballast bridge.mass_per_m includes; without, the track
// model's vibrating ballast is used and the note says how little it moves the mass.
TEST_CASE("mass bounds from the ballast bed's density and depth replace the included ballast", "[long]") {
  const std::string path = vt::source("scenarios/old-guadiana-assess.toml");
  const std::vector<std::string> bed = {"assess.ballast_width_m=2.0", "assess.ballast_depth_m=0.45"};
  io::FlatScenario flat = io::load_flat(path, bed);
  const study::AssessPlan p = io::plan_assessment(flat, path);
  REQUIRE(p.variants.size() == 2);
  const double m0 = 8727.0, nominal = 1800.0 * 0.45 * 2.0;  // the defaults: 1800, 1700, 2100 kg/m³, +30 %
  CHECK(p.ballast_nominal == Approx(nominal));
  CHECK(p.ballast_lower == Approx(1700.0 * 0.45 * 2.0));
  CHECK(p.ballast_upper == Approx(2100.0 * 1.3 * 0.45 * 2.0));
  CHECK(p.variants[0].scenario.bridge.spans[0].mass_per_m == Approx(m0 - nominal + 1700.0 * 0.45 * 2.0));
  CHECK(p.variants[1].scenario.bridge.spans[1].mass_per_m == Approx(m0 - nominal + 2100.0 * 1.3 * 0.45 * 2.0));
  // The upper bound adds 7 % or more to this half deck, where the track model's ballast gave 1.8 %.
  CHECK(p.variants[1].scenario.bridge.spans[0].mass_per_m / m0 > 1.07);
  // The included ballast given as a key is the one replaced.
  std::vector<std::string> given = bed;
  given.push_back("assess.ballast_mass_per_m=1500");
  io::FlatScenario flat2 = io::load_flat(path, given);
  const study::AssessPlan q = io::plan_assessment(flat2, path, 3);  // the trains' distances on three threads
  CHECK(q.variants[0].scenario.bridge.spans[0].mass_per_m == Approx(m0 - 1500.0 + 1700.0 * 0.45 * 2.0));
  // ... each train's own, the numbers of one thread (the same trains: the mass does not enter).
  REQUIRE(q.train_distance.size() == p.train_distance.size());
  REQUIRE(q.train_distance.size() > 3);
  CHECK(q.train_distance == p.train_distance);
  // Without the bed: the track's vibrating ballast, and a note that says it is far below a bed's.
  io::FlatScenario flat3 = io::load_flat(path);
  const study::AssessPlan r = io::plan_assessment(flat3, path);
  const bool said = std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) { return n.find("far below a real bed") != std::string::npos; });
  CHECK(said);
  CHECK(r.variants[1].scenario.bridge.spans[0].mass_per_m / m0 < 1.02);
  // A minimum density above the saturated one is refused at its key.
  std::vector<std::string> bad = bed;
  bad.push_back("assess.ballast_density_min_kgpm3=2500");
  io::FlatScenario flat4 = io::load_flat(path, bad);
  CHECK_THROWS_WITH(io::plan_assessment(flat4, path), Catch::Contains("assess.ballast_density_min_kgpm3") && Catch::Contains("saturated"));
}
