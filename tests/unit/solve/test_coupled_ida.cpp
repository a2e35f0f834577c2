#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/ida.hpp"
#include "coupled_fixtures.hpp"

using namespace viaduct;

namespace coupled_ida_unit {

// A wheel on rigid ground under which the rail (positive down) falls away with acceleration 2c
// from t0 for tau1 seconds, then goes on at the speed it reached: r = c τ², then linear (C¹).
class Parabola : public solve::ContactPath {
 public:
  Parabola(double t0, double c, double tau1) : t0_(t0), c_(c), tau1_(tau1) {}
  void contact(std::size_t, double t, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
    dof.clear();
    weight.clear();
    r = at(t - t0_);
  }
  std::vector<double> breaks(double) const override { return {t0_, t0_ + tau1_}; }
  double at(double tau) const {
    if (tau <= 0.0) return 0.0;
    if (tau <= tau1_) return c_ * tau * tau;
    return c_ * tau1_ * tau1_ + 2.0 * c_ * tau1_ * (tau - tau1_);
  }

 private:
  double t0_, c_, tau1_;
};

}  // namespace coupled_ida_unit

using namespace coupled_ida_unit;

TEST_CASE("coupled IDA locates a wheel's loss of contact and its landing at their closed-form times") {
  // A 1000 kg wheel on a 1e7 N/m spring (ω = 100 rad/s) over a rail falling away at 2g from
  // t0 = 0.05 s. In contact (τ = t − t0): z = cτ² − (2c/ω²)(1 − cos ωτ), so the force is
  // P0 − 2cm(1 − cos ωτ): zero at ωτ = arccos(1 − g/2c) = π/3 for c = g. Then free flight at g,
  // the rail reaching constant speed at τ1 = 20 ms; it lands when P0 + k(z − r) returns to zero.
  const coupled_fixtures::Untouched st;  // a structure the wheel never touches
  const SparseMatrix &M = st.M, &C = st.C, &K = st.K;
  const double m = 1000.0, g = 9.81, k = 1e7, w = std::sqrt(k / m), c = g, t0 = 0.05, tau1 = 0.02;
  const solve::LinearVehicle veh = coupled_fixtures::one_wheel(m, m * g, k);
  const Parabola path(t0, c, tau1);
  const double tauL = std::acos(1.0 - g / (2.0 * c)) / w;
  const double zL = c * tauL * tauL - 2.0 * c / (w * w) * (1.0 - std::cos(w * tauL));
  const double vL = 2.0 * c * tauL - 2.0 * c / w * std::sin(w * tauL);
  // Landing after τ1: zL + vL s + g s²/2 − (c τ1² + 2cτ1(τL + s − τ1)) + P0/k = 0, s = τ − τL.
  const double qa = 0.5 * g, qb = vL - 2.0 * c * tau1, qc = zL - c * tau1 * tau1 - 2.0 * c * tau1 * (tauL - tau1) + m * g / k;
  const double s_land = (-qb + std::sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
  const double t_loss = t0 + tauL, t_land = t0 + tauL + s_land;
  REQUIRE(tauL < tau1);
  REQUIRE(tauL + s_land > tau1);
  solve::IdaOptions opt;
  opt.rtol = 1e-8;
  opt.atol_disp = 1e-12;
  opt.atol_vel = 1e-10;
  const solve::TimeGrid grid{1e-3, t_land + 0.005};
  const solve::CoupledSummary s = solve::coupled_ida(M, C, K, veh, path, grid, opt, nullptr);
  REQUIRE(s.events.size() >= 2);
  INFO("loss " << s.events[0].t << " s (closed form " << t_loss << "), landing " << s.events[1].t << " s (" << t_land << ")");
  CHECK_FALSE(s.events[0].landed);
  CHECK(s.events[1].landed);
  // IDA's root finding on an interpolant good to rtol = 1e-8: microseconds, against a 1 ms output step.
  CHECK(std::abs(s.events[0].t - t_loss) < 1e-6);
  CHECK(std::abs(s.events[1].t - t_land) < 1e-6);
  CHECK(s.first_release_t == s.events[0].t);
  CHECK(s.airborne_s[0] == Approx(t_land - t_loss).margin(2e-6));
  CHECK(s.min_contact_force[0] == 0.0);
  CHECK(s.summary.n_restarts >= 4);  // two breaks, two events

  // Newmark finds the same events only at its step's resolution.
  const double dt = 1e-4;
  const solve::CoupledSummary nm = solve::coupled_newmark(M, C, K, veh, path, {dt, grid.t_end}, {}, nullptr);
  REQUIRE(nm.events.size() >= 2);
  CHECK(std::abs(nm.events[0].t - t_loss) < 2 * dt);
  CHECK(std::abs(nm.events[1].t - t_land) < 2 * dt);
  CHECK(nm.airborne_s[0] == Approx(t_land - t_loss).margin(3 * dt));
}

TEST_CASE("coupled IDA agrees with IDA on the same system assembled by hand") {
  // Independent paths to the same equations: the reduced Newton solve, the residual with the
  // contact read from the path, against the full KLU Jacobian of the assembled system.
  const double ms = 2e4, ks = 8e7, cs = 3e4, mv = 1500, kc = 2e8, w = 0.7, P0 = 1e5, r = 1e-3, t_r = 0.05;
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = ms;
  C.insert(0, 0) = cs;
  K.insert(0, 0) = ks;
  solve::LinearVehicle veh = coupled_fixtures::one_wheel(mv, P0, kc);
  veh.release = false;  // linear: the step pulls on the wheel for a while
  const coupled_fixtures::FixedContact path(w, r, t_r);
  const coupled_fixtures::Assembled sys(ms, ks, cs, mv, kc, w, P0, r, t_r);
  solve::IdaOptions opt;
  opt.rtol = 1e-9;
  opt.atol_disp = 1e-14;
  opt.atol_vel = 1e-12;
  const solve::TimeGrid grid{1e-3, 0.3};
  std::vector<double> u1, z1, u2, z2;
  solve::coupled_ida(M, C, K, veh, path, grid, opt, [&](Index, double, const solve::CoupledState& x) {
    u1.push_back(x.u[0]);
    z1.push_back(x.z[0]);
  });
  solve::ida(sys, grid, opt, [&](Index, double, const Vector& u, const Vector&, const Vector&) {
    u2.push_back(u[0]);
    z2.push_back(u[1]);
  });
  REQUIRE(u1.size() == u2.size());
  double eu = 0, ez = 0, su = 0, sz = 0;
  for (std::size_t k = 0; k < u1.size(); ++k) {
    eu = std::max(eu, std::abs(u1[k] - u2[k]));
    ez = std::max(ez, std::abs(z1[k] - z2[k]));
    su = std::max(su, std::abs(u2[k]));
    sz = std::max(sz, std::abs(z2[k]));
  }
  // Two adaptive runs at rtol = 1e-9, each within ~1e-7 of the exact solution.
  CHECK(su > 1e-4);
  CHECK(eu < 1e-6 * su);
  CHECK(ez < 1e-6 * sz);
}

TEST_CASE("coupled IDA refuses what it cannot integrate, naming the rule") {
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = 1.0;
  K.insert(0, 0) = 1.0;
  C.resize(1, 1);
  const coupled_fixtures::FixedContact path(1.0, 0.0, 1.0);
  const solve::TimeGrid grid{1e-3, 0.01};
  solve::LinearVehicle veh = coupled_fixtures::one_wheel(1.0, 1.0, std::numeric_limits<double>::infinity());
  CHECK_THROWS_WITH(solve::coupled_ida(M, C, K, veh, path, grid, {}, nullptr), Catch::Contains("rigid"));
  veh.contact_stiffness[0] = 1e6;
  veh.M(0, 0) = 0.0;  // a massless wheel: an algebraic equation IDA is not given
  veh.K(0, 0) = 1.0;
  CHECK_THROWS_WITH(solve::coupled_ida(M, C, K, veh, path, grid, {}, nullptr), Catch::Contains("mass on every vehicle DOF"));
  veh.M(0, 0) = 1.0;
  const coupled_fixtures::FixedContact step(1.0, 1e-3, 0.0);
  CHECK_THROWS_WITH(solve::coupled_ida(M, C, K, veh, step, grid, {}, nullptr), Catch::Contains("t = 0"));
  solve::IdaOptions bad;
  bad.rtol = 0.0;
  CHECK_THROWS_WITH(solve::coupled_ida(M, C, K, veh, path, grid, bad, nullptr), Catch::Contains("rtol"));
  SparseMatrix big(3001, 3001);
  big.setIdentity();
  CHECK_THROWS_WITH(solve::coupled_ida(big, big, big, veh, path, grid, {}, nullptr), Catch::Contains("modes"));
}
