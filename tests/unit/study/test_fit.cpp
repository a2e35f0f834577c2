#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "viaduct/core/error.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/fit.hpp"
#include "viaduct/study/simulation.hpp"
#include "fit_synthetic.hpp"

using namespace viaduct;
using namespace viaduct::study;
using viaduct::test::small_scenario;
using viaduct::test::synthetic_record;

using viaduct::test::param;
using viaduct::test::ei_damping_problem;

TEST_CASE("normalised coordinates map the bounds onto [0, 1] and back") {
  const FitParameter lg = param("k", 1e6, 1e9, 1e7);
  REQUIRE(to_unit(lg, 1e6) == Approx(0.0).margin(1e-15));
  REQUIRE(to_unit(lg, 1e9) == Approx(1.0));
  REQUIRE(to_unit(lg, std::sqrt(1e6 * 1e9)) == Approx(0.5));  // geometric middle
  REQUIRE(from_unit(lg, to_unit(lg, 3.3e7)) == Approx(3.3e7).epsilon(1e-14));
  const FitParameter ln = param("c", -1.0, 3.0, 0.0, ParameterScale::linear);
  REQUIRE(to_unit(ln, 1.0) == Approx(0.5));
  REQUIRE(from_unit(ln, 0.25) == Approx(0.0).margin(1e-15));
}

TEST_CASE("fit recovers stiffness and damping from a noisy synthetic record", "[long]") {
  const std::vector<double> truth = {5.5e9, 0.025};
  FitProblem p = ei_damping_problem(5.0e9, 0.015, {synthetic_record(truth, 0.03)});
  FitOptions o;
  o.threads = 2;
  const FitResult r = fit(p, o);
  INFO(r.message);
  REQUIRE(r.status == FitResult::Status::converged);
  REQUIRE(r.warnings.empty());
  REQUIRE(r.cost_final < 0.05 * r.cost_initial);
  // Noise of 3 % of the peak on both channels: the errors measured are 0.02 % (EI) and 0.4 %
  // (damping), 0.9 and 1.0 standard errors; the standard errors from the Jacobian must cover
  // them (4 sigma), and the relative limits (0.3 %, 5 %) are an order above what was measured.
  for (std::size_t i = 0; i < 2; ++i) {
    INFO(p.params[i].key << " estimate " << r.estimate[i] << " +- " << r.std_error[i]);
    REQUIRE(std::abs(r.estimate[i] - truth[i]) < 4 * r.std_error[i]);
    REQUIRE(r.determined[i]);
  }
  REQUIRE(r.estimate[0] == Approx(truth[0]).epsilon(3e-3));
  REQUIRE(r.estimate[1] == Approx(truth[1]).epsilon(0.05));
  // The record started 0.7 s before the train: shift = t0 + 0.7 s within half a sample.
  REQUIRE(r.shift_s.size() == 1);
  REQUIRE(r.shift_s[0] == Approx(5.7).margin(0.5 / 500));
  // Reports: a trace from the start, terms and overlays for both channels.
  REQUIRE(r.trace.front().iteration == 0);
  REQUIRE(r.trace.front().stage == 1);  // the spectral pre-stage comes first
  REQUIRE(r.trace.back().stage == 0);
  REQUIRE(r.trace.front().values[0] == Approx(5.0e9));
  REQUIRE(r.terms.size() == 2);
  for (const auto& t : r.terms) REQUIRE(t.after < t.before);
  REQUIRE(r.overlays.size() == 2);
  REQUIRE(r.overlays[0].measured.size() == p.records[0].channels[0].samples.size());
  REQUIRE(std::abs(r.correlation(0, 1)) <= 1.0);
  REQUIRE(r.correlation(0, 0) == Approx(1.0));
}

TEST_CASE("each record objective alone recovers the stiffness from a clean record", "[long]") {
  // From 18 % below the truth (frequencies 9 % low) for the phase-aware objectives; peak and
  // envelope only see amplitudes, which rise and fall with resonance as EI changes: from 4.5e9
  // they stop at a local minimum near 3.86e9 (measured), so they start from 5 % below.
  const std::vector<double> truth = {5.5e9, 0.02};
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 4.5e9)};
  p.records = {synthetic_record(truth, 0.0)};
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], 0.02}); };
  for (const char* objective : {"time", "peak", "envelope", "spectrum"}) {
    FitOptions o;
    o.weights = FitWeights{0, 0, 0, 0, 0};
    const std::string obj = objective;
    if (obj == "time") o.weights.time = 1;
    if (obj == "peak") o.weights.peak = 1;
    if (obj == "envelope") o.weights.envelope = 1;
    p.params[0].initial = obj == "peak" || obj == "envelope" ? 5.2e9 : 4.5e9;
    if (obj == "spectrum") o.weights.spectrum = 1;
    o.threads = 2;
    const FitResult r = fit(p, o);
    INFO(obj << ": " << r.message << " estimate " << r.estimate[0]);
    REQUIRE(r.status == FitResult::Status::converged);
    // The record is the model itself (one sample per step, processed alike), so only the
    // solver's tolerances remain: 1e-5 relative (time and spectrum reach 1e-9).
    REQUIRE(r.estimate[0] == Approx(truth[0]).epsilon(1e-5));
  }
}

TEST_CASE("a strain channel fits the stiffness through the model's strain at the gauge's fibre") {
  // The "measured" strain: the model's mid-span strain 0.4 m below the neutral axis at EI = 5.5e9,
  // 1 % noise, sampled on the model's grid from t0 = 2 s. From EI = 4.5e9 (the strain scales as
  // 1/EI and the timing with it) the fit must come back within 0.5 %.
  const double ei_true = 5.5e9;
  auto with_gauge = [](const std::vector<double>& v) {
    Scenario sc = small_scenario(v);
    sc.stations[0].fibre_m = 0.4;
    return sc;
  };
  const Scenario sc = with_gauge({ei_true, 0.02});
  RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  const RunResult run = simulate(prepare_model(sc, false, true), sc.trains[0], 30.0, rs);
  const auto e = std::find_if(run.effects.begin(), run.effects.end(), [](const EffectHistory& x) { return x.name == "mid_strain_ue"; });
  REQUIRE(e != run.effects.end());
  FitRecord rec;
  rec.name = "strain";
  rec.speed = 30.0;
  rec.fs_hz = 500.0;
  rec.t0_s = 2.0;
  FitChannel ch;
  ch.name = "mid_strain_ue";
  ch.station = "mid";
  ch.acceleration = false;
  ch.strain = true;
  std::mt19937 rng(5);
  std::normal_distribution<double> nd(0.0, 0.01 * e->value.cwiseAbs().maxCoeff());
  ch.samples = e->value;
  for (Index j = 0; j < ch.samples.size(); ++j) ch.samples[j] += nd(rng);
  rec.channels = {ch};
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 4.5e9)};
  p.records = {rec};
  p.scenario_at = [&](const std::vector<double>& v) { return with_gauge({v[0], 0.02}); };
  FitOptions o;
  o.threads = 2;
  const FitResult r = fit(p, o);
  INFO(r.message << "; EI " << r.estimate[0] << " +- " << r.std_error[0]);
  REQUIRE(r.estimate[0] == Approx(ei_true).epsilon(5e-3));
  // Without a fibre at the station the strain channel is refused with the reason.
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], 0.02}); };
  REQUIRE_THROWS_WITH(fit(p, o), Catch::Contains("has no stations[].fibre_m"));
}

TEST_CASE("a parameter the data do not depend on is flagged, not reported as fitted", "[long]") {
  // Bearing damping on rigid bearings changes nothing.
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 5e9), param("bridge.damping.ratio", 0.005, 0.08, 0.02),
              param("bridge.bearings.c", 1e3, 1e6, 1e4)};
  p.records = {synthetic_record({5.5e9, 0.02}, 0.02)};
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], v[1], 10000.0, v[2]}); };
  FitOptions o;
  o.threads = 2;
  const FitResult r = fit(p, o);
  REQUIRE(r.sensitivity[2] == 0.0);
  REQUIRE_FALSE(r.determined[2]);
  REQUIRE(std::isinf(r.std_error[2]));
  REQUIRE(r.estimate[2] == Approx(1e4));  // never moved
  bool named = false;
  for (const auto& w : r.warnings) named = named || w.find("bridge.bearings.c is insensitive") != std::string::npos;
  REQUIRE(named);
  REQUIRE(r.determined[0]);
  REQUIRE(r.estimate[0] == Approx(5.5e9).epsilon(3e-3));
}

TEST_CASE("stiffness and mass fitted to frequencies alone are flagged as correlated") {
  // f ∝ sqrt(EI / m): the first two frequencies fix the ratio only.
  const Scenario truth = small_scenario({5.5e9, 0.02, 11000.0});
  const model::Structure s = model::build_structure(truth.bridge, std::nullopt);
  const model::Modes md = model::compute_modes(s, 2);
  ModalTarget t;
  for (Index k = 0; k < 2; ++k) t.modes.push_back({md.frequency_hz[k], Vector()});
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 5e9), param("bridge.mass_per_m", 8000, 14000, 10000)};
  p.modal = t;
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], 0.02, v[1]}); };
  FitOptions o;
  o.weights = FitWeights{0, 0, 0, 0, 1};
  const FitResult r = fit(p, o);
  INFO(r.message);
  REQUIRE(r.status == FitResult::Status::converged);
  bool named = false;
  for (const auto& w : r.warnings) named = named || w.find("combination") != std::string::npos;
  REQUIRE(named);
  REQUIRE_FALSE(r.determined[0]);
  REQUIRE_FALSE(r.determined[1]);
  // The ratio is still recovered: EI/m within 1e-6 (frequencies fitted exactly).
  REQUIRE(r.estimate[0] / r.estimate[1] == Approx(5.5e9 / 11000.0).epsilon(1e-6));
}

TEST_CASE("the modal objective recovers the stiffness from identified frequencies and shapes") {
  const Scenario truth = small_scenario({6.2e9, 0.02});
  const model::Structure s = model::build_structure(truth.bridge, std::nullopt);
  const model::Modes md = model::compute_modes(s, 3);
  const auto st = resolve_stations(s, truth.stations);
  ModalTarget t;
  t.sensors = {"mid", "quarter"};
  // Modes 1 and 3 (mode 2 has a node at mid-span); the shapes scaled arbitrarily, sign flipped.
  for (Index k : {0, 2}) {
    Vector shape(2);
    for (std::size_t i = 0; i < 2; ++i) shape[static_cast<Index>(i)] = -3.0 * st[i].deck.value(md.shape.col(k));
    t.modes.push_back({md.frequency_hz[k], shape});
  }
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 4e9)};
  p.modal = t;
  p.scenario_at = small_scenario;
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], 0.02}); };
  FitOptions o;
  o.weights = FitWeights{0, 0, 0, 0, 1};
  const FitResult r = fit(p, o);
  REQUIRE(r.status == FitResult::Status::converged);
  REQUIRE(r.estimate[0] == Approx(6.2e9).epsilon(1e-6));  // exact data: solver tolerance only
  REQUIRE(r.modal_pairs.size() == 2);
  for (const auto& mp : r.modal_pairs) {
    REQUIRE(mp.model_after_hz == Approx(mp.frequency_hz).epsilon(1e-6));
    REQUIRE(mp.mac_after == Approx(1.0).epsilon(1e-9));
    REQUIRE(mp.model_before_hz < mp.frequency_hz);  // softer start
  }
  // A shape of the wrong length is refused.
  p.modal->modes[0].shape = Vector::Ones(3);
  REQUIRE_THROWS_WITH(fit(p, o), Catch::Contains("3 entries for 2 sensors"));
}

TEST_CASE("bounds hold: a value beyond them stops on the bound and is flagged") {
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 5e9, 4.7e9)};  // 15 % below the truth, 6 % below the bound
  p.records = {synthetic_record({5.5e9, 0.02}, 0.01)};
  std::vector<double> seen_max(1, 0.0);
  p.scenario_at = [&seen_max](const std::vector<double>& v) {
    seen_max[0] = std::max(seen_max[0], v[0]);  // evaluations are serial here (threads = 1)
    return small_scenario({v[0], 0.02});
  };
  FitOptions o;
  const FitResult r = fit(p, o);
  REQUIRE(r.estimate[0] == Approx(5e9).epsilon(1e-6));
  REQUIRE(r.at_bound[0]);
  REQUIRE_FALSE(r.determined[0]);
  REQUIRE(seen_max[0] <= 5e9 * (1 + 1e-12));  // never simulated beyond the bound
  bool named = false;
  for (const auto& w : r.warnings) named = named || w.find("bridge.EI ended on its upper bound") != std::string::npos;
  REQUIRE(named);
}

TEST_CASE("a fit that cannot finish says why instead of hanging", "[long]") {
  FitProblem p = ei_damping_problem(3.5e9, 0.06);
  FitOptions o;
  o.max_iterations = 1;
  FitResult r = fit(p, o);
  REQUIRE(r.status == FitResult::Status::no_convergence);
  REQUIRE_THAT(r.message, Catch::Contains("did not converge") && Catch::Contains("iterations"));
  REQUIRE(r.estimate.size() == 2);  // the best point so far is still reported
  // A model that fails away from the start: the solver backs off, the start is kept or improved.
  p.scenario_at = [](const std::vector<double>& v) {
    if (v[0] > 4.0e9) throw SolverError("model refuses EI > 4e9");
    return small_scenario(v);
  };
  o.max_iterations = 6;
  r = fit(p, o);
  REQUIRE(r.estimate[0] <= 4.0e9);
  REQUIRE(r.cost_final <= r.cost_initial);
  // The initial values themselves fail: an error, not a result.
  p.scenario_at = [](const std::vector<double>&) -> Scenario { throw SolverError("broken model"); };
  REQUIRE_THROWS_WITH(fit(p, o), Catch::Contains("broken model"));
}

TEST_CASE("several starts: every start reported, the best kept", "[long]") {
  FitProblem p = ei_damping_problem(3.2e9, 0.07);
  FitOptions o;
  o.starts = 3;
  o.threads = 2;
  const FitResult r = fit(p, o);
  REQUIRE(r.start_costs.size() == 3);
  const double best = *std::min_element(r.start_costs.begin(), r.start_costs.end());
  REQUIRE(r.start_costs[static_cast<std::size_t>(r.best_start)] == best);
  REQUIRE(r.cost_final == Approx(best).epsilon(1e-9));
  int starts_seen = 0;
  for (const auto& tp : r.trace) starts_seen = std::max(starts_seen, tp.start + 1);
  REQUIRE(starts_seen == 3);
  REQUIRE(r.estimate[0] == Approx(5.5e9).epsilon(3e-3));
}

TEST_CASE("inconsistent fit problems are refused with the reason") {
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 5e9)};
  p.records = {synthetic_record({5.5e9, 0.02}, 0.01)};
  p.scenario_at = small_scenario;
  p.scenario_at = [](const std::vector<double>& v) { return small_scenario({v[0], 0.02}); };
  FitOptions o;
  auto expect = [&](FitProblem q, FitOptions oo, const std::string& what) {
    REQUIRE_THROWS_WITH(fit(q, oo), Catch::Contains(what));
  };
  FitProblem q = p;
  q.params[0].lower = 9e9;
  expect(q, o, "lower < upper");
  q = p;
  q.params[0].initial = 2e9;
  expect(q, o, "outside the bounds");
  q = p;
  q.params[0].lower = -1;
  expect(q, o, "logarithmic scale needs lower > 0");
  q = p;
  q.records.clear();
  expect(q, o, "need at least one record");
  q = p;
  q.records[0].channels[0].station = "nowhere";
  expect(q, o, "no station 'nowhere'");
  q = p;
  q.records[0].channels[0].samples[10] = NAN;
  expect(q, o, "non-finite");
  q = p;
  q.records[0].train = "ICE";
  expect(q, o, "no train named 'ICE'");
  FitOptions oo = o;
  oo.weights = FitWeights{0, 0, 0, 0, 0};
  expect(p, oo, "at least one objective weight");
  oo = o;
  oo.weights.modal = 1;
  expect(p, oo, "need identified modes");
  oo = o;
  oo.fd_step = 0.5;
  expect(p, oo, "fd_step");
  oo = o;
  oo.starts = 0;
  expect(p, oo, "FitOptions::starts = 0: violated constraint starts >= 1");
}

TEST_CASE("a train speed 5 % off is recovered through the spectral pre-stage", "[long]") {
  // The time misfit is full of local minima in speed (every axle shifts); the amplitude spectra
  // are not, so each start fits them first.
  FitProblem p;
  p.params = {param("run.speed_kmh", 90, 130, 103)};  // truth 108 km/h (30 m/s)
  p.records = {synthetic_record({5.5e9, 0.02}, 0.01)};
  p.records[0].speed = 0;  // the scenario's run speed, which is fitted
  p.scenario_at = [](const std::vector<double>& v) {
    Scenario sc = small_scenario({5.5e9, 0.02});
    sc.run_speed = v[0] / 3.6;
    return sc;
  };
  FitOptions o;
  o.threads = 2;
  const FitResult r = fit(p, o);
  INFO(r.message);
  REQUIRE(r.status == FitResult::Status::converged);
  // 1 % noise: measured error 0.0002 %, standard error 0.0035 %; the limits are 1e-4 relative
  // (an order above) and 4 standard errors.
  REQUIRE(r.estimate[0] == Approx(108.0).epsilon(1e-4));
  REQUIRE(std::abs(r.estimate[0] - 108.0) < 4 * r.std_error[0]);
}

TEST_CASE("the damping objective recovers a damping ratio from identified modal damping") {
  // Modal damping: every span mode has the scenario's ratio, so phi'C phi / (2 omega) is it.
  const Scenario truth = small_scenario({6.2e9, 0.031});
  const model::Structure s = model::build_structure(truth.bridge, std::nullopt);
  const model::Modes md = model::compute_modes(s, 1);
  ModalTarget t;
  ModalTarget::Mode m;
  m.frequency_hz = md.frequency_hz[0];
  m.damping_ratio = 0.031;
  t.modes.push_back(m);
  FitProblem p;
  p.params = {param("bridge.EI", 3e9, 8e9, 5e9), param("bridge.damping.ratio", 0.005, 0.08, 0.02)};
  p.modal = t;
  p.scenario_at = small_scenario;
  FitOptions o;
  o.weights = FitWeights{0, 0, 0, 0, 1, 1};
  const FitResult r = fit(p, o);
  INFO(r.message);
  REQUIRE(r.status == FitResult::Status::converged);
  REQUIRE(r.estimate[0] == Approx(6.2e9).epsilon(1e-6));  // exact data: solver tolerance only
  REQUIRE(r.estimate[1] == Approx(0.031).epsilon(1e-6));
  REQUIRE(r.modal_pairs[0].model_damping_after == Approx(0.031).epsilon(1e-6));
  REQUIRE(r.modal_pairs[0].model_damping_before == Approx(0.02).epsilon(1e-9));
  // Without identified damping the objective has nothing to fit.
  p.modal->modes[0].damping_ratio = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(fit(p, o), Catch::Contains("needs identified damping ratios"));
}

TEST_CASE("several passages are fitted jointly", "[long]") {
  // Two passages at 30 and 24 m/s, both channels each: four time-history blocks in one fit.
  const std::vector<double> truth = {5.5e9, 0.025};
  FitProblem p = ei_damping_problem(5.0e9, 0.015, {synthetic_record(truth, 0.03, 3, 30.0), synthetic_record(truth, 0.03, 4, 24.0)});
  p.records[1].name = "slow";
  FitOptions o;
  o.threads = 2;
  const FitResult r = fit(p, o);
  INFO(r.message);
  REQUIRE(r.status == FitResult::Status::converged);
  REQUIRE(r.terms.size() == 4);
  REQUIRE(r.terms[2].record == "slow");
  REQUIRE(r.shift_s.size() == 2);
  REQUIRE(r.shift_s[1] == Approx(5.7).margin(0.5 / 500));
  for (std::size_t i = 0; i < 2; ++i) REQUIRE(std::abs(r.estimate[i] - truth[i]) < 4 * r.std_error[i]);
  // Twice the data: the standard errors are below those of one passage with the same noise.
  FitProblem one = p;
  one.records.pop_back();
  const FitResult r1 = fit(one, o);
  REQUIRE(r.std_error[0] < r1.std_error[0]);
  REQUIRE(r.std_error[1] < r1.std_error[1]);
}
