#include <catch2/catch.hpp>
#include <thread>
#include <atomic>
#include <cmath>

#include "viaduct/core/cancel.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/study/sweep.hpp"

using namespace viaduct;
using namespace viaduct::study;

namespace {
Scenario small_sweep_scenario() {
  Scenario sc;
  sc.bridge.spans = {{12.0, 5e9, 10000.0}};
  sc.bridge.element_size = 1.0;
  sc.bridge.damping.ratio = 0.02;
  sc.trains = {load::regular_train("t3", 3, 10.0, 100e3), load::regular_train("t1", 1, 0.0, 200e3)};
  sc.stations = {{"mid", true, 0, 6.0, 0.0}, {"q", true, 0, 3.0, 0.0}};
  sc.settings.dt = 2e-3;
  sc.settings.free_vibration_s = 0.2;
  sc.settings.filter.cheby.high_hz = 30.0;
  sc.sweep_speeds = {20.0, 30.0, 40.0, 50.0};
  return sc;
}
}  // namespace

TEST_CASE("a failing case is recorded and every other case completes") {
  std::vector<Variant> v = {{"reference", small_sweep_scenario()}};
  SweepOptions o;
  o.threads = 2;
  o.runner = [](const PreparedModel& m, const load::Train& t, double speed, const RunSettings& rs) {
    if (speed == 30.0 && t.name == "t3") throw SolverError("injected failure");
    return simulate(m, t, speed, rs);
  };
  const SweepResult r = run_sweep(v, o);
  REQUIRE(r.summary.n_cases == 8);
  REQUIRE(r.failures.size() == 1);
  REQUIRE(r.failures[0].speed == 30.0);
  REQUIRE(r.failures[0].message == "injected failure");
  REQUIRE(r.rows.size() == 7 * 2);  // 7 completed cases x 2 stations
  for (const auto& row : r.rows) REQUIRE(std::isfinite(row.max_abs_acc));
}

TEST_CASE("a variant whose model cannot be built fails its own cases only") {
  Scenario bad = small_sweep_scenario();
  bad.bridge.spans[0].EI = -1.0;
  std::vector<Variant> v = {{"reference", small_sweep_scenario()}, {"EI x-1", bad}};
  const SweepResult r = run_sweep(v, SweepOptions{});
  REQUIRE(r.failures.size() == 8);
  REQUIRE(r.failures[0].message.find("EI must be > 0") != std::string::npos);
  REQUIRE(r.rows.size() == 16);
}

TEST_CASE("a variant that could not be formed fails its own cases with its reason") {
  Variant broken{"EI x0", small_sweep_scenario(), "variant 'EI x0': factor 0 on key 'bridge.EI': must be > 0"};
  std::vector<Variant> v = {{"reference", small_sweep_scenario()}, broken};
  const SweepResult r = run_sweep(v, SweepOptions{});
  REQUIRE(r.failures.size() == 8);
  for (const auto& f : r.failures) {
    CHECK(f.variant == "EI x0");
    CHECK(f.message == broken.error);
    CHECK(f.input_error);  // the input's fault: the CLI exits 2 when every case fails so
  }
  REQUIRE(r.rows.size() == 16);
  for (const auto& row : r.rows) CHECK(row.variant == "reference");
  // A computation that fails is not the input's.
  SweepOptions throwing;
  throwing.runner = [](const PreparedModel&, const load::Train&, double, const RunSettings&) -> RunResult {
    throw SolverError("non-finite state");
  };
  const SweepResult t = run_sweep({{"reference", small_sweep_scenario()}}, throwing);
  REQUIRE_FALSE(t.failures.empty());
  for (const auto& f : t.failures) CHECK_FALSE(f.input_error);
}

TEST_CASE("with load effects, a train whose quasi-static extremes fail fails its variant's cases, as a model would") {
  // The quasi-static extremes run as tasks after the jobs; a failing one (here a train Train::validate
  // refuses) still fails every case of its variant with the model's prefix, and only those.
  Scenario bad = small_sweep_scenario();
  bad.trains[1].load[0] = std::nan("");
  std::vector<Variant> v = {{"reference", small_sweep_scenario()}, {"bad train", bad}};
  for (int threads : {1, 2}) {
    SweepOptions o;
    o.threads = threads;
    o.load_effects = true;
    const SweepResult r = run_sweep(v, o);
    REQUIRE(r.failures.size() == 8);
    for (const auto& f : r.failures) {
      CHECK(f.variant == "bad train");
      CHECK(f.message.rfind("model: ", 0) == 0);
      CHECK(f.input_error);
    }
    REQUIRE(r.rows.size() == 16);
    REQUIRE_FALSE(r.quantities.empty());
    for (const auto& q : r.quantities) {
      CHECK(q.variant == "reference");
      CHECK(q.quasi_static.max_abs() > 0.0);  // every quantity's quasi-static extremes are in
    }
  }
}

TEST_CASE("sweep results are identical for any thread count") {
  Scenario b = small_sweep_scenario();
  b.bridge.spans[0].EI *= 2;
  const std::vector<Variant> v = {{"reference", small_sweep_scenario()}, {"EI x2", b}};
  SweepOptions one, two;
  one.threads = 1;
  two.threads = 2;
  std::size_t calls = 0;
  two.progress = [&](std::size_t done, std::size_t total) {
    ++calls;
    REQUIRE(done <= total);
  };
  const SweepResult r1 = run_sweep(v, one), r2 = run_sweep(v, two);
  REQUIRE(calls == 16);
  REQUIRE(r1.rows.size() == r2.rows.size());
  for (std::size_t i = 0; i < r1.rows.size(); ++i) {
    REQUIRE(r1.rows[i].variant == r2.rows[i].variant);
    REQUIRE(r1.rows[i].speed == r2.rows[i].speed);
    REQUIRE(r1.rows[i].max_abs_acc == r2.rows[i].max_abs_acc);  // bitwise: same arithmetic
    REQUIRE(r1.rows[i].max_abs_disp == r2.rows[i].max_abs_disp);
  }
  // A stiffer bridge deflects less.
  REQUIRE(r1.rows.back().max_abs_disp < r1.rows[r1.rows.size() / 2 - 1].max_abs_disp);
}

TEST_CASE("governing cases: the largest value per station and quantity, and where it occurs") {
  std::vector<EnvelopeRow> rows = {{"reference", "A1", "mid", 50.0, 1.0, 0.004}, {"reference", "A1", "end", 50.0, 0.5, 0.001},
                                   {"reference", "A2", "mid", 60.0, 3.0, 0.002}, {"Kp x2", "A1", "mid", 55.0, 2.0, 0.005},
                                   {"Kp x2", "A2", "end", 70.0, 0.7, 0.0009}};
  const auto g = governing(rows);
  REQUIRE(g.size() == 2);
  CHECK(g[0].station == "mid");
  CHECK(g[0].acc.value == 3.0);
  CHECK(g[0].acc.train == "A2");
  CHECK(g[0].acc.speed == 60.0);
  CHECK(g[0].disp.value == 0.005);
  CHECK(g[0].disp.variant == "Kp x2");
  CHECK(g[0].disp.speed == 55.0);
  CHECK(g[1].station == "end");
  CHECK(g[1].acc.value == 0.7);
  CHECK(g[1].acc.variant == "Kp x2");
  CHECK(g[1].disp.value == 0.001);
  CHECK(g[1].disp.train == "A1");
  CHECK(governing({}).empty());
}

TEST_CASE("shards of a sweep: the case ranges together give the full sweep bit for bit") {
  // Every job layout: batched Newmark (reference), the modal peaks kernel with speed blocks,
  // unit-response superposition (a speed with every train), and a variant that fails to form.
  Scenario modal = small_sweep_scenario(), unit = small_sweep_scenario();
  modal.settings.method = Method::modal;
  unit.settings.superposition = Superposition::unit_response;
  modal.sweep_speeds = unit.sweep_speeds = {20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0};
  const std::vector<Variant> v = {{"reference", small_sweep_scenario()},
                                  {"modal", modal},
                                  {"unit", unit},
                                  {"EI x0", small_sweep_scenario(), "factor 0 on key 'bridge.EI': must be > 0"}};
  const std::size_t n = count_cases(v);
  REQUIRE(n == 8 + 20 + 20 + 8);
  SweepOptions full_options;
  full_options.threads = 2;
  const SweepResult full = run_sweep(v, full_options);
  REQUIRE(full.summary.n_cases == n);
  REQUIRE(full.failures.size() == 8);
  for (std::size_t parts : {2, 3, 7}) {
    std::vector<EnvelopeRow> rows;
    std::vector<CaseFailure> failures;
    std::size_t cases = 0;
    for (std::size_t k = 0; k < parts; ++k) {
      SweepOptions o = full_options;
      o.case_begin = k * n / parts;
      o.case_end = (k + 1) * n / parts;
      std::size_t progress_calls = 0;
      o.progress = [&](std::size_t done, std::size_t total) {
        ++progress_calls;
        REQUIRE(done <= total);
      };
      const SweepResult r = run_sweep(v, o);
      REQUIRE(r.summary.n_cases == o.case_end - o.case_begin);
      REQUIRE(progress_calls == r.summary.n_cases);
      REQUIRE(r.rows.size() / 2 + r.failures.size() == r.summary.n_cases);  // two stations per case
      cases += r.summary.n_cases;
      rows.insert(rows.end(), r.rows.begin(), r.rows.end());
      failures.insert(failures.end(), r.failures.begin(), r.failures.end());
    }
    INFO(parts << " shards");
    REQUIRE(cases == n);
    REQUIRE(rows.size() == full.rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      REQUIRE(rows[i].variant == full.rows[i].variant);
      REQUIRE(rows[i].train == full.rows[i].train);
      REQUIRE(rows[i].station == full.rows[i].station);
      REQUIRE(rows[i].speed == full.rows[i].speed);
      REQUIRE(rows[i].max_abs_acc == full.rows[i].max_abs_acc);  // bitwise: the same jobs
      REQUIRE(rows[i].max_abs_disp == full.rows[i].max_abs_disp);
    }
    REQUIRE(failures.size() == full.failures.size());
    for (std::size_t i = 0; i < failures.size(); ++i) REQUIRE(failures[i].speed == full.failures[i].speed);
  }
}

TEST_CASE("a shard builds only the variants it runs") {
  Scenario bad = small_sweep_scenario();
  bad.bridge.spans[0].EI = -1.0;  // its model cannot be built
  const std::vector<Variant> v = {{"reference", small_sweep_scenario()}, {"EI x-1", bad}};
  SweepOptions first_half;
  first_half.case_end = count_cases(v) / 2;
  const SweepResult r = run_sweep(v, first_half);
  REQUIRE(r.failures.empty());  // the broken variant is the other half's
  REQUIRE(r.rows.size() == 8 * 2);
  REQUIRE(r.summary.n_dofs[1] == 0);
  SweepOptions second_half;
  second_half.case_begin = count_cases(v) / 2;
  REQUIRE(run_sweep(v, second_half).failures.size() == 8);
}

TEST_CASE("a cancelled sweep skips the cases not started and says so") {
  const std::vector<Variant> v = {{"reference", small_sweep_scenario()}};
  std::atomic<bool> cancel{true};
  SweepOptions o;
  o.cancel = &cancel;
  const SweepResult r = run_sweep(v, o);
  REQUIRE(r.rows.empty());
  REQUIRE(r.failures.size() == 8);
  for (const auto& f : r.failures) CHECK((f.message == "cancelled" && !f.input_error));
  cancel = false;
  REQUIRE(run_sweep(v, o).failures.empty());
}

TEST_CASE("a cancellation request stops the time stepping of every method") {
  for (const Method m : {Method::newmark, Method::modal, Method::ida}) {
    Scenario sc = small_sweep_scenario();
    sc.settings.method = m;
    const PreparedModel pm = prepare_model(sc);
    std::atomic<bool> flag{true};
    {
      const CancelScope scope(&flag);
      CHECK_THROWS_AS(simulate(pm, sc.trains[0], 30.0, sc.settings), Cancelled);
      flag = false;
      CHECK(simulate(pm, sc.trains[0], 30.0, sc.settings).t.size() > 0);  // cleared: runs again
      flag = true;
    }
    CHECK(simulate(pm, sc.trains[0], 30.0, sc.settings).t.size() > 0);  // out of the scope: not this thread's
  }
}

TEST_CASE("a cancellation is one call's: another thread's sweep runs to its end (issue #36)") {
  const std::vector<Variant> v = {{"reference", small_sweep_scenario()}};
  // Thread A's flag is set before it runs: its cases stop. Thread B, running at the same time
  // without it, completes every case (before #36 the request was process-wide: B lost cases).
  std::atomic<bool> a_flag{true};
  SweepResult a, b;
  std::thread ta([&] {
    const CancelScope scope(&a_flag);
    SweepOptions o;
    o.threads = 2;  // the flag reaches the pool's workers
    o.cancel = &a_flag;
    a = run_sweep(v, o);
  });
  std::thread tb([&] {
    SweepOptions o;
    o.threads = 2;
    b = run_sweep(v, o);
  });
  ta.join();
  tb.join();
  CHECK(a.failures.size() == 8);
  CHECK(a.summary.cancelled);
  CHECK(b.failures.empty());
  CHECK(b.summary.n_cases == 8);
  CHECK_FALSE(b.summary.cancelled);
}
