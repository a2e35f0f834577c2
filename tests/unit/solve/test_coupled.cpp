#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/newmark.hpp"
#include "coupled_fixtures.hpp"

using namespace viaduct;


using namespace coupled_fixtures;

TEST_CASE("coupled Newmark is Newmark on the assembled system (one structure DOF, one wheel)") {
  const double ms = 2e4, ks = 8e7, cs = 3e4, mv = 1500, kc = 2e8, w = 0.7, P0 = 1e5, r = 1e-3;
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = ms;
  C.insert(0, 0) = cs;
  K.insert(0, 0) = ks;
  solve::LinearVehicle veh = one_wheel(mv, P0, kc);
  veh.release = false;  // the assembled system is linear: the 1 mm step pulls on the wheel for a while
  const FixedContact path(w, r, 0.05);
  const Assembled sys(ms, ks, cs, mv, kc, w, P0, r, 0.05);
  for (const double alpha : {0.0, -0.1}) {
    const solve::NewmarkOptions opt = solve::NewmarkOptions::hht(alpha);
    const solve::TimeGrid grid{1e-3, 0.3};
    std::vector<double> u1, z1, p1, u2, z2, p2;
    solve::coupled_newmark(M, C, K, veh, path, grid, opt, [&](Index, double, const solve::CoupledState& x) {
      u1.push_back(x.u[0]);
      z1.push_back(x.z[0]);
      p1.push_back(x.contact_force[0]);
    });
    solve::newmark(sys, grid, opt, [&](Index k, double t, const Vector& u, const Vector&, const Vector&) {
      u2.push_back(u[0]);
      z2.push_back(u[1]);
      p2.push_back(P0 + kc * (u[1] - w * u[0] - (t >= 0.05 ? r : 0.0)));
      (void)k;
    });
    REQUIRE(u1.size() == u2.size());
    double eu = 0, ez = 0, ep = 0, su = 0;
    for (std::size_t k = 0; k < u1.size(); ++k) {
      eu = std::max(eu, std::abs(u1[k] - u2[k]));
      ez = std::max(ez, std::abs(z1[k] - z2[k]));
      ep = std::max(ep, std::abs(p1[k] - p2[k]));
      su = std::max(su, std::abs(u2[k]));
    }
    INFO("alpha = " << alpha);
    // The same scheme and equations, solved in another order: rounding only.
    CHECK(eu < 1e-10 * su);
    CHECK(ez < 1e-10 * su);
    CHECK(ep < 1e-8 * P0);
    CHECK(su > 1e-4);  // the step did move things
  }
}

TEST_CASE("a rigid contact is Newmark on the structure carrying the wheel's mass (plain and HHT)") {
  // One structure DOF u, a wheel of mass mv rigidly on it at weight w (z = w u): the wheel adds
  // mv w² to the structure's mass, (ms + mv w²) ü + cs u̇ + ks u = w P0 from rest. The coupled
  // kernel imposes z̈ = w ü and keeps z = w u, ż = w u̇: the same scheme on the assembled DOF.
  const double ms = 2e4, ks = 8e7, cs = 3e4, mv = 1500, w = 0.7, P0 = 1e5;
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = ms;
  C.insert(0, 0) = cs;
  K.insert(0, 0) = ks;
  solve::LinearVehicle veh = one_wheel(mv, P0, std::numeric_limits<double>::infinity());
  veh.release = false;
  const FixedContact path(w);
  class Assembled1 : public solve::SecondOrderSystem {
   public:
    Assembled1(double m, double c, double k, double f) : f_(f) {
      M_.resize(1, 1), C_.resize(1, 1), K_.resize(1, 1);
      M_.insert(0, 0) = m, C_.insert(0, 0) = c, K_.insert(0, 0) = k;
    }
    const SparseMatrix& mass() const override { return M_; }
    const SparseMatrix& damping() const override { return C_; }
    const SparseMatrix& stiffness() const override { return K_; }
    void force(double, Vector& f) const override { f[0] = f_; }

   private:
    SparseMatrix M_, C_, K_;
    double f_;
  } sdof(ms + mv * w * w, cs, ks, w * P0);
  for (const double alpha : {0.0, -0.1}) {
    const solve::NewmarkOptions opt = solve::NewmarkOptions::hht(alpha);
    const solve::TimeGrid grid{1e-3, 0.2};
    std::vector<double> u1, z1, p1, u2;
    solve::coupled_newmark(M, C, K, veh, path, grid, opt, [&](Index, double, const solve::CoupledState& x) {
      u1.push_back(x.u[0]);
      z1.push_back(x.z[0]);
      p1.push_back(x.contact_force[0]);
    });
    // From rest with the load on: the assembled DOF's initial acceleration is w P0 / (ms + mv w²);
    // the coupled kernel starts the wheel at rest (z̈ = 0) and the structure at w P0 / ms, then the
    // constraint holds from the first step: the first acceleration's mismatch is all that differs.
    solve::newmark(sdof, grid, opt, [&](Index, double, const Vector& u, const Vector&, const Vector&) { u2.push_back(u[0]); });
    REQUIRE(u1.size() == u2.size());
    double eu = 0, ez = 0, su = 0, pmax = 0;
    for (std::size_t k = 0; k < u1.size(); ++k) {
      eu = std::max(eu, std::abs(u1[k] - u2[k]));
      ez = std::max(ez, std::abs(z1[k] - w * u1[k]));
      su = std::max(su, std::abs(u2[k]));
      pmax = std::max(pmax, std::abs(p1[k]));
    }
    INFO("alpha = " << alpha << ": |u - u_assembled| " << eu / su << ", |z - w u| " << ez / su);
    CHECK(ez < 1e-12 * su);  // the wheel stays on the rail: exactly (projected every step)
    CHECK(eu < 2e-3 * su);   // the start's acceleration mismatch (measured 5.7e-4 plain, 4.6e-4 HHT)
    CHECK(pmax < 1.5 * P0);  // bounded: m_v w ü at most (no 1/dt² multiplier)
  }
}

TEST_CASE("coupled Newmark refuses what it cannot do, naming the rule") {
  SparseMatrix M(1, 1), C(1, 1), K(1, 1);
  M.insert(0, 0) = 1.0;
  K.insert(0, 0) = 1.0;
  C.resize(1, 1);
  solve::LinearVehicle veh;
  veh.M = Matrix::Constant(1, 1, 1.0);
  veh.C = Matrix::Zero(1, 1);
  veh.K = Matrix::Zero(1, 1);
  veh.wheel_dof = {0};
  veh.static_load = Vector::Constant(1, 1.0);
  veh.contact_stiffness = Vector::Constant(1, std::numeric_limits<double>::infinity());
  const FixedContact path(1.0);
  const solve::TimeGrid grid{1e-3, 0.01};
  // A rigid contact on a path that cannot give the rail's rates (the constraint is on accelerations).
  class NoRates : public solve::ContactPath {
    void contact(std::size_t, double, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
      dof.assign(1, 0);
      weight.assign(1, 1.0);
      r = 0.0;
    }
  } no_rates;
  CHECK_THROWS_WITH(solve::coupled_newmark(M, C, K, veh, no_rates, grid, {}, nullptr), Catch::Contains("rates of the rail"));
  CHECK_NOTHROW(solve::coupled_newmark(M, C, K, veh, path, grid, {}, nullptr));
  CHECK_NOTHROW(solve::coupled_newmark(M, C, K, veh, path, grid, solve::NewmarkOptions::hht(-0.1), nullptr));
  // A rail that is not level where the wheel starts.
  const FixedContact step(1.0, 1e-3, 0.0);
  veh.contact_stiffness[0] = 1e6;
  CHECK_THROWS_WITH(solve::coupled_newmark(M, C, K, veh, step, grid, {}, nullptr), Catch::Contains("t = 0"));
  veh.static_load[0] = -1.0;
  CHECK_THROWS_WITH(solve::coupled_newmark(M, C, K, veh, path, grid, {}, nullptr), Catch::Contains("static_load[0]"));
  veh.static_load[0] = 1.0;
  solve::NewmarkOptions lin;
  lin.beta = 1.0 / 6.0;
  CHECK_THROWS_WITH(solve::coupled_newmark(M, C, K, veh, path, grid, lin, nullptr), Catch::Contains("unconditionally stable"));
}

namespace coupled_unit {

// A wheel on rigid ground whose rail drops by `depth` over 1 ms at t0 (a dip, positive down).
class StepDown : public solve::ContactPath {
 public:
  StepDown(double t0, double depth) : t0_(t0), depth_(depth) {}
  void contact(std::size_t, double t, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
    dof.clear();
    weight.clear();
    r = depth_ * std::clamp((t - t0_) / 1e-3, 0.0, 1.0);
  }

 private:
  double t0_, depth_;
};

}  // namespace coupled_unit

using namespace coupled_unit;

TEST_CASE("a wheel leaves a rail that drops away faster than it can fall, flies under gravity and lands") {
  // A free 1000 kg wheel on a Hertz spring; the rail drops 5 mm at t0 = 0.1 s. Unilateral contact:
  // the wheel falls freely from rest, z = g (t - t0)² / 2, and lands after sqrt(2 d / g) = 31.93 ms.
  const Untouched st;  // a structure the wheel never touches
  const SparseMatrix &M = st.M, &C = st.C, &K = st.K;
  const double m = 1000.0, g = 9.81, d = 5e-3, dt = 1e-4;
  solve::LinearVehicle veh = one_wheel(m, m * g, 2e9);
  const StepDown path(0.1, d);
  const solve::TimeGrid grid{dt, 0.2};
  double left = -1, landed = -1, worst_g = 0.0;
  const auto s = solve::coupled_newmark(M, C, K, veh, path, grid, {}, [&](Index, double t, const solve::CoupledState& x) {
    const bool air = x.contact_force[0] == 0.0;
    if (air && left < 0) left = t;
    if (!air && left > 0 && landed < 0) landed = t;
    if (air && landed < 0) worst_g = std::max(worst_g, std::abs(x.za[0] - g));
  });
  const double flight = landed - left, expected = std::sqrt(2 * d / g);
  INFO("left " << left << " s, landed " << landed << " s");
  CHECK(std::abs(left - 0.1) < 2 * dt);             // leaves within the first steps of the drop
  CHECK(std::abs(flight - expected) < 1e-3 + 2 * dt);  // the 1 ms ramp and the step's resolution
  CHECK(worst_g < 1e-9 * g);                          // in the air only gravity acts
  CHECK(s.steps_released[0] > 0);
  CHECK(s.first_release_t == Approx(left).margin(1e-12));
  CHECK(s.min_contact_force[0] == 0.0);
  // The linear contact instead pulls the wheel down with the rail: a tensile force, reported.
  veh.release = false;
  const auto lin = solve::coupled_newmark(M, C, K, veh, path, grid, {}, nullptr);
  CHECK(lin.min_contact_force[0] < -m * g);
  CHECK(lin.steps_released[0] == 0);
}
