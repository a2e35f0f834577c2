// The FRF of a test from its records (ident::estimate_frf, io::frf_inputs, io::label_frf) and the
// whole modal fit (ident::modal_fit): what viaduct frf RECORD and viaduct modal-fit compute.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "synthetic.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/ident/frf_estimate.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/io/frf.hpp"

using namespace viaduct;
using namespace viaduct::ident;

namespace {
// A known FRF: one mode at 5 Hz, 2 % damping (receptance, unit modal mass).
Complex h_true(double f) {
  const double w = 2 * M_PI * f, wn = 2 * M_PI * 5.0;
  return 1.0 / Complex(wn * wn - w * w, 2 * 0.02 * wn * w);
}

// A phase-continuous stepped sine through `sched` and the steady-state response to it: every
// dwell's phasor ratio is h_true(f) exactly (a sin(θ) drive has phasor −i, |H| sin(θ + arg H)
// has phasor −i·H).
void stepped_record(const std::vector<SineStep>& sched, double fs, Vector& force, Matrix& resp) {
  const Index n = static_cast<Index>(sched.back().t_end_s * fs);
  force.resize(n);
  resp.resize(n, 1);
  double phase = 0.0;
  std::size_t s = 0;
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / fs;
    while (s + 1 < sched.size() && t >= sched[s].t_end_s) ++s;
    const Complex H = h_true(sched[s].frequency_hz);
    force[k] = std::sin(phase);
    resp(k, 0) = std::abs(H) * std::sin(phase + std::arg(H));
    phase += 2 * M_PI * sched[s].frequency_hz / fs;
  }
}
}  // namespace

TEST_CASE("estimate_frf: a stepped sine given or detected gives one point per dwell, sorted by frequency") {
  // Dwells going down in frequency: the FRF's rows come out ascending, `order` maps them back.
  std::vector<SineStep> sched;
  const double freqs[] = {6.0, 5.5, 5.0, 4.5, 4.0};
  for (int k = 0; k < 5; ++k) sched.push_back({8.0 * k, 8.0 * (k + 1), freqs[k]});
  Vector force;
  Matrix resp;
  stepped_record(sched, 200.0, force, resp);
  FrfEstimateOptions o;
  o.method = FrfMethod::stepped;
  o.steps = sched;
  o.stepped.settle_cycles = 5;  // the record is steady from the start
  const FrfEstimate e = estimate_frf(force, resp, 200.0, 0.0, o);
  REQUIRE_FALSE(e.steps_detected);
  REQUIRE(e.points.size() == 5);
  REQUIRE(e.frf.frequency_hz.size() == 5);
  for (Index j = 0; j < 5; ++j) {
    const double f = e.frf.frequency_hz[j];
    if (j > 0) CHECK(f > e.frf.frequency_hz[j - 1]);
    CHECK(f == Approx(freqs[e.order[static_cast<std::size_t>(j)]]).epsilon(1e-6));
    // Steady state and an exact sine: the fit's only error is rounding (1e-6 leaves room for the
    // frequency refinement's tolerance).
    CHECK(std::abs(e.frf.h(j, 0) / h_true(f) - 1.0) < 1e-6);
  }
  CHECK(e.worst_distortion < 1e-6);
  // Without a schedule the dwells are detected from the force: the same points.
  o.steps.clear();
  const FrfEstimate d = estimate_frf(force, resp, 200.0, 0.0, o);
  REQUIRE(d.steps_detected);
  REQUIRE(d.frf.frequency_hz.size() == 5);
  for (Index j = 0; j < 5; ++j) CHECK(std::abs(d.frf.h(j, 0) / e.frf.h(j, 0) - 1.0) < 1e-4);
}

TEST_CASE("estimate_frf: Welch keeps the lines inside the band, swept needs its band, methods are named") {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  const Index n = 8192;
  Vector force(n);
  for (Index k = 0; k < n; ++k) force[k] = g(rng);
  const Matrix resp = 2.5 * force;  // H = 2.5 at every frequency, coherence 1
  FrfEstimateOptions o;
  o.welch.nperseg = 512;
  o.f_min_hz = 5.0;
  o.f_max_hz = 20.0;
  const FrfEstimate e = estimate_frf(force, resp, 100.0, 0.0, o);
  // Lines every 100/512 Hz: those in [5, 20] Hz.
  CHECK(e.frf.frequency_hz.size() == static_cast<Index>(std::floor(20.0 * 5.12) - std::ceil(5.0 * 5.12) + 1));
  CHECK(e.frf.frequency_hz.minCoeff() >= 5.0);
  CHECK(e.frf.frequency_hz.maxCoeff() <= 20.0);
  CHECK((e.frf.h.array() - Complex(2.5, 0.0)).abs().maxCoeff() < 1e-9);
  CHECK(e.frf.coherence.minCoeff() > 1.0 - 1e-9);
  CHECK(e.n_segments > 1);
  o.f_min_hz = 30.0;
  o.f_max_hz = 30.1;
  CHECK_THROWS_WITH(estimate_frf(force, resp, 100.0, 0.0, o), Catch::Contains("fewer than 2 Welch lines"));
  o.method = FrfMethod::swept;
  o.f_max_hz.reset();
  CHECK_THROWS_WITH(estimate_frf(force, resp, 100.0, 0.0, o), Catch::Contains("needs --f-min and --f-max"));
  CHECK(frf_method("stepped", "--method") == FrfMethod::stepped);
  CHECK_THROWS_WITH(frf_method("sine", "--method"), Catch::Contains("--method must be welch, stepped or swept, got 'sine'"));
}

TEST_CASE("frf_inputs picks the force and response channels of records, label_frf names the FRF after them") {
  io::Record r;
  r.fs_hz = 100.0;
  r.channels = {"force_kN", "S1_mid_acc_mps2", "S2_disp_m", "supply_V"};
  r.units = {"kN", "mps2", "m", "V"};
  r.data = Matrix::Random(50, 4);
  const io::FrfInputs in = io::frf_inputs(r, "r.csv", nullptr, "force", {});
  // Default responses: every m, mps and mps2 channel (not the voltage).
  REQUIRE(in.response_channels == std::vector<std::string>{"S1_mid_acc_mps2", "S2_disp_m"});
  CHECK(in.force_channel == "force_kN");
  CHECK(in.force == r.data.col(0));
  CHECK(in.responses.col(1) == r.data.col(2));
  Frf frf;
  io::label_frf(frf, in);
  CHECK(frf.responses == std::vector<std::string>{"S1_mid", "S2"});
  CHECK(frf.quantity == std::vector<FrfQuantity>{FrfQuantity::accelerance, FrfQuantity::receptance});
  CHECK(frf.force_unit == "kN");
  CHECK(io::frf_inputs(r, "r.csv", nullptr, "force_kN", {"S2_disp"}).response_channels == std::vector<std::string>{"S2_disp_m"});
  CHECK_THROWS_WITH(io::frf_inputs(r, "r.csv", nullptr, "S2_disp", {}), Catch::Contains("must be in N or kN"));
  CHECK_THROWS_WITH(io::frf_inputs(r, "r.csv", nullptr, "force", {"nope"}), Catch::Contains("no channel 'nope'"));
  // A separate force record must cover the same samples at the same rate.
  io::Record f = r;
  f.fs_hz = 200.0;
  CHECK_THROWS_WITH(io::frf_inputs(r, "r.csv", &f, "force", {}), Catch::Contains("mismatched sampling rates"));
  f.fs_hz = 100.0;
  f.data = Matrix::Random(49, 4);
  CHECK_THROWS_WITH(io::frf_inputs(r, "r.csv", &f, "force", {}), Catch::Contains("do not cover the same samples"));
  io::Record only_force = r;
  only_force.channels = {"force_N"};
  only_force.units = {"N"};
  only_force.data = Matrix::Random(50, 1);
  CHECK_THROWS_WITH(io::frf_inputs(only_force, "f.csv", nullptr, "force", {}), Catch::Contains("no response channel (m, mps or mps2) in f.csv"));
}

TEST_CASE("modal_fit: peak picking, circle fit and LSCF agree on a clean single mode") {
  vt::ModalSystem m;
  m.f_hz = {5.0};
  m.zeta = {0.02};
  m.shapes = {{1.0, 0.5}};
  const Frf frf = m.frf(vt::grid(3.0, 7.0, 801), FrfQuantity::accelerance, -1.0);
  ModalFitOptions o;
  o.max_order = 12;
  const ModalFitResult r = modal_fit(frf, o);
  REQUIRE(r.peak_picking.size() == 1);
  REQUIRE(r.circle_fit.size() == 1);
  REQUIRE(r.lscf.modes.size() == 1);
  CHECK(r.warnings.empty());
  // Noise-free: the circle fit and the refined LSCF are exact to their tolerances; peak picking
  // is limited by the 5 mHz line spacing (bias up to half a line, 0.05 %).
  CHECK(r.circle_fit[0].frequency_hz == Approx(5.0).epsilon(1e-4));
  CHECK(r.lscf.modes[0].frequency_hz == Approx(5.0).epsilon(1e-4));
  CHECK(r.lscf.modes[0].damping_ratio == Approx(0.02).epsilon(1e-3));
  CHECK(r.peak_picking[0].frequency_hz == Approx(5.0).epsilon(5e-4));
  // Without refinement the modes are the stabilization diagram's.
  o.refine = false;
  const ModalFitResult d = modal_fit(frf, o);
  REQUIRE(d.lscf.modes.size() == 1);
  CHECK(d.lscf.modes[0].frequency_hz == r.lscf.diagram_modes[0].frequency_hz);
  // The band limits every method.
  o.f_min_hz = 6.0;
  const ModalFitResult b = modal_fit(frf, o);
  CHECK(b.peak_picking.empty());
  CHECK(b.lscf.modes.empty());
}
