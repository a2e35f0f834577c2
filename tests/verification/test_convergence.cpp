#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <functional>

#include "helpers.hpp"

using namespace viaduct;

namespace {
// The span under a smooth force P (1 - cos Ωt) at mid-span (f and f' vanish at t = 0).
class SmoothForce : public solve::SecondOrderSystem {
 public:
  SmoothForce(const model::Structure& s, double P, double Om) : s_(s), P_(P), Om_(Om), pt_(s.deck_point(0, 10.0)) {}
  const SparseMatrix& mass() const override { return s_.M; }
  const SparseMatrix& damping() const override { return s_.C; }
  const SparseMatrix& stiffness() const override { return s_.K; }
  void force(double t, Vector& f) const override {
    f.setZero();
    for (std::size_t q = 0; q < 4; ++q)
      if (pt_.dofs[q] >= 0) f[pt_.dofs[q]] += P_ * (1 - std::cos(Om_ * t)) * pt_.N[q];
  }

 private:
  const model::Structure& s_;
  double P_, Om_;
  model::PointCoupling pt_;
};

// States (u, v) at t = 0, T/8, ..., T for step dt (all DOFs).
std::vector<std::pair<Vector, Vector>> states(const solve::SecondOrderSystem& sys, double dt, double T) {
  std::vector<std::pair<Vector, Vector>> out;
  const solve::NewmarkOptions o;
  const solve::TimeGrid g{dt, T};
  const auto every = static_cast<Index>(std::llround(T / 8 / dt));
  REQUIRE(std::abs(every * dt * 8 - T) < 1e-9 * T);  // samples fall on steps of every run
  solve::newmark(sys, g, o, [&](Index k, double, const Vector& u, const Vector& v, const Vector&) {
    if (k % every == 0) out.emplace_back(u, v);
  });
  return out;
}

// max over the sampled times of the energy norm sqrt(Δuᵀ K Δu + Δvᵀ M Δv)
double distance(const model::Structure& s, const std::vector<std::pair<Vector, Vector>>& a,
                const std::vector<std::pair<Vector, Vector>>& b) {
  double d = 0;
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vector du = a[i].first - b[i].first, dv = a[i].second - b[i].second;
    d = std::max(d, std::sqrt(du.dot(s.K * du) + dv.dot(s.M * dv)));
  }
  return d;
}

// max over the sampled times of sqrt(Δw² + (Δẇ/ω)²) at one point
double point_distance(const model::PointCoupling& p, double w, const std::vector<std::pair<Vector, Vector>>& a,
                      const std::vector<std::pair<Vector, Vector>>& b) {
  double d = 0;
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double du = p.value(a[i].first) - p.value(b[i].first), dv = p.value(a[i].second) - p.value(b[i].second);
    d = std::max(d, std::hypot(du, dv / w));
  }
  return d;
}

using Distance = std::function<double(const std::vector<std::pair<Vector, Vector>>&, const std::vector<std::pair<Vector, Vector>>&)>;

void check_order(const solve::SecondOrderSystem& sys, const Distance& distance_of, double dt0, double T, const char* what) {
  std::vector<std::vector<std::pair<Vector, Vector>>> runs;
  for (int i = 0; i < 4; ++i) runs.push_back(states(sys, dt0 / std::pow(2.0, i), T));
  const double e0 = distance_of(runs[0], runs[1]), e1 = distance_of(runs[1], runs[2]), e2 = distance_of(runs[2], runs[3]);
  const double p1 = std::log2(e0 / e1), p2 = std::log2(e1 / e2);
  std::printf("Newmark convergence (%s): successive differences %.3e %.3e %.3e, orders %.3f %.3f\n", what, e0, e1, e2, p1, p2);
  // Average acceleration is second order; 1.9 leaves room for the pre-asymptotic first halving.
  REQUIRE(p2 > 1.9);
  REQUIRE(p2 < 2.1);
}
}  // namespace

TEST_CASE("Newmark converges at second order in displacement and velocity (energy norm)") {
  const model::Structure s = model::build_structure(vt::span(20.0, 1e10, 1e4, 1.0, 0.02), std::nullopt);
  const SmoothForce sys(s, 1e5, 2 * M_PI * 3.0);
  check_order(sys, [&](const auto& a, const auto& b) { return distance(s, a, b); }, 1.0 / 256, 1.0,
              "smooth force, damped span, energy norm");
}

TEST_CASE("Newmark converges at second order for a moving load on the track-bridge model") {
  const study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const load::MovingLoads loads(s, load::regular_train("axle", 1, 0.0, 105e3), 50.0);
  const study::MovingLoadSystem sys(s, loads);
  // 0.64 s: the axle crosses approach track and bridge. The consistent load is C¹ in time
  // (element crossings), which still allows second order. Measured on the deck at mid-span 1
  // (displacement and velocity): the energy norm of the whole model is dominated by rail and pad
  // modes at kHz excited by the axle's step entry, for which ω dt >> 1 at any practical step
  // (pre-asymptotic: orders 1.1-1.2 there), while the deck response users read converges at 2.
  const auto deck = s.deck_point(0, 11.93 / 2);
  check_order(sys, [&](const auto& a, const auto& b) { return point_distance(deck, 2 * M_PI * 10.0, a, b); }, 2e-3,
              0.64, "moving axle, Old Guadiana with track, deck mid-span");
}
