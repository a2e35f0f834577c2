#include <catch2/catch.hpp>

#include "viaduct/core/eigensolvers.hpp"

#include "viaduct/core/error.hpp"
#include "viaduct/load/vehicle.hpp"

using namespace viaduct;

namespace vehicle_unit {

// REFERENCE.md §8: the AVE S103 intermediate coach.
load::CoachSpec ave() {
  load::CoachSpec c;
  c.name = "AVE S103";
  c.body_mass = 47800, c.body_pitch_inertia = 1957888, c.bogie_spacing = 17.375, c.bogie_mass = 3500;
  c.bogie_pitch_inertia = 1715, c.wheelbase = 2.5, c.wheelset_mass = 1800, c.primary_k = 2.4e6, c.primary_c = 2e4;
  c.secondary_k = 7e5, c.secondary_c = 4e4, c.length = 25.0;
  return c;
}

// Eigenvalues of a symmetric matrix, ascending.
Vector eigenvalues(const Matrix& A) { return Eigen::SelfAdjointEigenSolver<Matrix>(A).eigenvalues(); }

}  // namespace vehicle_unit

using namespace vehicle_unit;

TEST_CASE("AVE S103 coach: masses, static axle loads and axle positions of REFERENCE.md section 8") {
  const load::CoachSpec c = ave();
  CHECK(c.mass() == Approx(62000.0).epsilon(1e-15));
  CHECK(c.axle_load(9.81) == Approx(152055.0).epsilon(1e-12));
  const load::Train t = load::coach_train("3 AVE", c, 3);
  REQUIRE(t.n_axles() == 12);
  const std::vector<double> first = {0.0, 2.5, 17.375, 19.875};
  for (std::size_t i = 0; i < 4; ++i) {
    CHECK(t.offset[i] == first[i]);
    CHECK(t.offset[8 + i] == first[i] + 50.0);
  }
  CHECK(t.total_load() == Approx(3 * 62000.0 * 9.81).epsilon(1e-12));
  CHECK(t.coaches.size() == 3);
}

TEST_CASE("multibody coaches: symmetric matrices, free motions and the static loads they carry") {
  const load::Train t = load::coach_train("2 AVE", ave(), 2);
  const load::TrainVehicles v = load::multibody_vehicles(t);
  REQUIRE(v.n_dofs() == 20);
  REQUIRE(v.wheel_dof.size() == 8);
  CHECK((v.K - v.K.transpose()).norm() == 0.0);
  CHECK((v.C - v.C.transpose()).norm() == 0.0);
  CHECK(v.M.trace() == Approx(2 * (47800 + 1957888 + 2 * (3500 + 1715) + 4 * 1800)).epsilon(1e-14));
  // A coach in the air has four free motions (body bounce and pitch, each bogie's pitch with its
  // wheels following): K is positive semi-definite with nullity 4 per coach.
  const Vector ev = eigenvalues(v.K);
  const double big = ev.maxCoeff();
  int zero = 0;
  for (Index i = 0; i < ev.size(); ++i) {
    CHECK(ev[i] > -1e-9 * big);
    if (std::abs(ev[i]) < 1e-9 * big) ++zero;
  }
  CHECK(zero == 8);
  // On rigid supports under its wheels (a stiff spring each), none is left.
  Matrix Kg = v.K;
  for (Index d : v.wheel_dof) Kg(d, d) += 1e9;
  CHECK(eigenvalues(Kg).minCoeff() > 0.0);
  // Statics: pressing the body down by its weight and each bogie by its own, the wheels fixed,
  // the springs pass to each wheel a quarter of the body and half a bogie: with K_ff z_f = F_f the
  // free DOFs' displacement, the wheel reactions −K_wf z_f are the axle loads minus the wheelsets.
  std::vector<Index> free, wheel;
  for (Index i = 0; i < 10; ++i) (i >= 6 ? wheel : free).push_back(i);
  Matrix Kff(6, 6), Kwf(4, 6);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) Kff(i, j) = v.K(free[i], free[j]);
    for (int w = 0; w < 4; ++w) Kwf(w, i) = v.K(wheel[w], free[i]);
  }
  Vector F = Vector::Zero(6);
  F[0] = 47800 * 9.81, F[2] = 3500 * 9.81, F[4] = 3500 * 9.81;
  const Vector reaction = -Kwf * Kff.ldlt().solve(F);
  for (int w = 0; w < 4; ++w) CHECK(reaction[w] == Approx(152055.0 - 1800 * 9.81).epsilon(1e-10));
}

TEST_CASE("sprung masses per axle and the sprung reduction of a coach") {
  const load::Train t = load::regular_train("4 x 170 kN", 4, 3.0, 170e3);
  const load::TrainVehicles v = load::sprung_vehicles(t, {1800.0, 3e5, 1e4});
  REQUIRE(v.n_dofs() == 8);
  CHECK(v.M(0, 0) + v.M(1, 1) == Approx(170e3 / 9.81).epsilon(1e-14));
  CHECK(v.K(0, 1) == -3e5);
  CHECK(v.C(0, 0) == 1e4);
  CHECK(v.body_names.front() == "a1");
  const load::SprungSpec s = load::sprung_of(ave());
  CHECK(s.unsprung_mass == 1800.0);
  CHECK(s.k == Approx(1.0 / (1.0 / 2.4e6 + 2.0 / 7e5)).epsilon(1e-14));
  CHECK(s.c == Approx(1e4).epsilon(1e-14));
}

TEST_CASE("vehicle models refuse impossible parameters, naming the field and the rule") {
  load::CoachSpec c = ave();
  c.body_mass = -1.0;
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("body_mass = -1") && Catch::Contains("> 0"));
  c = ave();
  c.length = 19.0;  // shorter than its own axles
  CHECK_THROWS_WITH(load::coach_train("t", c, 2), Catch::Contains("length = 19") && Catch::Contains("next coach"));
  c = ave();
  c.wheelbase = 20.0;
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("bogie_spacing") && Catch::Contains("overlap"));
  CHECK_THROWS_WITH(load::coach_train("t", ave(), 0), Catch::Contains("n_coaches = 0"));
  const load::Train light = load::regular_train("light", 2, 3.0, 10e3);
  CHECK_THROWS_WITH(load::sprung_vehicles(light, {1800.0, 3e5, 0.0}), Catch::Contains("not more than its unsprung mass"));
  CHECK_THROWS_WITH(load::sprung_vehicles(light, {100.0, -1.0, 0.0}), Catch::Contains("stiffness = -1"));
  CHECK_THROWS_WITH(load::multibody_vehicles(light), Catch::Contains("not of coaches"));
}

TEST_CASE("articulated coaches share their bogies: loads, free motions and the static load of each axle") {
  const load::CoachSpec c = ave();
  const load::Train t = load::articulated_train("3 on 4 bogies", c, 3);
  REQUIRE(t.articulated);
  REQUIRE(t.n_axles() == 8);
  CHECK(t.offset[2] == c.bogie_spacing);
  CHECK(t.offset[3] == c.bogie_spacing + c.wheelbase);
  CHECK(t.total_load() == Approx(9.81 * (3 * 47800 + 4 * 3500 + 8 * 1800)).epsilon(1e-12));
  CHECK(t.load[0] == Approx(9.81 * (47800 / 4.0 + 3500 / 2.0 + 1800)).epsilon(1e-12));
  CHECK(t.load[3] == Approx(9.81 * (47800 / 2.0 + 3500 / 2.0 + 1800)).epsilon(1e-12));
  const load::TrainVehicles v = load::multibody_vehicles(t);
  REQUIRE(v.n_dofs() == 6 * 3 + 4);
  REQUIRE(v.wheel_dof.size() == 8);
  CHECK(v.dof_names.size() == static_cast<std::size_t>(v.n_dofs()));
  CHECK((v.K - v.K.transpose()).norm() == 0.0);
  // In the air 22 DOFs against 14 springs: each bogie's pitch with its wheels following (4) and
  // the chain of bodies, hinged at the shared pivots (6 DOFs less 2 hinges: 4).
  const Vector ev = eigenvalues(v.K);
  int zero = 0;
  for (Index i = 0; i < ev.size(); ++i)
    if (std::abs(ev[i]) < 1e-9 * ev.maxCoeff()) ++zero;
  CHECK(zero == 8);
  // Statics with the wheels fixed: the wheel reactions are the axle loads minus the wheelsets.
  const Index nf = v.n_dofs() - 8;
  const Matrix Kff = v.K.topLeftCorner(nf, nf), Kwf = v.K.bottomLeftCorner(8, nf);
  Vector F = Vector::Zero(nf);
  for (Index k = 0; k < 3; ++k) F[2 * k] = 47800 * 9.81;
  for (Index j = 0; j < 4; ++j) F[6 + 2 * j] = 3500 * 9.81;
  const Vector reaction = -Kwf * Kff.ldlt().solve(F);
  for (Index w = 0; w < 8; ++w) CHECK(reaction[w] == Approx(t.load[static_cast<std::size_t>(w)] - 1800 * 9.81).epsilon(1e-10));
}

TEST_CASE("car-body floor points: the pitch DOF and the arm to the bogie centres, where the secondary springs act") {
  // The comfort check's floor positions (above the bogie centres) must be the points the model's
  // secondary suspension acts at: a body pitching alone stretches its two springs by ± arm, so
  // K(pitch, pitch) = 2 k2 arm², conventional and articulated alike. Sprung masses do not pitch.
  const load::CoachSpec c = ave();
  for (const load::Train& t : {load::coach_train("2 AVE", c, 2), load::articulated_train("3 on 4", c, 3)}) {
    INFO(t.name);
    const load::TrainVehicles v = load::multibody_vehicles(t);
    REQUIRE(v.body_pitch_dof.size() == v.body_dof.size());
    REQUIRE(v.body_arm.size() == v.body_dof.size());
    for (std::size_t b = 0; b < v.body_dof.size(); ++b) {
      const Index p = v.body_pitch_dof[b];
      REQUIRE(p >= 0);
      CHECK(v.dof_names[static_cast<std::size_t>(p)] == v.body_names[b] + "_body_pitch");
      CHECK(v.body_arm[b] == c.bogie_spacing / 2.0);
      CHECK(v.K(p, p) == Approx(2.0 * c.secondary_k * v.body_arm[b] * v.body_arm[b]).epsilon(1e-14));
    }
  }
  const load::TrainVehicles s = load::sprung_vehicles(load::regular_train("4", 4, 3.0, 170e3), load::SprungSpec{1800.0, 1e6, 1e4});
  for (std::size_t b = 0; b < s.body_dof.size(); ++b) {
    CHECK(s.body_pitch_dof[b] == -1);
    CHECK(s.body_arm[b] == 0.0);
  }
}
