#include <catch2/catch.hpp>
#include <cstdio>

#include "helpers.hpp"

using namespace viaduct;

namespace {
struct Outcome {
  double max_disp = 0, max_acc = 0, e_max = 0, e_exit_min = 1e300, e_exit_max = 0;
  bool finite = true;
};

// Runs the Old Guadiana track-bridge model under two 105 kN wheels 3 m apart and watches the
// energy ½vᵀMv + ½uᵀKu along the way.
Outcome run(study::Scenario sc, double v, double dt, double free_s = 0.2) {
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const load::Train t = load::regular_train("bogie", 2, 3.0, 210e3);
  const load::MovingLoads loads(s, t, v, 0.5);
  const study::MovingLoadSystem sys(s, loads);
  const solve::NewmarkOptions o = sc.settings.newmark;
  const solve::TimeGrid g{dt, loads.t_exit() + free_s};
  const auto deck = s.deck_point(0, 11.93 / 2);
  Outcome out;
  solve::newmark(sys, g, o, [&](Index, double time, const Vector& u, const Vector& vel, const Vector& a) {
    out.finite = out.finite && u.allFinite() && vel.allFinite() && a.allFinite();
    out.max_disp = std::max(out.max_disp, std::abs(deck.value(u)));
    out.max_acc = std::max(out.max_acc, std::abs(deck.value(a)));
    const double e = 0.5 * vel.dot(s.M * vel) + 0.5 * u.dot(s.K * u);
    out.e_max = std::max(out.e_max, e);
    if (time > loads.t_exit() + 2 * dt) {
      out.e_exit_min = std::min(out.e_exit_min, e);
      out.e_exit_max = std::max(out.e_exit_max, e);
    }
  });
  return out;
}

// Static deflection and strain energy with both wheels at mid-span: the scale of "sensible".
std::pair<double, double> static_scale(const study::Scenario& sc) {
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  Vector f = Vector::Zero(s.n_dofs);
  const auto p = s.rail_point(11.93 / 2);
  for (std::size_t q = 0; q < 4; ++q) f[p.dofs[q]] += 2 * 105e3 * p.N[q];
  Eigen::SimplicialLDLT<SparseMatrix> lk(s.K);
  const Vector u = lk.solve(f);
  return {s.deck_point(0, 11.93 / 2).value(u), 0.5 * u.dot(f)};
}

void sensible(const Outcome& o, const study::Scenario& sc, const char* what) {
  const auto [w, e] = static_scale(sc);
  std::printf("extreme %-28s max deck disp %.3e m (static %.3e), max acc %.3e, energy max/static %.2f\n", what,
              o.max_disp, w, o.max_acc, o.e_max / e);
  REQUIRE(o.finite);
  // A linear model under moving constant loads stays within a few times its static response:
  // 3x static deflection and 10x static energy bound every case here with margin.
  REQUIRE(o.max_disp < 3 * w);
  REQUIRE(o.max_disp > 0.3 * w);
  REQUIRE(o.e_max < 10 * e);
}
}  // namespace

TEST_CASE("stability at the extremes: pad stiffness x1e4 and x1e-3") {
  for (double factor : {1e4, 1e-3}) {
    study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
    sc.track->pad.k *= factor;
    const Outcome o = run(sc, 40.0, 1e-3);
    sensible(o, sc, factor > 1 ? "pads x1e4" : "pads x1e-3");
  }
}

TEST_CASE("stability at the extremes: zero damping conserves energy after the train leaves") {
  study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
  for (auto* sd : {&sc.track->pad, &sc.track->ballast, &sc.track->shear, &sc.track->subgrade, &sc.track->subgrade_on_bridge})
    sd->c = 0.0;
  sc.bridge.damping.kind = model::DampingKind::none;
  const Outcome o = run(sc, 40.0, 1e-3, 1.0);
  sensible(o, sc, "zero damping");
  // Average acceleration conserves the energy of the undamped free system to round-off.
  REQUIRE((o.e_exit_max - o.e_exit_min) / o.e_exit_max < 1e-9);
}

TEST_CASE("stability at the extremes: 5 km/h and 600 km/h") {
  const study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
  sensible(run(sc, 5.0 / 3.6, 2e-3), sc, "5 km/h");
  sensible(run(sc, 600.0 / 3.6, 1e-3), sc, "600 km/h");
}

TEST_CASE("stability at the extremes: time steps x10 and /100 of the default", "[long]") {
  const study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
  sensible(run(sc, 50.0, 1e-2), sc, "dt = 10 ms");
  sensible(run(sc, 50.0, 1e-5, 0.02), sc, "dt = 10 us");
  // dt = 10 ms cannot carry the 60 Hz filter of the scenario: a clear error, not a wrong answer.
  REQUIRE_THROWS_WITH(vt::shipped("old-guadiana-sensitivity", {"analysis.dt=0.01"}),
                      Catch::Contains("high_hz in (0, fs/2 = 50) Hz"));
}

// The same extremes for modal superposition (issue #5): exact per-step modal equations, complex
// modes for the coupled track damping, modes up to 180 Hz (the `default` preset at f_c = 60 Hz)
// with the static correction; deflection at mid-span of span 1 against the static deflection.
TEST_CASE("stability at the extremes with modal superposition: pads and damping and speeds and steps", "[long]") {
  struct Case {
    const char* what;
    double pad_factor;
    bool undamped;
    double v, dt;
  };
  const Case cases[] = {{"modal pads x1e4", 1e4, false, 40.0, 1e-3},
                        {"modal pads x1e-3", 1e-3, false, 40.0, 1e-3},
                        {"modal zero damping", 1.0, true, 40.0, 1e-3},
                        {"modal 5 km/h", 1.0, false, 5 / 3.6, 5e-3},
                        {"modal 600 km/h", 1.0, false, 600 / 3.6, 1e-3},
                        {"modal dt x10 (10 ms)", 1.0, false, 40.0, 1e-2},
                        {"modal dt /100 (10 us)", 1.0, false, 40.0, 1e-5}};
  for (const Case& c : cases) {
    study::Scenario sc = vt::shipped("old-guadiana-sensitivity");
    sc.track->pad.k *= c.pad_factor;
    if (c.undamped) {
      for (auto* sd : {&sc.track->pad, &sc.track->ballast, &sc.track->shear, &sc.track->subgrade, &sc.track->subgrade_on_bridge})
        sd->c = 0.0;
      sc.bridge.damping.kind = model::DampingKind::none;
    }
    sc.trains = {load::regular_train("bogie", 2, 3.0, 210e3)};
    sc.stations = {{"mid", true, 0, 11.93 / 2, 0.0}};
    sc.settings.method = study::Method::modal;
    sc.settings.modal.max_frequency_hz = 180.0;
    sc.settings.dt = c.dt;
    sc.settings.filter.enabled = false;  // the 60 Hz filter needs dt < 8.3 ms
    sc.settings.free_vibration_s = 0.2;
    const study::PreparedModel m = study::prepare_model(sc);
    const study::RunResult r = study::simulate(m, sc.trains[0], c.v, sc.settings);
    const auto [w, e] = static_scale(sc);
    (void)e;
    const double d = r.stations[0].disp.cwiseAbs().maxCoeff();
    std::printf("extreme %-28s %ld modes, max deck disp %.3e m (static %.3e), max acc %.3e\n", c.what,
                static_cast<long>(m.modal->n_modes()), d, w, r.stations[0].acc.cwiseAbs().maxCoeff());
    REQUIRE((r.stations[0].disp.allFinite() && r.stations[0].acc.allFinite()));
    // Same bounds as the Newmark cases: within [0.3, 3] x the static deflection.
    REQUIRE(d < 3 * w);
    REQUIRE(d > 0.3 * w);
  }
}

// IDA at the extremes (issue #5), at rtol 1e-3 (the tradeoff's middle rung): soft pads on the Old Guadiana model
// with 3 m of approach and exit track; zero damping, 20 and 600 km/h on the bare 15 m HSLM span.
TEST_CASE("stability at the extremes with IDA: pads and zero damping and slow and fast axles", "[long]") {
  struct Case {
    const char* what;
    bool track;
    double pad_factor;
    bool undamped;
    double v;
  };
  // Pads x1e4 are left out of the suite: stable (1.966 mm against 1.990 mm static) but 90 570
  // internal steps and 75 s for one second of simulation — the rail-on-pad modes move to tens of
  // kHz and the error test follows them (docs/accuracy.md).
  const Case cases[] = {{"ida pads x1e-3", true, 1e-3, false, 40.0},
                        {"ida zero damping", false, 1.0, true, 40.0},
                        {"ida 20 km/h", false, 1.0, false, 20 / 3.6},
                        {"ida 600 km/h", false, 1.0, false, 600 / 3.6}};
  for (const Case& c : cases) {
    study::Scenario sc = c.track ? vt::shipped("old-guadiana-sensitivity", {"track.approach_length=3.0", "track.exit_length=3.0"})
                                 : vt::shipped("hslm-simply-supported");
    if (c.track) sc.track->pad.k *= c.pad_factor;
    if (c.undamped) sc.bridge.damping.kind = model::DampingKind::none;
    const double L = sc.bridge.spans[0].length;
    sc.trains = {load::regular_train("bogie", 2, 3.0, 210e3)};
    sc.stations = {{"mid", true, 0, L / 2, 0.0}};
    sc.settings.method = study::Method::ida;
    sc.settings.ida.rtol = 1e-3;
    sc.settings.ida.atol_disp = 1e-6;
    sc.settings.ida.atol_vel = 1e-4;
    sc.settings.dt = 1e-3;
    sc.settings.filter.enabled = false;
    sc.settings.load_factor = 1.0;
    sc.settings.free_vibration_s = 0.2;
    const study::PreparedModel m = study::prepare_model(sc);
    const study::RunResult r = study::simulate(m, sc.trains[0], c.v, sc.settings);
    // Static deflection at mid-span with both axles there.
    Vector f = Vector::Zero(m.structure.n_dofs);
    const auto p = c.track ? m.structure.rail_point(m.structure.span_start[0] + L / 2) : m.structure.deck_point(0, L / 2);
    for (std::size_t q = 0; q < 4; ++q)
      if (p.dofs[q] >= 0) f[p.dofs[q]] += 2 * 210e3 * p.N[q];
    Eigen::SimplicialLDLT<SparseMatrix> lk(m.structure.K);
    const double w = m.structure.deck_point(0, L / 2).value(lk.solve(f));
    const double d = r.stations[0].disp.cwiseAbs().maxCoeff();
    std::printf("extreme %-28s max deck disp %.3e m (static %.3e); %s\n", c.what, d, w, r.summary.stop_reason.c_str());
    REQUIRE((r.stations[0].disp.allFinite() && r.stations[0].acc.allFinite()));
    REQUIRE(d < 3 * w);
    REQUIRE(d > 0.3 * w);
  }
}
