// Forced vibration of the model: direct-solve FRFs against the modal sum, and a simulated
// shaker test whose stepped-sine processing recovers the model's modes.
#include <catch2/catch.hpp>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/forced.hpp"

using namespace viaduct;
using namespace viaduct::study;

namespace {
model::Structure span(double zeta) {
  model::BridgeParams b;
  b.spans = {{12.0, 5e9, 10000.0}};  // f1 = π/(2L²)·√(EI/m) = 7.71 Hz
  b.element_size = 1.0;
  b.damping.kind = model::DampingKind::modal;
  b.damping.ratio = zeta;
  return model::build_structure(b, std::nullopt);
}

ForcedSetup setup_on(const model::Structure& s) {
  ForcedSetup f;
  f.force_x_m = 4.3;  // between nodes: the force is shared by the element's shape functions
  f.responses = {deck_station_at(s, "q1", 3.0), deck_station_at(s, "mid", 6.0), deck_station_at(s, "q3", 9.5)};
  return f;
}
}  // namespace

TEST_CASE("Model FRF by direct solve equals the modal sum of all modes with modal damping") {
  const model::Structure s = span(0.02);
  const ForcedSetup setup = setup_on(s);
  const Vector f = Vector::LinSpaced(60, 1.0, 80.0);
  const ident::Frf frf = model_frf(s, setup, f, 2);
  REQUIRE(frf.h.rows() == 60);
  REQUIRE(frf.h.cols() == 3);
  const model::Modes m = model::compute_modes(s, 0);
  const auto stations = resolve_stations(s, setup.responses);
  const model::PointCoupling at = model::point_on(s.deck_elements, setup.force_x_m, "deck");
  double worst = 0;
  for (Index k = 0; k < f.size(); ++k) {
    const double w = 2 * M_PI * f[k];
    for (Index c = 0; c < 3; ++c) {
      std::complex<double> h = 0;
      for (Index r = 0; r < m.frequency_hz.size(); ++r) {
        const double wr = 2 * M_PI * m.frequency_hz[r];
        const Vector phi = m.shape.col(r);
        h += stations[static_cast<std::size_t>(c)].deck.value(phi) * at.value(phi) /
             std::complex<double>(wr * wr - w * w, 2 * 0.02 * wr * w);
      }
      h *= -w * w;  // accelerance
      worst = std::max(worst, std::abs(frf.h(k, c) - h) / std::abs(h));
    }
  }
  // Same linear algebra two ways (sparse LU against the eigenvector sum): rounding only.
  CHECK(worst < 1e-8);
  // Reciprocity: the response at q1 to a force at 4.3 m = the response at 4.3 m to a force at q1.
  ForcedSetup swapped;
  swapped.force_x_m = 3.0;
  swapped.responses = {deck_station_at(s, "p", 4.3)};
  const ident::Frf back = model_frf(s, swapped, f, 1);
  CHECK((back.h.col(0) - frf.h.col(0)).norm() < 1e-10 * frf.h.col(0).norm());
}

TEST_CASE("Stepped-sine processing of a simulated shaker test recovers the bridge's first mode") {
  const double zeta = 0.02;
  const model::Structure s = span(zeta);
  const ForcedSetup setup = setup_on(s);
  const double f1 = model::compute_modes(s, 1).frequency_hz[0];
  ShakerTest t;
  t.steps = ident::regular_schedule(0.85 * f1, 1.15 * f1, 31, 15.0);
  t.fs_hz = 100.0;
  t.amplitude_N = 5e3;
  t.noise_snr_db = 40.0;
  const ShakerRecord r = simulate_shaker_test(s, setup, t);
  REQUIRE(r.force.size() == 465 * 100 + 1);
  ident::SteppedSineOptions so;
  so.settle_cycles = 60;  // 2 % damping: e^{-2π·0.02·60} = 5e-4 of the transient left
  const auto pts = ident::stepped_sine(r.force, r.responses, r.fs_hz, 0.0, t.steps, so);
  REQUIRE(pts.size() == 31);
  ident::Frf frf;
  frf.frequency_hz.resize(31);
  frf.h.resize(31, 3);
  for (Index k = 0; k < 31; ++k) {
    frf.frequency_hz[k] = pts[static_cast<std::size_t>(k)].frequency_hz;
    frf.h.row(k) = pts[static_cast<std::size_t>(k)].h.transpose();
  }
  frf.responses = {"q1", "mid", "q3"};
  frf.quantity.assign(3, ident::FrfQuantity::accelerance);
  // Point by point against the direct solve: noise (40 dB over ~1000 samples per fit) and the
  // Newmark period error (< 1e-4 by the automatic substeps) leave well under 1 %.
  const ident::Frf direct = model_frf(s, setup, frf.frequency_hz, 1);
  for (Index k = 0; k < 31; ++k)
    for (Index c = 0; c < 3; ++c) CHECK(std::abs(frf.h(k, c) - direct.h(k, c)) < 0.01 * std::abs(direct.h(k, c)));
  ident::LscfOptions lo;
  lo.max_order = 8;
  const auto fit = ident::lscf(frf, lo);
  REQUIRE(fit.modes.size() == 1);
  // Issue #4's targets for identification: frequency < 0.1 %, damping < 5 % relative.
  CHECK(std::abs(fit.modes[0].frequency_hz / f1 - 1) < 1e-3);
  CHECK(std::abs(fit.modes[0].damping_ratio / zeta - 1) < 0.05);
  // First bending mode: all three sensors in phase, the middle one largest.
  CHECK(fit.modes[0].shape[1].real() == Approx(1.0));
  CHECK(fit.modes[0].shape[0].real() > 0.5);
  CHECK(fit.modes[0].shape[2].real() > 0.5);
}

TEST_CASE("Forced-vibration inputs are checked") {
  const model::Structure s = span(0.02);
  ForcedSetup setup = setup_on(s);
  CHECK_THROWS_AS(deck_station_at(s, "off", 12.5), InputError);
  setup.force_x_m = -1.0;
  CHECK_THROWS_AS(model_frf(s, setup, Vector::LinSpaced(5, 1.0, 5.0), 1), InputError);
  setup = setup_on(s);
  CHECK_THROWS_AS(model_frf(s, setup, Vector::LinSpaced(5, 0.0, 5.0), 1), InputError);   // f = 0
  CHECK_THROWS_AS(model_frf(s, setup, Vector::LinSpaced(5, 5.0, 1.0), 1), InputError);   // descending
  ShakerTest t;
  t.steps = {{0.0, 5.0, 8.0}, {6.0, 10.0, 9.0}};  // gap
  CHECK_THROWS_WITH(simulate_shaker_test(s, setup, t), Catch::Contains("contiguous"));
  t.steps = {{0.0, 5.0, 80.0}};
  t.fs_hz = 100.0;
  CHECK_THROWS_WITH(simulate_shaker_test(s, setup, t), Catch::Contains("Nyquist"));
  t.kind = ShakerTest::Kind::swept;
  t.sweep_f_start_hz = 10.0;
  t.sweep_f_end_hz = 5.0;
  t.sweep_s = 10.0;
  CHECK_THROWS_AS(simulate_shaker_test(s, setup, t), InputError);
}
