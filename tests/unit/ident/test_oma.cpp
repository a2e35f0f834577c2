// Output-only identification (SSI-COV, stabilization, clustering, jackknife, FDD, tracking) on
// records of known modes from the independent generator of ambient.hpp (issue #41).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "ambient.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/ident/oma.hpp"

using namespace viaduct;
using Catch::Matchers::Contains;

namespace {

ident::ComplexVector true_shape(const vt::AmbientMode& m) {
  ident::ComplexVector phi(static_cast<Index>(m.shape.size()));
  for (std::size_t c = 0; c < m.shape.size(); ++c) phi[static_cast<Index>(c)] = m.shape[c];
  return phi;
}

// The identified mode nearest to `m` in frequency (nullptr when none within 5 %).
const ident::OmaMode* nearest(const std::vector<ident::OmaMode>& modes, const vt::AmbientMode& m) {
  const ident::OmaMode* best = nullptr;
  for (const auto& e : modes)
    if (std::abs(e.frequency_hz - m.f_hz) < 0.05 * m.f_hz && (!best || std::abs(e.frequency_hz - m.f_hz) < std::abs(best->frequency_hz - m.f_hz)))
      best = &e;
  return best;
}

// Issue #41's targets, checked mode by mode; returns the number of modes reported that match none.
std::size_t check_targets(const std::vector<ident::OmaMode>& found, const std::vector<vt::AmbientMode>& truth, bool with_std) {
  std::size_t matched = 0;
  for (const auto& m : truth) {
    INFO("true mode " << m.f_hz << " Hz, zeta " << m.zeta);
    const ident::OmaMode* e = nearest(found, m);
    REQUIRE(e);
    ++matched;
    CHECK(std::abs(e->frequency_hz - m.f_hz) / m.f_hz < 0.005);   // issue #41: 0.5 % in f
    CHECK(std::abs(e->damping_ratio - m.zeta) / m.zeta < 0.30);   // 30 % in ζ
    CHECK(ident::mac(e->shape, true_shape(m))(0, 0) >= 0.9);      // MAC >= 0.9
    if (with_std) {
      // The jackknife standard deviations cover the errors (4σ: 15 draws per run, none should
      // exceed it) without being so wide that covering means nothing (0.2 % of f, half of ζ).
      CHECK(std::abs(e->frequency_hz - m.f_hz) <= 4.0 * e->frequency_std_hz);
      CHECK(std::abs(e->damping_ratio - m.zeta) <= 4.0 * e->damping_std);
      CHECK(e->frequency_std_hz < 0.002 * m.f_hz);
      CHECK(e->damping_std < 0.5 * m.zeta);
    }
  }
  return found.size() - matched;
}

}  // namespace

TEST_CASE("SSI-COV finds five known modes, a pair 2 % apart among them, in 30 minutes of ambient vibration of 6 channels", "[long]") {
  const auto modes = vt::ambient_modes();
  for (unsigned seed : {11u, 12u, 13u}) {
    INFO("seed " << seed);
    const Matrix y = vt::ambient_record(modes, 100.0, 180000, 0.05, seed);
    ident::SsiOptions o;
    o.f_min_hz = 1.0;
    o.f_max_hz = 20.0;
    const ident::SsiResult r = ident::ssi_cov(y, 100.0, o);
    CHECK(check_targets(r.modes, modes, true) <= 2);  // at most 2 spurious modes
    CHECK(r.orders.size() == 30);
  }
}

TEST_CASE("SSI-COV on 5 minutes of 3 channels: three modes, the stabilization diagram's statuses and clusters") {
  std::vector<vt::AmbientMode> modes = {{1.5, 0.01, {1.0, 0.7, 0.2}}, {3.2, 0.02, {0.5, -0.6, 1.0}}, {6.1, 0.015, {1.0, -1.0, 0.4}}};
  const Matrix y = vt::ambient_record(modes, 50.0, 15000, 0.05, 3);
  ident::SsiOptions o;
  o.f_min_hz = 1.0;
  o.max_order = 30;
  const ident::SsiResult r = ident::ssi_cov(y, 50.0, o);
  CHECK(check_targets(r.modes, modes, false) == 0);
  // Each mode's cluster holds its poles, one per order, all stable in frequency and shape and
  // within the cluster distance (2 %) of its frequency.
  for (std::size_t m = 0; m < r.modes.size(); ++m) {
    std::size_t n = 0;
    for (const auto& p : r.poles)
      if (p.cluster == static_cast<int>(m)) {
        ++n;
        CHECK(p.clusterable());
        CHECK(std::abs(p.frequency_hz - r.modes[m].frequency_hz) < o.cluster_distance * r.modes[m].frequency_hz);
      }
    CHECK(static_cast<Index>(n) == r.modes[m].n_poles);
    CHECK(n >= 0.3 * r.orders.size());
  }
  // Below the band nothing is physical; the record's sensor noise gives poles that are not stable.
  for (const auto& p : r.poles)
    if (p.frequency_hz < 1.0) CHECK_FALSE(p.physical);
  // Fewer references than channels (the first two): the same modes.
  o.references = {0, 1};
  CHECK(check_targets(ident::ssi_cov(y, 50.0, o).modes, modes, false) == 0);
}

TEST_CASE("SSI-COV on a free decay after a passage: correlations as sums, the start found") {
  std::vector<vt::AmbientMode> modes = {{2.5, 0.02, {1.0, 0.6, -0.3}}, {5.0, 0.01, {0.3, -1.0, 0.8}}, {9.0, 0.03, {1.0, 1.0, 1.0}}};
  const double fs = 100.0;
  const Matrix decay = vt::free_decay_record(modes, fs, 3000, 0.02, 5);
  // The passage before it: 10 s of stronger random forcing, then the decay.
  Matrix passage = 3.0 * vt::ambient_record(modes, fs, 1000, 0.0, 9);
  passage *= decay.row(0).norm() / passage.bottomRows(1).norm();
  Matrix y(passage.rows() + decay.rows(), 3);
  y << passage, decay;
  ident::OmaPlan plan;
  plan.ssi.free_decay = true;
  plan.ssi.f_min_hz = 1.0;
  plan.ssi.max_order = 30;
  const auto w = ident::identify_output_only(y, fs, 100.0, {"a", "b", "c"}, plan);
  REQUIRE(w.size() == 1);
  REQUIRE(w[0].error.empty());
  // The decay is found after the passage's end (10 s into the record, which starts at 100 s),
  // within the running rms window (2 periods of 1 Hz) past it.
  CHECK(w[0].t_start_s >= 110.0);
  CHECK(w[0].t_start_s <= 112.5);
  for (const auto& m : modes) {
    INFO("mode " << m.f_hz);
    const ident::OmaMode* e = nearest(w[0].ssi.modes, m);
    REQUIRE(e);
    CHECK(std::abs(e->frequency_hz - m.f_hz) / m.f_hz < 0.002);
    CHECK(std::abs(e->damping_ratio - m.zeta) / m.zeta < 0.10);
    CHECK(ident::mac(e->shape, true_shape(m))(0, 0) > 0.99);
    CHECK(std::isnan(e->frequency_std_hz));  // no jackknife on a decay
  }
}

TEST_CASE("shape quality: MPC and MPD of real, rotated and circular shapes") {
  ident::ComplexVector real(3);
  real << 1.0, -0.5, 0.25;
  const auto q = ident::shape_quality(real * std::polar(2.0, 0.7));
  CHECK(q.mpc == Approx(1.0).margin(1e-12));
  CHECK(q.mpd_deg == Approx(0.0).margin(1e-9));
  CHECK(q.normalised[0].real() == Approx(1.0));
  CHECK(q.normalised[1].real() == Approx(-0.5));
  CHECK(std::abs(q.normalised[2].imag()) < 1e-12);
  ident::ComplexVector circle(2);
  circle << 1.0, std::complex<double>(0.0, 1.0);
  const auto c = ident::shape_quality(circle);
  CHECK(c.mpc == Approx(0.0).margin(1e-12));
  CHECK(c.mpd_deg == Approx(45.0));
}

TEST_CASE("FDD: peaks of the first singular value at the modes, EFDD damping of a separated mode") {
  std::vector<vt::AmbientMode> modes = {{2.0, 0.01, {1.0, 0.7, 0.2}}, {5.0, 0.02, {0.5, -0.6, 1.0}}};
  const Matrix y = vt::ambient_record(modes, 50.0, 90000, 0.05, 4);
  ident::FddOptions o;
  o.f_min_hz = 0.5;
  const ident::FddResult r = ident::fdd(y, 50.0, o);
  CHECK(r.singular_values.cols() == 3);
  for (Index k = 0; k < r.singular_values.rows(); ++k) CHECK(r.singular_values(k, 0) >= r.singular_values(k, 1));
  for (const auto& m : modes) {
    INFO("mode " << m.f_hz);
    const ident::FddMode* e = nullptr;
    for (const auto& f : r.modes)
      if (std::abs(f.frequency_hz - m.f_hz) < 0.02 * m.f_hz) e = &f;
    REQUIRE(e);
    const double line = 50.0 / static_cast<double>(r.nperseg);
    CHECK(std::abs(e->frequency_hz - m.f_hz) < line);  // within one line
    CHECK(ident::mac(e->shape, true_shape(m))(0, 0) > 0.98);
    // EFDD: issue #41's targets for SSI (0.5 % in f, 30 % in ζ) hold for a separated mode.
    CHECK(std::abs(e->efdd_frequency_hz - m.f_hz) < 0.005 * m.f_hz);
    CHECK(std::abs(e->efdd_damping_ratio - m.zeta) / m.zeta < 0.30);
  }
}

TEST_CASE("output-only identification refuses what it cannot identify, naming the channel") {
  const auto modes = vt::ambient_modes();
  Matrix y = vt::ambient_record(modes, 100.0, 30000, 0.05, 2);
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f"};
  ident::OmaPlan plan;
  plan.ssi.f_min_hz = 1.0;
  plan.ssi.max_order = 20;
  plan.min_periods = 100.0;
  auto error_of = [&](const Matrix& m, const ident::OmaPlan& p) {
    const auto w = ident::identify_output_only(m, 100.0, 0.0, std::vector<std::string>(names.begin(), names.begin() + m.cols()), p);
    REQUIRE(w.size() == 1);
    return w[0].error;
  };
  CHECK_THAT(error_of(y.leftCols(1), plan), Contains("at least 2 channels"));
  Matrix dead = y;
  dead.col(2).setConstant(0.1);
  CHECK_THROWS_WITH(ident::identify_output_only(dead, 100.0, 0.0, names, plan), Contains("channel 'c' is constant"));
  Matrix clipped = y;
  const double top = 0.3 * clipped.col(4).maxCoeff();
  clipped.col(4) = clipped.col(4).cwiseMin(top);
  CHECK_THROWS_WITH(ident::identify_output_only(clipped, 100.0, 0.0, names, plan), Contains("channel 'e' is clipped"));
  Matrix gap = y;
  gap(500, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(ident::identify_output_only(gap, 100.0, 0.0, names, plan), Contains("channel 'b' holds NaN"));
  ident::OmaPlan high = plan;
  high.ssi.f_max_hz = 60.0;
  CHECK_THAT(error_of(y, high), Contains("above the Nyquist frequency 50 Hz"));
  ident::OmaPlan low = plan;
  low.ssi.f_min_hz = 0.05;  // 300 s hold 15 periods of 0.05 Hz
  CHECK_THAT(error_of(y, low), Contains("periods of the band's lowest frequency"));
  // A mode at the band's edge is flagged.
  ident::OmaPlan edge = plan;
  edge.ssi.f_max_hz = 11.1;
  const auto w = ident::identify_output_only(y, 100.0, 0.0, names, edge);
  REQUIRE(w[0].error.empty());
  const ident::OmaMode* top_mode = nearest(w[0].ssi.modes, modes.back());
  REQUIRE(top_mode);
  CHECK_THAT(top_mode->note, Contains("band's edge"));
  ident::OmaPlan tiny = plan;
  tiny.window_s = 0.001;  // rounds to no sample at 100 Hz: refused, not an endless loop
  CHECK_THROWS_WITH(ident::identify_output_only(y, 100.0, 0.0, names, tiny), Contains("at least 64"));
  ident::OmaPlan odd = plan;
  odd.ssi.max_order = 21;
  CHECK_THAT(error_of(y, odd), Contains("max_order"));
}

TEST_CASE("windows of a record, decimated, and modes tracked across them") {
  std::vector<vt::AmbientMode> modes = {{1.5, 0.01, {1.0, 0.7, 0.2}}, {3.2, 0.02, {0.5, -0.6, 1.0}}};
  const Matrix y = vt::ambient_record(modes, 200.0, 200 * 600, 0.05, 8);
  ident::OmaPlan plan;
  plan.ssi.f_min_hz = 1.0;
  plan.ssi.f_max_hz = 10.0;
  plan.ssi.max_order = 20;
  plan.decimate = 4;
  plan.window_s = 200.0;
  const auto w = ident::identify_output_only(y, 200.0, 50.0, {"a", "b", "c"}, plan);
  REQUIRE(w.size() == 3);
  CHECK(w[1].t_start_s == Approx(250.0));
  CHECK(w[2].t_end_s == Approx(50.0 + 600.0 - 1.0 / 50.0));
  std::vector<std::vector<ident::OmaMode>> found;
  for (const auto& x : w) {
    REQUIRE(x.error.empty());
    CHECK(check_targets(x.ssi.modes, modes, false) == 0);
    found.push_back(x.ssi.modes);
  }
  // Decimating by 4 passes up to 0.8 of the new Nyquist frequency (20 Hz): a band beyond is refused.
  ident::OmaPlan wide = plan;
  wide.ssi.f_max_hz = 22.0;
  CHECK_THROWS_WITH(ident::identify_output_only(y, 200.0, 50.0, {"a", "b", "c"}, wide), Contains("passband edge"));
  const auto tracks = ident::track_modes(found);
  for (std::size_t k = 0; k < found.size(); ++k)
    for (std::size_t m = 0; m < found[k].size(); ++m) CHECK(tracks[k][m] == static_cast<int>(m));
}

TEST_CASE("mode tracking: drift followed, a new mode starts a track, a lost one leaves a gap, shapes keep a crossing apart") {
  auto mode = [](double f, std::vector<double> s) {
    ident::OmaMode m;
    m.frequency_hz = f;
    m.shape = ident::ComplexVector(static_cast<Index>(s.size()));
    for (std::size_t k = 0; k < s.size(); ++k) m.shape[static_cast<Index>(k)] = s[k];
    return m;
  };
  std::vector<std::vector<ident::OmaMode>> w;
  w.push_back({mode(2.00, {1, 1}), mode(2.10, {1, -1})});
  w.push_back({mode(2.04, {1, 1}), mode(2.06, {1, -1})});              // drifting towards each other
  w.push_back({mode(2.09, {1, -1}), mode(2.11, {1, 1})});              // crossed: the shapes decide
  w.push_back({mode(2.12, {1, 1.05}), mode(5.0, {1, 0})});             // one lost, one new
  const auto t = ident::track_modes(w);
  CHECK(t[0] == std::vector<int>{0, 1});
  CHECK(t[1] == std::vector<int>{0, 1});
  CHECK(t[2] == std::vector<int>{1, 0});
  CHECK(t[3] == std::vector<int>{0, 2});
  ident::TrackingOptions bad;
  bad.min_mac = 1.5;
  CHECK_THROWS_AS(ident::track_modes(w, bad), InputError);
}

TEST_CASE("a burst in an ambient window is said, stationary noise and short windows are not judged") {
  // Two channels of unit white noise (different units: 1 and 1e-3), 2000 samples at 100 Hz.
  Matrix y(2000, 2);
  unsigned s = 7;
  auto noise = [&s]() {  // uniform in [-1, 1): a small LCG, no library generator's version to depend on
    s = s * 1664525u + 1013904223u;
    return static_cast<double>(s >> 8) / 8388608.0 - 1.0;
  };
  for (Index i = 0; i < y.rows(); ++i) y(i, 0) = noise(), y(i, 1) = 1e-3 * noise();
  CHECK(ident::stationarity_warning(y, 100.0, 0.0).empty());
  // A passage-like burst 20 times the noise over 2 s (t = 8 to 10 s) in both channels.
  Matrix b = y;
  for (Index i = 800; i < 1000; ++i) b.row(i) *= 20.0;
  const std::string w = ident::stationarity_warning(b, 100.0, 5.0);
  CHECK_THAT(w, Contains("not stationary: its loudest tenth (13 to 15 s) has"));
  CHECK_THAT(w, Contains("a train passage or another burst"));
  // 9 times in one channel only: averaged over the two, under the threshold of 10.
  Matrix c = y;
  for (Index i = 800; i < 1000; ++i) c(i, 0) *= 9.0;
  CHECK(ident::stationarity_warning(c, 100.0, 0.0).empty());
  // Fewer than 64 samples a tenth: not judged.
  CHECK(ident::stationarity_warning(b.topRows(600), 100.0, 0.0).empty());
}
