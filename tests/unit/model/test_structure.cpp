#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"
#include "viaduct/model/damping.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/model/structure.hpp"

using namespace viaduct;
using namespace viaduct::model;

namespace {
BridgeParams two_spans() {
  BridgeParams b;
  b.spans = {{11.93, 7.09e9, 8727.0}, {11.93, 7.09e9, 8727.0}};
  b.element_size = 0.6;
  b.bearings = {false, 22.33e8, 0.0};
  b.damping.kind = DampingKind::modal;
  b.damping.ratio = 0.01565;
  return b;
}
TrackParams table1_track() {
  TrackParams t;
  t.rail_EI = 2.1e11 * 3055e-8;
  t.rail_mass_per_m = 7850 * 76.86e-4;
  t.sleeper_spacing = 0.6;
  t.sleeper_mass = 300;
  t.ballast_mass = 317.91;
  t.pad = {1e8, 7.5e4};
  t.ballast = {1.933e8, 5.88e4};
  t.shear = {7.84e7, 8e4};
  t.subgrade = {7.3987e7, 3.115e4};
  t.subgrade_on_bridge = {7.3987e9, 0.0};
  return t;
}
double symmetry_error(const SparseMatrix& A) { return (Matrix(A) - Matrix(A).transpose()).norm() / Matrix(A).norm(); }
double total_translational_mass(const Structure& s) {
  // Rigid unit vertical translation of everything (rotations 0): uᵀ M u = total mass.
  Vector u = Vector::Zero(s.n_dofs);
  for (const auto* els : {&s.deck_elements, &s.rail_elements})
    for (const auto& e : *els)
      for (std::size_t q : {0u, 2u})
        if (e.dofs[q] >= 0) u[e.dofs[q]] = 1.0;
  for (Index d : s.sleeper_dof) u[d] = 1.0;
  for (Index d : s.ballast_dof) u[d] = 1.0;
  return u.dot(s.M * u);
}
}  // namespace

TEST_CASE("Hermite beam element: rigid-body modes, symmetry, mass") {
  const double h = 0.7, EI = 3.0, m = 5.0;
  const Matrix4 k = beam_stiffness(EI, h), mm = beam_mass(m, h);
  Eigen::Vector4d translate(1, 0, 1, 0), rotate(0, 1, h, 1);
  REQUIRE((k * translate).norm() < 1e-12 * k.norm());  // tolerance: round-off of O(k) sums
  REQUIRE((k * rotate).norm() < 1e-12 * k.norm());
  REQUIRE((k - k.transpose()).norm() == 0.0);
  REQUIRE(translate.dot(mm * translate) == Approx(m * h).epsilon(1e-14));
  for (double xi : {0.0, 0.3, 1.0}) {
    const auto N = hermite_shape(xi, h);
    REQUIRE(N[0] + N[2] == Approx(1.0).epsilon(1e-15));  // partition of unity for w
  }
  const auto N0 = hermite_shape(0.0, h);
  REQUIRE(N0[0] == 1.0);
  REQUIRE(N0[1] == 0.0);
}

TEST_CASE("bridge and track assembly: M and K symmetric positive definite, mass accounted") {
  for (bool with_track : {false, true}) {
    for (bool rigid : {false, true}) {
      BridgeParams b = two_spans();
      b.bearings.rigid = rigid;
      const auto t = with_track ? std::optional<TrackParams>(table1_track()) : std::nullopt;
      const Structure s = build_structure(b, t);
      INFO("track " << with_track << " rigid " << rigid);
      REQUIRE(s.has_track == with_track);
      REQUIRE(symmetry_error(s.M) == 0.0);  // assembled from exactly symmetric blocks
      REQUIRE(symmetry_error(s.K) == 0.0);
      REQUIRE(symmetry_error(s.C) == 0.0);
      Eigen::SimplicialLDLT<SparseMatrix> lk(s.K), lm(s.M);
      REQUIRE(lk.info() == Eigen::Success);
      REQUIRE(lm.info() == Eigen::Success);
      REQUIRE(lk.vectorD().minCoeff() > 0.0);
      REQUIRE(lm.vectorD().minCoeff() > 0.0);
      const double L = 23.86;
      if (rigid) continue;  // fixed end DOFs carry part of the mass to the supports
      if (!with_track) {
        REQUIRE(total_translational_mass(s) == Approx(8727.0 * L).epsilon(1e-12));
      } else {
        const TrackParams tp = table1_track();
        const double rail_len = s.path_end() - s.path_start();
        const double expect = 8727.0 * L + tp.rail_mass_per_m * rail_len +
                              (tp.sleeper_mass + tp.ballast_mass) * static_cast<double>(s.sleeper_x.size());
        REQUIRE(total_translational_mass(s) == Approx(expect).epsilon(1e-12));
      }
    }
  }
}

TEST_CASE("mass_includes_track takes the modelled track mass off the deck") {
  BridgeParams b = two_spans();
  b.mass_includes_track = true;
  const TrackParams t = table1_track();
  const Structure s = build_structure(b, t);
  REQUIRE(s.deck_mass_per_m_used == Approx(8727.0 - t.mass_per_m()).epsilon(1e-14));
  REQUIRE(t.mass_per_m() == Approx(7850 * 76.86e-4 + (300 + 317.91) / 0.6).epsilon(1e-14));
  // Without track the flag has no effect.
  REQUIRE(build_structure(b, std::nullopt).deck_mass_per_m_used == 8727.0);
  b.spans[0].mass_per_m = 1000.0;  // less than the track: rejected, not clamped
  REQUIRE_THROWS_WITH(build_structure(b, t), Catch::Contains("must be > 0"));
}

TEST_CASE("invalid physics is rejected with the violated constraint") {
  BridgeParams b = two_spans();
  b.spans[1].length = 0.0;
  REQUIRE_THROWS_WITH(build_structure(b, std::nullopt), Catch::Contains("span 2 length must be > 0"));
  b = two_spans();
  b.spans[0].EI = -1.0;
  REQUIRE_THROWS_WITH(build_structure(b, std::nullopt), Catch::Contains("EI must be > 0"));
  b = two_spans();
  b.bearings.k = 0.0;
  REQUIRE_THROWS_WITH(build_structure(b, std::nullopt), Catch::Contains("bearing stiffness k must be > 0"));
  TrackParams t = table1_track();
  t.pad.k = -1e8;
  REQUIRE_THROWS_WITH(build_structure(two_spans(), t), Catch::Contains("pad.k must be >= 0"));
  t = table1_track();
  t.ballast.c = std::nan("");
  REQUIRE_THROWS_WITH(build_structure(two_spans(), t), Catch::Contains("ballast.c"));
  b = two_spans();
  b.damping.ratio = 1.5;
  REQUIRE_THROWS_WITH(build_structure(b, std::nullopt), Catch::Contains("[0, 1)"));
}

TEST_CASE("Rayleigh coefficients reproduce both ratios") {
  const auto [a0, a1] = rayleigh_coefficients(10.065, 0.031, 90.0, 0.0156);
  auto zeta = [&](double f) {
    const double w = 2 * M_PI * f;
    return a0 / (2 * w) + a1 * w / 2;
  };
  REQUIRE(zeta(10.065) == Approx(0.031).epsilon(1e-12));
  REQUIRE(zeta(90.0) == Approx(0.0156).epsilon(1e-12));
}

TEST_CASE("modal damping gives the same ratio in every span mode") {
  BridgeParams b = two_spans();
  b.spans.resize(1);
  const Structure s = build_structure(b, std::nullopt);
  const Modes m = compute_modes(s, 0);
  const Matrix Cm = m.shape.transpose() * Matrix(s.C) * m.shape;
  for (Index j = 0; j < m.frequency_hz.size(); ++j) {
    const double w = 2 * M_PI * m.frequency_hz[j];
    REQUIRE(Cm(j, j) / (2 * w) == Approx(0.01565).epsilon(1e-8));  // eigen-solver accuracy
  }
  REQUIRE((Cm - Matrix(Cm.diagonal().asDiagonal())).cwiseAbs().maxCoeff() < 1e-8 * Cm.diagonal().maxCoeff());
}

TEST_CASE("a continuous deck: shared nodes over the supports, one bearing per support, modal damping of the whole deck") {
  BridgeParams b = two_spans();
  b.bearings = {true, 0.0, 0.0};
  BridgeParams chain_b = b;
  b.continuous = true;
  const Structure s = build_structure(b, std::nullopt);
  // The joint's node is shared: one rotation fewer than two simply supported spans (rigid
  // bearings fix both deflections there), and one deflection fewer too on elastic bearings.
  CHECK(s.n_bridge_dofs == build_structure(chain_b, std::nullopt).n_bridge_dofs - 1);
  BridgeParams elastic = b;
  chain_b.bearings = elastic.bearings = two_spans().bearings;
  CHECK(build_structure(elastic, std::nullopt).n_bridge_dofs == build_structure(chain_b, std::nullopt).n_bridge_dofs - 2);
  REQUIRE(s.bearings.size() == 3);
  CHECK(s.bearings[0].name == "support1");
  CHECK(s.bearings[2].name == "support3");
  CHECK(s.bearings[1].elements.size() == 2);
  CHECK(s.bearings[1].x == Approx(b.spans[0].length));
  CHECK(s.span_bearings[0] == std::array<std::size_t, 2>{{0, 1}});
  CHECK(s.span_bearings[1] == std::array<std::size_t, 2>{{1, 2}});
  CHECK(s.deck_elements[s.span_first_element[1] - 1].dofs[3] == s.deck_elements[s.span_first_element[1]].dofs[1]);
  // The permanent loads add up to the deck's weight.
  double total = 0.0;
  for (const auto& br : s.bearings) total += br.permanent;
  CHECK(total == Approx(9.80665 * (b.spans[0].mass_per_m * b.spans[0].length + b.spans[1].mass_per_m * b.spans[1].length)).epsilon(1e-12));
  // Modal damping of the whole deck: the deck's modes are uncoupled and damped at the ratio.
  const Modes m = compute_modes(s, 0);
  const Matrix Cm = m.shape.transpose() * Matrix(s.C) * m.shape;
  for (Index j = 0; j < m.frequency_hz.size(); ++j)
    REQUIRE(Cm(j, j) / (4 * M_PI * m.frequency_hz[j]) == Approx(b.damping.ratio).epsilon(1e-8));
  REQUIRE((Cm - Matrix(Cm.diagonal().asDiagonal())).cwiseAbs().maxCoeff() < 1e-8 * Cm.diagonal().maxCoeff());
  // Too many elements for one deck's dense damping eigenproblem: an error naming the key.
  BridgeParams big = b;
  big.spans = std::vector<SpanParams>(3, {400.0, 1e10, 1e4});
  big.element_size = 0.5;
  CHECK_THROWS_WITH(build_structure(big, std::nullopt), Catch::Contains("bridge.element_size 0.5 m gives 2400 elements on the continuous deck"));
}

TEST_CASE("points on deck and rail interpolate with the element's shape functions") {
  const Structure s = build_structure(two_spans(), table1_track());
  REQUIRE_THROWS_AS(s.deck_point(2, 1.0), InputError);          // no third span
  REQUIRE_THROWS_AS(s.deck_point(0, 12.5), InputError);         // beyond the span
  REQUIRE_THROWS_AS(s.rail_point(s.path_end() + 1.0), InputError);
  // A deflection field w = a + b x on the rail's DOFs is reproduced exactly.
  Vector u = Vector::Zero(s.n_dofs);
  for (const auto& e : s.rail_elements) {
    u[e.dofs[0]] = 1.0 + 0.1 * e.x0;
    u[e.dofs[1]] = 0.1;
    u[e.dofs[2]] = 1.0 + 0.1 * (e.x0 + e.h);
    u[e.dofs[3]] = 0.1;
  }
  for (double x : {-19.7, 0.0, 5.123, 23.86, 40.0})
    REQUIRE(s.rail_point(x).value(u) == Approx(1.0 + 0.1 * x).epsilon(1e-13));
}

TEST_CASE("sparse shift-invert modes (Spectra) match the dense solver") {
  // Two spans with track, two rail elements per bay: a few hundred DOFs. The sparse solver must
  // give the same frequencies (1e-8 relative: both converge to machine precision) and genuine
  // eigenvectors (residual ‖Kφ − λMφ‖ / ‖Kφ‖ < 1e-6), mass-normalised; the close pairs of the
  // track rule out comparing individual vectors.
  TrackParams t = table1_track();
  t.rail_elements_per_bay = 2;
  const Structure s = build_structure(two_spans(), t);
  const Modes dense = compute_modes_up_to(s, 0, 120.0, ModeSolver::dense);
  for (const auto& [n_modes, f_max] : {std::pair<Index, double>{0, 120.0}, {12, 0.0}, {12, 120.0}}) {
    const Modes sparse = compute_modes_up_to(s, n_modes, f_max, ModeSolver::sparse);
    const Index n = n_modes > 0 ? std::min<Index>(n_modes, dense.frequency_hz.size()) : dense.frequency_hz.size();
    REQUIRE(sparse.frequency_hz.size() == n);
    for (Index i = 0; i < n; ++i) {
      REQUIRE(sparse.frequency_hz[i] == Approx(dense.frequency_hz[i]).epsilon(1e-8));
      const Vector phi = sparse.shape.col(i);
      const double lam = std::pow(2 * M_PI * sparse.frequency_hz[i], 2);
      REQUIRE((s.K * phi - lam * (s.M * phi)).norm() < 1e-6 * (s.K * phi).norm());
      REQUIRE(phi.dot(s.M * phi) == Approx(1.0).epsilon(1e-10));
    }
  }
  REQUIRE(dense.frequency_hz.size() > 20);  // the test exercises the growing request
}

TEST_CASE("deck mass share tells deck modes from track modes") {
  using namespace viaduct::model;
  BridgeParams b;
  b.spans = {SpanParams{12.0, 4e9, 10000.0}};
  Structure bare = build_structure(b, std::nullopt);
  const Modes mb = compute_modes(bare, 3);
  for (Index j = 0; j < 3; ++j) CHECK(deck_mass_share(bare, mb.shape.col(j)) == Approx(1.0));
  CHECK(std::string(mode_kind(1.0)) == "deck");
  CHECK(std::string(mode_kind(0.05)) == "track");
  CHECK(std::string(mode_kind(0.3)) == "coupled");
  // A vector on the track DOFs only has no share on the deck.
  const Structure with = build_structure(b, table1_track());
  Vector track_only = Vector::Zero(with.n_dofs);
  track_only.tail(with.n_track_dofs).setOnes();
  CHECK(deck_mass_share(with, track_only) == Approx(0.0));
  Vector deck_only = Vector::Zero(with.n_dofs);
  deck_only.head(with.n_bridge_dofs).setOnes();
  CHECK(deck_mass_share(with, deck_only) == Approx(1.0));
}

TEST_CASE("deck bending order and span of each mode") {
  // One span on rigid bearings: mode n is the n-th bending mode (f_n = n² f_1).
  BridgeParams b;
  b.spans = {SpanParams{12.0, 4e9, 10000.0}};
  const Structure one = build_structure(b, std::nullopt);
  const Modes m1 = compute_modes(one, 5);
  for (Index j = 0; j < 5; ++j) {
    INFO("mode " << j + 1);
    const DeckBending d = deck_bending(one, m1.shape.col(j));
    CHECK(d.span == 1);
    CHECK(d.order == j + 1);
  }
  // Two unequal spans (12 m and 9 m): the first mode bends the longer span once, the mode near
  // the short span's first frequency bends that one.
  b.spans = {SpanParams{12.0, 4e9, 10000.0}, SpanParams{9.0, 4e9, 10000.0}};
  const Structure two = build_structure(b, std::nullopt);
  const Modes m2 = compute_modes(two, 4);
  CHECK(deck_bending(two, m2.shape.col(0)).span == 1);
  CHECK(deck_bending(two, m2.shape.col(0)).order == 1);
  CHECK(deck_bending(two, m2.shape.col(1)).span == 2);
  CHECK(deck_bending(two, m2.shape.col(1)).order == 1);
  // Soft bearings: the lowest mode is the span bouncing on them (order 0), the next bends it.
  b.spans = {SpanParams{12.0, 4e9, 10000.0}};
  b.bearings = {false, 1e5, 0.0};
  const Structure soft = build_structure(b, std::nullopt);
  const Modes ms = compute_modes(soft, 3);
  CHECK(deck_bending(soft, ms.shape.col(0)).order == 0);
  CHECK(deck_bending(soft, ms.shape.col(2)).order == 1);
  // No deck deflection: no span.
  CHECK(deck_bending(one, Vector::Zero(one.n_dofs)).span == 0);
}

TEST_CASE("deck moment and end rotations: the static closed forms of a simply supported span") {
  // 15 m span on rigid bearings, 0.5 m elements; a point force P at a, solved statically.
  BridgeParams b;
  b.spans = {SpanParams{15.0, 7.694e9, 15000.0}};
  b.element_size = 0.5;
  const Structure s = build_structure(b, std::nullopt);
  Eigen::SimplicialLDLT<SparseMatrix> K(s.K);
  REQUIRE(K.info() == Eigen::Success);
  const double L = 15.0, EI = 7.694e9, P = 1e5;
  for (const double a : {2.0, 5.25, 7.5, 11.1}) {
    Vector f = Vector::Zero(s.n_dofs);
    const PointCoupling at = s.deck_point(0, a);
    for (std::size_t i = 0; i < 4; ++i)
      if (at.dofs[i] >= 0) f[at.dofs[i]] += P * at.N[i];
    const Vector u = K.solve(f);
    for (const double x : {7.5, 3.75, 11.25, 4.1}) {
      INFO("force at " << a << " m, moment at " << x << " m");
      const double exact = x <= a ? P * (L - a) * x / L : P * a * (L - x) / L;
      // Hermite elements are exact at the nodes (and so is the curvature of an element without
      // the force); an element that holds it, or a point inside one, is off by up to about
      // P·h/8 (h = 0.5 m): h/2L = 1.7 % of P·L/4 here.
      const double tol = (std::abs(x - a) < 0.5 || std::fmod(x, 0.5) != 0.0) ? 0.02 * P * L / 4 : 1e-9 * P * L / 4;
      CHECK(std::abs(s.deck_moment(0, x).value(u) - exact) <= tol);
    }
    // End rotations: θ_A = P b (L² − b²) / (6 EI L), b = L − a; θ_B = −P a (L² − a²) / (6 EI L). Exact at nodes.
    const double bb = L - a;
    CHECK(s.deck_end_rotation(0, false).value(u) == Approx(P * bb * (L * L - bb * bb) / (6 * EI * L)).epsilon(1e-9));
    CHECK(s.deck_end_rotation(0, true).value(u) == Approx(-P * a * (L * L - a * a) / (6 * EI * L)).epsilon(1e-9));
  }
  CHECK_THROWS_WITH(s.deck_moment(0, 16.0), Catch::Contains("outside span 1"));
  CHECK_THROWS_WITH(s.deck_moment(1, 1.0), Catch::Contains("span 2 does not exist"));
}

TEST_CASE("bearing forces: the static reactions of a simply supported span, rigid or elastic, with or without track") {
  const double L = 15.0, P = 1e5;
  BridgeParams b;
  b.spans = {SpanParams{L, 7.694e9, 15000.0}};
  b.element_size = 0.5;
  for (const bool rigid : {true, false}) {
    b.bearings = {rigid, rigid ? 0.0 : 5e9, 0.0};
    const Structure s = build_structure(b, std::nullopt);
    REQUIRE(s.bearings.size() == 2);
    Eigen::SimplicialLDLT<SparseMatrix> K(s.K);
    for (const double a : {0.2, 3.3, 7.5, 14.9}) {
      INFO((rigid ? "rigid" : "elastic") << ", force at " << a << " m");
      Vector f = Vector::Zero(s.n_dofs);
      const PointCoupling at = s.deck_point(0, a);
      for (std::size_t i = 0; i < 4; ++i)
        if (at.dofs[i] >= 0) f[at.dofs[i]] += P * at.N[i];
      const Vector u = K.solve(f);
      for (const auto& br : s.bearings) {
        // A force on the bearing's own element loads its fixed DOF directly: P·N there.
        double direct = 0.0;
        REQUIRE(br.elements.size() == 1);
        const PathElement& el = br.elements[0].element;
        if (br.rigid && a >= el.x0 && a <= el.x0 + el.h)
          direct = P * hermite_shape((a - el.x0) / el.h, el.h)[static_cast<std::size_t>(br.elements[0].fixed_local)];
        const double R = br.k.value(u) + direct;
        // Statics: R_start = P (L − a)/L, R_end = P a/L, exact (1e-9) either way.
        CHECK(R == Approx(br.end ? P * a / L : P * (L - a) / L).epsilon(1e-9));
      }
    }
  }
  // With the Old Guadiana track on rigid bearings, a force on the rail: the bearings carry it
  // all (the track's links to the ground off the bridge take a part): R_start + R_end + ground
  // = P, and the force's own bearing carries most.
  b.bearings = {true, 0.0, 0.0};
  const Structure t = build_structure(b, table1_track());
  REQUIRE(t.bearings.size() == 2);
  Eigen::SimplicialLDLT<SparseMatrix> K(t.K);
  Vector f = Vector::Zero(t.n_dofs);
  const PointCoupling at = t.rail_point(2.0);
  for (std::size_t i = 0; i < 4; ++i)
    if (at.dofs[i] >= 0) f[at.dofs[i]] += P * at.N[i];
  const Vector u = K.solve(f);
  double ground = 0.0;  // the subgrade springs off the bridge
  for (std::size_t i = 0; i < t.sleeper_x.size(); ++i)
    if (t.sleeper_x[i] < -1e-9 || t.sleeper_x[i] > L + 1e-9) ground += table1_track().subgrade.k * u[t.ballast_dof[i]];
  const double R0 = t.bearings[0].k.value(u), R1 = t.bearings[1].k.value(u);
  CHECK(R0 + R1 + ground == Approx(P).epsilon(1e-9));
  CHECK(R0 > R1);
  CHECK(R1 > 0.0);
}

TEST_CASE("track.first_sleeper_offset places the sleepers relative to the bridge start") {
  BridgeParams b = two_spans();
  TrackParams t = table1_track();
  t.approach_length = 5.0;
  t.exit_length = 5.0;
  const Structure unset = build_structure(b, t);
  CHECK(unset.sleeper_x.front() == Approx(-5.0));  // unset: the track starts at −approach with a sleeper
  for (const double offset : {0.0, 0.25, 0.59}) {
    t.first_sleeper_offset = offset;
    const Structure s = build_structure(b, t);
    INFO("offset " << offset);
    // The first sleeper on the bridge at the offset, the track starting at or before −approach
    // (less than a bay before it), the grid regular.
    const auto on = std::find_if(s.sleeper_x.begin(), s.sleeper_x.end(), [](double x) { return x >= -1e-12; });
    REQUIRE(on != s.sleeper_x.end());
    CHECK(*on == Approx(offset).margin(1e-12));
    CHECK(s.sleeper_x.front() <= -5.0 + 1e-9);
    CHECK(s.sleeper_x.front() > -5.6);
    for (std::size_t i = 1; i < s.sleeper_x.size(); ++i) CHECK(s.sleeper_x[i] - s.sleeper_x[i - 1] == Approx(0.6));
    CHECK(s.sleeper_x.back() <= b.total_length() + 5.0 + 1e-9);
  }
  t.first_sleeper_offset = 0.6;  // must be below the spacing
  CHECK_THROWS_WITH(build_structure(b, t), Catch::Contains("first_sleeper_offset must be in [0, sleeper_spacing = 0.6)"));
}

TEST_CASE("two identical spans coupled by the track: which span the lower mode bends flips with the sleeper layout") {
  // The first bending modes of the two spans are 0.5 % apart (the track couples them); the span
  // that dominates the lower one follows where the sleepers sit at the joint (docs/model.md);
  // for every layout the two stay first bending modes of different spans within 1 %.
  const BridgeParams b = two_spans();
  TrackParams t = table1_track();
  std::set<int> lower_span;
  for (const double offset : {0.0, 0.15, 0.3, 0.45}) {
    t.first_sleeper_offset = offset;
    const auto modes = deck_bending_modes(build_structure(b, t), 2);
    REQUIRE(modes.size() == 2);
    INFO("offset " << offset);
    CHECK(modes[0].bending.order == 1);
    CHECK(modes[1].bending.order == 1);
    CHECK(modes[0].bending.span != modes[1].bending.span);
    CHECK(modes[1].frequency_hz / modes[0].frequency_hz - 1 < 0.01);
    lower_span.insert(modes[0].bending.span);
  }
  CHECK(lower_span.size() == 2);  // each span is the lower one for some layout
}

TEST_CASE("deck bending modes by the sparse solver are every dense mode's, the lowest the more accurate") {
  // Two spans on their track (hundreds of DOFs): deck_bending_modes takes the lowest modes by
  // shift-invert. The same deck modes from the dense solver of every mode agree to 1e-8 (the dense
  // solver's error grows with the highest mode: ~1e-9 on the lowest here), and the sparse lowest
  // mode has the smaller residual ‖Kφ − ω²Mφ‖ / ‖Kφ‖.
  const Structure s = build_structure(two_spans(), table1_track());
  REQUIRE(s.n_dofs > 64);  // the sparse solver is used for 2·4 + 4 = 12 modes (dense past n/4)
  const auto deck = deck_bending_modes(s, 4);
  REQUIRE(deck.size() == 4);
  const Modes dense = compute_modes_up_to(s, 40, 0.0, ModeSolver::dense);
  std::vector<double> dense_deck;
  for (Index j = 0; j < dense.frequency_hz.size() && dense_deck.size() < 4; ++j)
    if (tag_mode(s, dense.shape.col(j)).bending.order >= 1) dense_deck.push_back(dense.frequency_hz[j]);
  REQUIRE(dense_deck.size() == 4);
  for (std::size_t i = 0; i < 4; ++i) CHECK(deck[i].frequency_hz == Approx(dense_deck[i]).epsilon(1e-8));
  const Modes sparse = compute_modes_up_to(s, 4, 0.0, ModeSolver::sparse);
  auto residual = [&](const Modes& m) {
    const Vector phi = m.shape.col(0);
    const double w2 = std::pow(2.0 * M_PI * m.frequency_hz[0], 2);
    return (s.K * phi - w2 * (s.M * phi)).norm() / (s.K * phi).norm();
  };
  CHECK(residual(sparse) < 1e-9);
  CHECK(residual(sparse) <= residual(dense));
}
