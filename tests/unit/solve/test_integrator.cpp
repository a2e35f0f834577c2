#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/integrator.hpp"
#include "coupled_fixtures.hpp"

using namespace viaduct;
using namespace coupled_fixtures;

namespace {

// Two masses in a chain under a force that starts at t = 0 and stops at 0.05 s.
class TwoMasses : public solve::SecondOrderSystem {
 public:
  TwoMasses() {
    M_.resize(2, 2), C_.resize(2, 2), K_.resize(2, 2);
    M_.insert(0, 0) = 1.0, M_.insert(1, 1) = 2.0;
    C_.insert(0, 0) = 0.5;
    K_.insert(0, 0) = 3e3, K_.insert(0, 1) = -1e3, K_.insert(1, 0) = -1e3, K_.insert(1, 1) = 1e3;
  }
  const SparseMatrix& mass() const override { return M_; }
  const SparseMatrix& damping() const override { return C_; }
  const SparseMatrix& stiffness() const override { return K_; }
  void force(double t, Vector& f) const override {
    f.setZero();
    f[1] = t < 0.05 ? 10.0 : 0.0;
  }

 private:
  SparseMatrix M_, C_, K_;
};

}  // namespace

TEST_CASE("the integration face keeps velocities and every stride-th sample, and tells progress") {
  const TwoMasses sys;
  std::vector<solve::Functional> outs{{{0}, {1.0}}, {{0, 1}, {0.5, 0.5}}};
  solve::LoadCase c;
  c.system = &sys;
  c.t_end = 0.3;
  solve::Recording all;
  all.vel_history = true;
  for (const solve::Method m : {solve::Method::newmark, solve::Method::ida}) {
    solve::IntegrationSettings s;
    s.method = m;
    s.dt = 1e-3;
    const auto integ = solve::make_integrator(s, outs);
    c.progress = nullptr;
    const solve::CaseResult every = integ->run(c, all);
    REQUIRE(every.vel.rows() == 301);
    solve::Recording strided = all;
    strided.stride = 4;
    std::size_t calls = 0, last = 0, total = 0;
    const ProgressSink progress = [&](std::size_t done, std::size_t n) { ++calls, last = done, total = n; };
    c.progress = &progress;
    const solve::CaseResult kept = integ->run(c, strided);
    INFO(solve::method_name(m));
    REQUIRE(kept.disp.rows() == 76);  // steps 0, 4, …, 300
    for (Index i = 0; i < kept.disp.rows(); ++i) {  // the same run, every fourth sample: bit for bit
      CHECK(kept.disp.row(i) == every.disp.row(4 * i));
      CHECK(kept.vel.row(i) == every.vel.row(4 * i));
      CHECK(kept.acc.row(i) == every.acc.row(4 * i));
    }
    CHECK(kept.max_abs_disp == every.max_abs_disp);  // the extremes see every step
    CHECK(total == 300);
    CHECK(last == 300);
    CHECK(calls >= 100);
    CHECK(calls <= 310);
    // The velocity is the derivative of the displacement: central differences agree to O(dt²).
    double err = 0.0, scale = 0.0;
    for (Index k = 1; k + 1 < every.disp.rows(); ++k) {
      err = std::max(err, std::abs((every.disp(k + 1, 0) - every.disp(k - 1, 0)) / 2e-3 - every.vel(k, 0)));
      scale = std::max(scale, std::abs(every.vel(k, 0)));
    }
    CHECK(scale > 1e-4);
    CHECK(err < 0.02 * scale);  // ω ≈ 50 rad/s: (ω dt)²/6 ≈ 4e-4, with the force's stop and IDA's tolerance
  }
  // Where a kernel does not have them, asked for, they are an input error, not silent zeros.
  solve::IntegrationSettings s;
  c.progress = nullptr;
  CHECK_THROWS_AS(solve::make_integrator(s, outs)->run_batch({c, c}, all), InputError);
  s.method = solve::Method::modal;
  CHECK_THROWS_WITH(solve::make_integrator(s, {})->run(c, solve::Recording{}), Catch::Contains("without a modal model"));
  // Sums of outputs are the modal peaks kernel's: elsewhere an input error, never ignored.
  solve::Recording with_sums;
  with_sums.sums.push_back({0, 1, -1, -1});
  for (const solve::Method m : {solve::Method::newmark, solve::Method::ida}) {
    s.method = m;
    INFO(solve::method_name(m));
    CHECK_THROWS_WITH(solve::make_integrator(s, outs)->run(c, with_sums), Catch::Contains("sums of outputs are tracked by the modal peaks kernel only"));
  }
  s.method = solve::Method::newmark;
  CHECK_THROWS_AS(solve::make_integrator(s, outs)->run_batch({c, c}, with_sums), InputError);
}

TEST_CASE("a method's traits are what its integrator does") {
  // Callers prepare models and batch cases from method_traits(), before any integrator exists:
  // each trait must hold for the integrator make_integrator() builds (a modal one without its
  // reduction refuses to run; one that batches histories has a batch wider than one case; the
  // modal one's four lanes are the peaks kernel's, not histories').
  for (const solve::Method m : {solve::Method::newmark, solve::Method::modal, solve::Method::ida}) {
    INFO(solve::method_name(m));
    solve::IntegrationSettings s;
    s.method = m;
    const solve::MethodTraits t = solve::method_traits(m);
    const auto integ = solve::make_integrator(s, {});
    CHECK(integ->method() == m);
    CHECK(integ->coupled_coordinates() == t.coupled);
    if (t.batches_histories) CHECK(integ->batch_width() > 1);
  }
  CHECK(solve::method_traits(solve::Method::modal).needs_reduction);
  CHECK_FALSE(solve::method_traits(solve::Method::newmark).needs_reduction);
  CHECK_FALSE(solve::method_traits(solve::Method::ida).needs_reduction);
}

TEST_CASE("vehicles go through the integration face: each method runs its coupled kernel") {
  // One structure DOF and one wheel on it (coupled_fixtures): the face's run_coupled() is the
  // kernel the method stands for, with the method's options, and names it.
  const double ms = 2e4, ks = 8e7, cs = 3e4, mv = 1500, kc = 2e8, w = 0.7, P0 = 1e5;
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = ms;
  C.insert(0, 0) = cs;
  K.insert(0, 0) = ks;
  solve::LinearVehicle veh = one_wheel(mv, P0, kc);
  veh.release = false;
  const FixedContact path(w, 1e-3, 0.05);
  const solve::TimeGrid grid{1e-3, 0.2};
  solve::IntegrationSettings s;
  s.dt = grid.dt;
  s.newmark = solve::NewmarkOptions{0.3025, 0.6, 0.0};  // not the default: the face must pass its own
  std::vector<double> direct, faced;
  solve::coupled_newmark(M, C, K, veh, path, grid, s.newmark, [&](Index, double, const solve::CoupledState& x) { direct.push_back(x.u[0]); });
  for (const solve::Method m : {solve::Method::newmark, solve::Method::modal, solve::Method::ida}) {
    s.method = m;
    const auto integ = solve::make_integrator(s, {});
    CHECK(integ->coupled_coordinates() == (m == solve::Method::newmark ? solve::Coordinates::physical : solve::Coordinates::modal));
    solve::CoupledCase cc;
    cc.M = &M, cc.C = &C, cc.K = &K, cc.vehicle = &veh, cc.path = &path, cc.grid = grid;
    faced.clear();
    cc.observe = [&](Index, double, const solve::CoupledState& x) { faced.push_back(x.u[0]); };
    const solve::CoupledSummary r = integ->run_coupled(cc);
    INFO(solve::method_name(m));
    REQUIRE(faced.size() == direct.size());
    if (m == solve::Method::ida) {
      CHECK(r.summary.kernel == solve::Kernel::ida_vehicles);
      double e = 0, sc = 0;
      for (std::size_t k = 0; k < direct.size(); ++k) e = std::max(e, std::abs(faced[k] - direct[k])), sc = std::max(sc, std::abs(direct[k]));
      CHECK(e < 0.05 * sc);  // BDF against Newmark (γ = 0.6 damps): the same motion, not the same numbers
    } else {
      CHECK(r.summary.kernel == (m == solve::Method::newmark ? solve::Kernel::newmark_vehicles : solve::Kernel::modal_vehicles));
      CHECK(faced == direct);  // the same kernel with the same options: bit for bit
    }
  }
  solve::CoupledCase empty;
  CHECK_THROWS_AS(solve::make_integrator(s, {})->run_coupled(empty), InputError);
}
