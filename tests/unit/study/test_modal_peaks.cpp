#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include "../../verification/helpers.hpp"
#include "viaduct/core/buffer.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/study/sweep.hpp"

using namespace viaduct;
using namespace viaduct::study;

// The fused peaks kernel must give what peaks(simulate(...)) gives on the same modal model: it
// evaluates the same piecewise cubics (folded over the train instead of summed per axle) and the
// same exact modal step. Differences are rounding plus the forward-difference drift within a
// piece (a few dozen additions): 1e-9 relative is far above both and far below any modelling
// error, so a wrong piece, lane, sign or missing term fails it.
namespace {
constexpr double kRel = 1e-9;

Scenario hslm_span(int n_modes, bool static_correction) {
  Scenario sc = vt::shipped("hslm-simply-supported",
                            {"analysis.method=\"modal\"", "modal.n_modes=" + std::to_string(n_modes),
                             "modal.static_correction=" + std::string(static_correction ? "true" : "false"),
                             "filter.enabled=false", "analysis.dt=0.0005", "analysis.free_vibration_s=0.5"});
  sc.stations.push_back({"quarter", true, 0, 3.75, 0.0});
  return sc;
}

void require_same_as_simulate(const Scenario& sc, const std::vector<double>& speeds) {
  const PreparedModel pm = prepare_model(sc, /*rail_outputs=*/false);
  REQUIRE(folds_trains(pm, sc.settings));
  for (const auto& train : sc.trains) {
    const auto folded = fold_train(pm, train, sc.settings.load_factor);
    const std::vector<CasePeaks> fast = simulate_peaks(pm, train, speeds, sc.settings, folded.get());
    REQUIRE(fast.size() == speeds.size());
    for (std::size_t s = 0; s < speeds.size(); ++s) {
      const RunResult full = simulate(pm, train, speeds[s], sc.settings);
      const std::vector<StationPeaks> ref = peaks(full);
      REQUIRE(fast[s].n_steps == full.summary.n_steps);
      REQUIRE(fast[s].peaks.size() == ref.size());
      for (std::size_t j = 0; j < ref.size(); ++j) {
        INFO(train.name << " at " << speeds[s] << " m/s, station " << j);
        REQUIRE(ref[j].max_abs_acc > 0.0);
        REQUIRE(fast[s].peaks[j].max_abs_acc == Approx(ref[j].max_abs_acc).epsilon(kRel));
        REQUIRE(fast[s].peaks[j].max_abs_disp == Approx(ref[j].max_abs_disp).epsilon(kRel));
      }
    }
  }
}
}  // namespace

TEST_CASE("modal peaks kernel: the same peaks as the full run on a single span, with and without static correction") {
  // 7 speeds: one full group of four lanes and a partial one (spare lanes must not leak);
  // speeds far apart so the lanes' cases end at very different steps.
  const std::vector<double> speeds = {140 / 3.6, 420 / 3.6, 200 / 3.6, 301 / 3.6, 250 / 3.6, 333 / 3.6, 180 / 3.6};
  for (bool sc_on : {true, false}) {
    INFO("static correction " << sc_on);
    Scenario sc = hslm_span(3, sc_on);
    sc.trains.resize(2);  // A1 and A2: 3.5 m bogies as well as 2 m
    require_same_as_simulate(sc, speeds);
  }
}

TEST_CASE("modal peaks kernel: a larger basis and three stations run the general-size loop") {
  Scenario sc = hslm_span(9, true);  // 9 modes: beyond the unrolled sizes
  sc.stations.push_back({"three-quarter", true, 0, 11.25, 0.0});
  sc.trains.resize(1);
  require_same_as_simulate(sc, {160 / 3.6, 390 / 3.6});
}

TEST_CASE("modal peaks kernel: a track model with classical damping (rail load path, many modes)") {
  // Without dashpots the track model's modes stay classical; every mode below 150 Hz.
  Scenario sc = vt::shipped("old-guadiana-sensitivity",
                            {"analysis.method=\"modal\"", "modal.max_frequency_hz=150", "filter.enabled=false",
                             "track.pad.c=0", "track.ballast.c=0", "track.shear.c=0", "track.subgrade.c=0",
                             "bridge.damping.kind=\"none\"", "analysis.free_vibration_s=0.3",
                             "sweep.mode=\"reference\""});
  const PreparedModel pm = prepare_model(sc, false);
  REQUIRE_FALSE(pm.modal->complex_modes());
  REQUIRE(pm.modal->n_modes() > 20);
  // The rail's ends are free, so an axle's load steps onto the model at the path's start. At
  // speeds where a sample falls exactly on such a step (60 or 80 m/s with dt = 1 ms: the head
  // moves a whole fraction of the 18 m axle spacing per step) rounding decides on which side it
  // is counted, differently in the two codes; these speeds keep clear of that.
  require_same_as_simulate(sc, {45.0, 83.7, 99.0});
}

TEST_CASE("modal peaks kernel: a filter, taken on the recorded accelerations") {
  // Classical modes with the scenario's low-pass: the kernel records the station accelerations
  // and filters them as simulate() does.
  Scenario sc = hslm_span(3, true);
  sc.settings.filter.enabled = true;
  sc.trains.resize(1);
  require_same_as_simulate(sc, {150 / 3.6, 300 / 3.6, 410 / 3.6});
}

TEST_CASE("modal peaks kernel: complex modes of a damped track model, with the filter", "[long]") {
  // The track's dashpots couple the modes: complex coordinates, damping vectors, static
  // correction, the band-pass filter; 5 speeds (a full lane group and a partial one).
  Scenario sc = vt::shipped("old-guadiana-sensitivity",
                            {"analysis.method=\"modal\"", "modal.max_frequency_hz=90", "analysis.free_vibration_s=0.3",
                             "sweep.mode=\"reference\""});
  const PreparedModel pm = prepare_model(sc, false);
  REQUIRE(pm.modal->complex_modes());
  REQUIRE(pm.modal->n_modes() > 34);  // the modes and their damping vectors
  // Speeds at which no sample falls on an axle's entry (see the classical track test above:
  // 45 m/s puts one on every 400th step, 99 m/s on step 2000, and the filter then sees which
  // side rounding chose: 18 m / (v dt) must not be a ratio of small integers).
  require_same_as_simulate(sc, {46.3, 83.7, 98.7, 52.3, 71.9});
  // and without the filter or the static correction
  Scenario raw = sc;
  raw.settings.filter.enabled = false;
  raw.settings.modal.static_correction = false;
  require_same_as_simulate(raw, {47.1, 91.3});
}

TEST_CASE("modal peaks kernel: refused inputs") {
  Scenario sc = hslm_span(3, true);
  PreparedModel pm = prepare_model(sc, false);
  REQUIRE(folds_trains(pm, sc.settings));
  RunSettings unit = sc.settings;
  unit.superposition = Superposition::unit_response;
  REQUIRE_FALSE(folds_trains(pm, unit));
  RunSettings newmark = sc.settings;
  newmark.method = Method::newmark;
  REQUIRE_FALSE(folds_trains(pm, newmark));
  const load::Train& tr = sc.trains[0];
  const auto folded = fold_train(pm, tr, 1.0);
  REQUIRE_THROWS_AS(simulate_peaks(pm, tr, {0.0}, sc.settings, folded.get()), InputError);
  REQUIRE_THROWS_AS(simulate_peaks(pm, tr, {50.0}, unit, folded.get()), InputError);
  REQUIRE_THROWS_AS(fold_train(pm, tr, -1.0), InputError);
  // A train folded over another model is refused.
  Scenario other = hslm_span(4, true);
  const PreparedModel pm4 = prepare_model(other, false);
  REQUIRE_THROWS_AS(simulate_peaks(pm4, tr, {50.0}, other.settings, folded.get()), InputError);
  // A speed so low that the case would take more than 2e9 steps is refused before any work
  // (fuzzing found it converted to an integer first: issue #18).
  REQUIRE_THROWS_WITH(simulate_peaks(pm, tr, {1e-16}, sc.settings, folded.get()), Catch::Contains("2e9 steps"));
}

TEST_CASE("a sweep on the peaks kernel gives the rows of the general path") {
  Scenario sc = hslm_span(3, true);
  sc.trains.resize(3);
  sc.sweep_speeds.clear();
  for (int k = 0; k < 11; ++k) sc.sweep_speeds.push_back((150.0 + 25.0 * k) / 3.6);  // two blocks of speeds
  const std::vector<Variant> v = {{"reference", sc}};
  SweepOptions fast, general;
  fast.threads = 2;
  general.threads = 2;
  general.runner = [](const PreparedModel& m, const load::Train& t, double speed, const RunSettings& rs) {
    return simulate(m, t, speed, rs);  // a custom runner opts out of the kernel
  };
  const SweepResult a = run_sweep(v, fast), b = run_sweep(v, general);
  REQUIRE(a.failures.empty());
  REQUIRE(a.rows.size() == 3 * 11 * 2);
  REQUIRE(a.rows.size() == b.rows.size());
  REQUIRE(a.summary.n_steps_total == b.summary.n_steps_total);
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    REQUIRE(a.rows[i].train == b.rows[i].train);
    REQUIRE(a.rows[i].station == b.rows[i].station);
    REQUIRE(a.rows[i].speed == b.rows[i].speed);
    REQUIRE(a.rows[i].max_abs_acc == Approx(b.rows[i].max_abs_acc).epsilon(kRel));
    REQUIRE(a.rows[i].max_abs_disp == Approx(b.rows[i].max_abs_disp).epsilon(kRel));
  }
}

TEST_CASE("a train folded in chunks, in any order and by two threads, is the table fold_train gives") {
  // A sweep's threads fill chunks of one TrainFold in whatever order they take them; each piece's
  // sums run over the axles and elements in the same order whichever chunk holds it, so the
  // tables are equal number for number.
  // 150 Hz: enough channels for a table of more than 4 MB (a large block, kept by BlockReuse).
  Scenario sc = vt::shipped("old-guadiana-sensitivity", {"analysis.method=\"modal\"", "modal.max_frequency_hz=150"});
  const PreparedModel pm = prepare_model(sc, false);
  const load::Train& train = sc.trains.at(0);
  const auto whole = fold_train(pm, train, 0.5);
  REQUIRE(whole->breaks.size() > 200);  // pieces for several chunks
  auto same = [&](const solve::MovingChannels& t) {
    REQUIRE(t.breaks == whole->breaks);
    REQUIRE(t.point == whole->point);
    REQUIRE(t.n_channels == whole->n_channels);
    REQUIRE(t.coef.size() == whole->coef.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < t.coef.size(); ++i) differ += t.coef[i] != whole->coef[i];
    REQUIRE(differ == 0);
  };
  {
    TrainFold f(pm, train, 0.5);
    REQUIRE(f.n_chunks() > 2);
    for (std::size_t c = f.n_chunks(); c-- > 0;) f.fill(c);  // last chunk first
    same(*f.table());
  }
  {
    TrainFold f(pm, train, 0.5);
    std::atomic<std::size_t> next{0};
    auto work = [&] {
      for (std::size_t c = next++; c < f.n_chunks(); c = next++) f.fill(c);
    };
    std::thread other(work);
    work();
    other.join();
    same(*f.table());
  }
  // In the memory a freed table left behind (BlockReuse, as in a sweep) the same numbers, and the
  // block beyond the last break zero.
  REQUIRE(whole->coef.size() * sizeof(double) >= kLargeBlock);  // a block that is kept
  {
    const BlockReuse reuse;
    const double* dirty_at = nullptr;
    {
      const auto dirty = fold_train(pm, train, 1.0);
      dirty_at = dirty->coef.data();
    }
    const auto again = fold_train(pm, train, 0.5);
    REQUIRE(again->coef.data() == dirty_at);  // the block was given again
    same(*again);
    const std::size_t nc = again->n_channels, last = (again->breaks.size() - 1) * 4 * nc;
    for (std::size_t i = last; i < again->coef.size(); ++i) REQUIRE(again->coef[i] == 0.0);
  }
}

TEST_CASE("modal peaks kernel: complex modes with 1 to 7 stations (every block size of the output sums)", "[long]") {
  // The complex kernel sums its outputs over the coordinates in blocks of four, the last block of
  // 1, 2, 3, 5 or 6: each count of outputs against the full run.
  Scenario sc = vt::shipped("old-guadiana-sensitivity",
                            {"analysis.method=\"modal\"", "modal.max_frequency_hz=60", "analysis.free_vibration_s=0.2",
                             "filter.enabled=false", "sweep.mode=\"reference\""});
  const std::vector<double> at = {0.5, 0.25, 0.75, 0.1, 0.9, 0.4, 0.6};
  for (std::size_t n : {1, 2, 3, 5, 6, 7}) {
    sc.stations.clear();
    for (std::size_t i = 0; i < n; ++i)
      sc.stations.push_back({"s" + std::to_string(i), true, i % 2, at[i] * 11.93, 0.0});
    INFO(n << " stations");
    REQUIRE(prepare_model(sc, false).modal->complex_modes());
    require_same_as_simulate(sc, {83.7});
  }
}

// solve::bound_residuals bounds each residual channel's cubic over its piece: every value at
// 2001 places of every piece within the bounds (the kernel leaves a block of steps out on them:
// a bound below a value loses an extreme), and not loose where the cubic is monotone in each
// term (all coefficients of one sign: the bound is the value at an end, within the 1e-10 margin).
TEST_CASE("the residuals' bounds of a folded train are each piece's cubic's range, within their margin") {
  solve::MovingChannels L;
  L.n_modes = 2, L.n_outputs = 3, L.n_channels = 5;
  L.breaks = {0.0, 0.3, 0.35, 1.2, 1.21, 1.9};
  const std::size_t np = L.breaks.size() - 1, nc = L.n_channels;
  L.coef.assign((np + 1) * 4 * nc, 0.0);
  unsigned seed = 7;
  auto rnd = [&seed] {  // deterministic values in [-1, 1)
    seed = seed * 1103515245u + 12345u;
    return static_cast<double>((seed >> 8) % 20000) / 10000.0 - 1.0;
  };
  for (std::size_t p = 0; p < np; ++p)
    for (std::size_t n = 0; n < 4; ++n)
      for (std::size_t ch = 0; ch < nc; ++ch) L.coef[p * 4 * nc + n * nc + ch] = 1e6 * rnd() * std::pow(10.0, n);
  // residual channel 2 of piece 2: every term positive, its largest value at the piece's end
  for (std::size_t n = 0; n < 4; ++n) L.coef[2 * 4 * nc + n * nc + L.n_modes + 2] = 1e6 * (1.0 + n);
  // residual 1 of the last piece: a cubic whose two turning points lie close together (a
  // discriminant near zero), s = 0.4 ± 1e-4
  {
    double* a = L.coef.data() + 4 * 4 * nc + L.n_modes + 1;
    const double r1 = 0.4 - 1e-4, r2 = 0.4 + 1e-4;  // slope 3(s − r1)(s − r2)
    a[0] = 5.0, a[nc] = 3.0 * r1 * r2, a[2 * nc] = -1.5 * (r1 + r2), a[3 * nc] = 1.0;
  }
  L.residual_bounds.resize(2 * np * L.n_outputs);
  solve::bound_residuals(L, 0, np);
  int interior = 0;
  for (std::size_t p = 0; p < np; ++p) {
    const double len = L.breaks[p + 1] - L.breaks[p];
    for (std::size_t j = 0; j < L.n_outputs; ++j) {
      const double* a = L.coef.data() + p * 4 * nc + L.n_modes + j;
      auto f = [&](double s) { return a[0] + s * (a[nc] + s * (a[2 * nc] + s * a[3 * nc])); };
      const double hi = L.residual_bounds[(2 * p) * L.n_outputs + j], lo = L.residual_bounds[(2 * p + 1) * L.n_outputs + j];
      // The range by sampling, each extreme then refined by ternary search about its sample.
      const int n = 2000;
      int kmax = 0, kmin = 0;
      for (int k = 0; k <= n; ++k) {
        if (f(len * k / n) > f(len * kmax / n)) kmax = k;
        if (f(len * k / n) < f(len * kmin / n)) kmin = k;
      }
      auto refine = [&](int k, double sign) {
        double x0 = len * std::max(k - 1, 0) / n, x1 = len * std::min(k + 1, n) / n;
        for (int it = 0; it < 200; ++it) {
          const double m1 = x0 + (x1 - x0) / 3.0, m2 = x1 - (x1 - x0) / 3.0;
          if (sign * f(m1) < sign * f(m2)) x0 = m1;
          else x1 = m2;
        }
        return std::max(sign * f(len * k / n), sign * f(0.5 * (x0 + x1))) * sign;
      };
      const double vmax = refine(kmax, 1.0), vmin = refine(kmin, -1.0);
      interior += (kmax > 0 && kmax < n) + (kmin > 0 && kmin < n);
      double ab = 0.0;  // the terms' magnitudes: the margin is 1e-10 of them
      for (std::size_t e = 0; e < 4; ++e) ab += std::abs(a[e * nc]) * std::pow(len, static_cast<double>(e));
      INFO("piece " << p << ", residual " << j);
      CHECK(hi >= vmax);
      CHECK(lo <= vmin);
      // tight: the margin and the rounding of a few operations (1e-14 of the terms) beyond it
      CHECK(hi - vmax <= 1e-10 * ab + 1e-14 * ab);
      CHECK(vmin - lo <= 1e-10 * ab + 1e-14 * ab);
    }
  }
  CHECK(interior >= 4);  // turning points within pieces are exercised (5 here)
  // An infinite coefficient: bounds that still hold (the terms' bound where the range is NaN).
  L.coef[1 * 4 * nc + 3 * nc + L.n_modes + 0] = std::numeric_limits<double>::infinity();
  solve::bound_residuals(L, 1, 2);
  CHECK(L.residual_bounds[(2 * 1) * L.n_outputs + 0] == std::numeric_limits<double>::infinity());
  CHECK(!std::isnan(L.residual_bounds[(2 * 1 + 1) * L.n_outputs + 0]));
}
