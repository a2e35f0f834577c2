// Every Newmark/HHT kernel over a grid of schemes (alpha, beta, gamma) and steps (issue #36): an
// accepted scheme stays bounded at every step, on a system whose modes span 1 to 1e4 rad/s; a
// refused one is refused before a step is taken (InputError naming the field), or, conditionally
// stable beyond its limit, with a SolverError. Never a run that grows without a word.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>

#include "viaduct/core/eigensolvers.hpp"

#include "coupled_fixtures.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/solve/newmark.hpp"

using namespace viaduct;
using namespace viaduct::solve;

namespace schemes_test {

// Three undamped masses whose modes lie near 1, 100 and 1e4 rad/s (springs to ground, weakly
// coupled), released from rest with a unit load on the first: its energy is bounded by the work
// of the load, so |u| stays below a few static deflections.
class Spread : public SecondOrderSystem {
 public:
  Spread() {
    M_.resize(3, 3), C_.resize(3, 3), K_.resize(3, 3);
    const double k[3] = {1.0, 1e4, 1e8};
    for (int i = 0; i < 3; ++i) M_.insert(i, i) = 1.0, K_.insert(i, i) = k[i] * 1.001;
    for (int i = 0; i + 1 < 3; ++i) K_.insert(i, i + 1) = K_.insert(i + 1, i) = -1e-3 * std::sqrt(k[i] * k[i + 1]);
    M_.makeCompressed(), C_.makeCompressed(), K_.makeCompressed();
  }
  const SparseMatrix& mass() const override { return M_; }
  const SparseMatrix& damping() const override { return C_; }
  const SparseMatrix& stiffness() const override { return K_; }
  void force(double, Vector& f) const override { f.setZero(), f[0] = 1.0, f[1] = 1e4, f[2] = 1e8; }

 private:
  SparseMatrix M_, C_, K_;
};

struct Outcome {
  bool refused_input = false, refused_solver = false;
  double max_u = 0.0;  // largest |u| over the DOFs, each divided by its static deflection (1)
};

template <class Run>
Outcome outcome(Run&& run) {
  Outcome o;
  try {
    o.max_u = run();
  } catch (const InputError&) {
    o.refused_input = true;
  } catch (const SolverError&) {
    o.refused_solver = true;
  }
  return o;
}

}  // namespace schemes_test

using namespace schemes_test;

TEST_CASE("every Newmark kernel over (alpha, beta, gamma) and the step: bounded or refused, never a silent growth") {
  const Spread sys;
  const std::vector<Functional> outputs = {{{0}, {1.0}}, {{1}, {1.0}}, {{2}, {1.0}}};
  int n_run = 0, n_refused = 0;
  for (const double alpha : {0.0, -0.05, -1.0 / 3.0})
    for (const double gamma : {0.5, 0.55, 0.7})
      for (const double beta : {1.0 / 6.0, 0.25, 0.3, 0.4})
        for (const double dt : {1e-5, 1e-3, 1e-1}) {
          NewmarkOptions opt;
          opt.alpha = alpha, opt.beta = beta, opt.gamma = gamma;
          const TimeGrid grid{dt, 400 * dt};
          INFO("alpha " << alpha << " beta " << beta << " gamma " << gamma << " dt " << dt);
          const Outcome single = outcome([&] {
            double m = 0.0;
            newmark(sys, grid, opt, [&](Index, double, const Vector& u, const Vector&, const Vector&) { m = std::max(m, u.cwiseAbs().maxCoeff()); });
            return m;
          });
          const Outcome batch = outcome([&] {
            const auto h = newmark_batch({{&sys, grid.t_end}}, dt, opt, outputs);
            return h.front().disp.cwiseAbs().maxCoeff();
          });
          // The coupled kernel: a 100 kg wheel of 1 N on a Hertz spring on the softest mass.
          const Outcome coupled = outcome([&] {
            const solve::LinearVehicle veh = coupled_fixtures::one_wheel(100.0, 1.0, 1e6);
            const coupled_fixtures::FixedContact path(1.0);
            double m = 0.0;
            coupled_newmark(sys.mass(), sys.damping(), sys.stiffness(), veh, path, grid, opt,
                            [&](Index, double, const CoupledState& x) { m = std::max(m, x.u.cwiseAbs().maxCoeff()); });
            return m;
          });
          const bool accepted = opt.unconditionally_stable();
          if (accepted) {
            // Undamped from rest under a constant load: twice the static deflection in each mode;
            // the modes mix the DOFs a little (measured 2.22 at most for every accepted scheme
            // and step). 3: any growth over 400 steps of a scheme that amplified would pass it by
            // orders of magnitude (alpha -0.05 with beta 1/4: 1e24 in a real run).
            CHECK_FALSE((single.refused_input || single.refused_solver || batch.refused_input || batch.refused_solver));
            CHECK(single.max_u <= 3.0);
            CHECK(batch.max_u <= 3.0);
            CHECK_FALSE(coupled.refused_input);
            // The wheel (1 N on a 1e6 N/m spring, 100 kg on a 1 kg mass) adds its weight and its
            // bouncing: measured 18.8 at most. 100: bounded, as above.
            CHECK(coupled.max_u < 100.0);
            ++n_run;
          } else {
            // alpha != 0 outside the stable set: refused as input; alpha = 0 conditionally stable:
            // refused beyond its step limit (SolverError), else bounded. The coupled kernel takes
            // only unconditionally stable schemes.
            if (alpha != 0.0) CHECK((single.refused_input && batch.refused_input));
            else CHECK((single.refused_solver || single.max_u <= 3.0));
            if (alpha == 0.0) CHECK(single.refused_solver == batch.refused_solver);
            CHECK(coupled.refused_input);
            ++n_refused;
          }
        }
  CHECK(n_run > 20);
  CHECK(n_refused > 20);
}

TEST_CASE("the divergence guard stops every kernel past its bound, naming the output and the cause") {
  // The Spread system's responses reach about 2 static deflections (1 per DOF). A bound of 1.5
  // on output 2 is passed within the run; 10 is not.
  const Spread sys;
  const std::vector<Functional> outputs = {{{0}, {1.0}}, {{1}, {1.0}}, {{2}, {1.0}}};
  DivergenceBound tight, loose;
  tight.max_abs = Vector::Constant(3, 1e9);
  tight.max_abs[2] = 1.5;
  tight.names = {"a", "b", "c deflection [m]"};
  tight.basis = "a test's bound";
  loose.max_abs = Vector::Constant(3, 10.0);
  // The modal kernel on the system's three exact modes (mass-normalised by the reduction).
  Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> es{Matrix(sys.stiffness()), Matrix(sys.mass())};
  auto modal = std::make_shared<const ModalReduction>(sys.mass(), sys.damping(), sys.stiffness(), es.eigenvectors(),
                                                      Vector(es.eigenvalues().cwiseSqrt()), outputs, false);
  for (const Method m : {Method::newmark, Method::modal, Method::ida}) {
    IntegrationSettings s;
    s.method = m;
    s.dt = 1e-4;
    s.ida.rtol = 1e-6;
    const auto integ = make_integrator(s, outputs, m == Method::modal ? modal : nullptr);
    LoadCase c;
    c.system = &sys;
    c.t_end = 0.05;
    Recording rec;
    INFO(method_name(m));
    c.bound = &loose;
    CHECK_NOTHROW(integ->run(c, rec));
    c.bound = &tight;
    CHECK_THROWS_WITH(integ->run(c, rec), Catch::Contains("the run diverged: c deflection [m] reached") &&
                                              Catch::Contains("beyond 1.5 (a test's bound)") && Catch::Contains("likely cause"));
    // Batches (four cases per factorisation for Newmark): the case past its bound stops the batch.
    CHECK_THROWS_WITH(integ->run_batch({c, c}, rec), Catch::Contains("diverged"));
  }
  // The coupled kernel: contact forces past theirs.
  const solve::LinearVehicle veh = coupled_fixtures::one_wheel(100.0, 1.0, 1e6);
  const coupled_fixtures::FixedContact path(1.0);
  DivergenceBound contact;
  contact.max_contact_force = 0.5;  // below the wheel's static 1 N
  CHECK_THROWS_WITH(coupled_newmark(sys.mass(), sys.damping(), sys.stiffness(), veh, path, TimeGrid{1e-3, 0.01}, {}, {}, &contact),
                    Catch::Contains("the contact force of wheel 1 [N] reached") && Catch::Contains("wheel-rail contact"));
  contact.max_contact_force = 1e3;
  CHECK_NOTHROW(coupled_newmark(sys.mass(), sys.damping(), sys.stiffness(), veh, path, TimeGrid{1e-3, 0.01}, {}, {}, &contact));
}
