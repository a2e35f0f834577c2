// Recorded passages over the model's envelope (issue #19 part 5, study::run_passages as `viaduct
// passages` runs it): twenty simulated passages of three trains at scattered speeds, each channel
// (acceleration, deflection, strain at mid-span) with white noise of 5 % of its RMS and a quiet
// lead. Made with the same model, every passage must land on the model within the noise: its
// speed identified within 0.5 % and its stated uncertainty, its peak within the band the command
// states, the noise it reports near the noise put in; and a passage 20 % stronger than the model
// must not.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>

#include "helpers.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/study/passages.hpp"

using namespace viaduct;

namespace {

struct Setup {
  study::Scenario sc;
  study::RunSettings rs;
  study::PreparedModel pm;
  std::vector<load::Train> trains;
};

Setup setup() {
  Setup s{vt::shipped("hslm-simply-supported", {"stations[0].fibre_m=0.6", "analysis.free_vibration_s=0.5", "analysis.method=\"modal\""}),
          {}, {}, {}};
  s.rs = s.sc.settings;
  s.rs.filter.enabled = false;
  s.pm = study::prepare_model(model::build_structure(s.sc.bridge, s.sc.track), s.sc.stations, s.rs, true, true);
  s.trains = {load::hslm_a("HSLM-A1", load::hslm_a_row(1)), load::hslm_a("HSLM-A7", load::hslm_a_row(7)),
              io::read_train_file(vt::source("data/trains/talgo-altaria.csv"))};
  return s;
}

constexpr study::ResponseKind kinds[] = {study::ResponseKind::acceleration, study::ResponseKind::deflection,
                                         study::ResponseKind::strain};

// A passage of train `t` at `v`: 1 s of quiet logging, then the model's response, 5 % noise
// (of each channel's RMS); `gain` scales the response (a bridge stronger than its model). The
// noise's RMS after each channel's filter goes to `filtered_noise`.
study::Passage passage(const Setup& s, std::size_t t, double v, double gain, std::mt19937& rng, double* filtered_noise) {
  const study::RunResult r = study::simulate(s.pm, s.trains[t], v, s.rs);
  const double fs = 1.0 / s.rs.dt;
  const auto lead = static_cast<Index>(fs);
  study::Passage p;
  p.name = s.trains[t].name + " at " + std::to_string(v * 3.6);
  p.train = t;
  p.fs_hz = fs;
  for (int k = 0; k < 3; ++k) {
    const Vector x = gain * study::station_response(r, 0, kinds[k]);
    std::normal_distribution<double> noise(0.0, 0.05 * std::sqrt(x.squaredNorm() / static_cast<double>(x.size())));
    Vector n(x.size() + lead), rec(x.size() + lead);
    for (Index j = 0; j < n.size(); ++j) n[j] = noise(rng);
    rec = n;
    rec.tail(x.size()) += x;
    const study::FilterSpec f = study::filter_for(s.sc.settings.filter, kinds[k]);
    const Vector nf = signal::sosfiltfilt(signal::cheby1(f.cheby, fs), n);
    filtered_noise[k] = std::sqrt(nf.squaredNorm() / static_cast<double>(nf.size()));
    p.channels.push_back({study::response_name(kinds[k]), 0, kinds[k], rec});
  }
  return p;
}

}  // namespace

TEST_CASE("twenty simulated passages of three trains land on the model's envelope within the noise", "[long]") {
  const Setup s = setup();
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> speed(160.0 / 3.6, 400.0 / 3.6);
  std::vector<study::Passage> passages;
  std::vector<double> truth;
  std::vector<std::array<double, 3>> noise;
  for (int i = 0; i < 20; ++i) {
    truth.push_back(speed(rng));
    noise.emplace_back();
    passages.push_back(passage(s, static_cast<std::size_t>(i % 3), truth.back(), 1.0, rng, noise.back().data()));
  }
  // One passage of a bridge 20 % stronger than the model: the check must say so.
  noise.emplace_back();
  passages.push_back(passage(s, 0, 250.0 / 3.6, 1.2, rng, noise.back().data()));
  // One unusable passage: it fails alone.
  passages.push_back(passages.front());
  passages.back().channels[1].x[5] = std::nan("");
  std::vector<double> speeds;
  for (double v = 150.0; v <= 410.0; v += 10.0) speeds.push_back(v / 3.6);
  study::PassageOptions o;
  o.v_min = 150.0 / 3.6;
  o.v_max = 410.0 / 3.6;
  o.threads = 2;
  const study::PassageStudy r = study::run_passages(s.pm, s.rs, s.sc.settings.filter, s.trains, speeds, passages, o);
  REQUIRE(r.passages.size() == 22);
  REQUIRE(r.curves.size() == 9);  // 3 trains x 3 responses at one station
  CHECK(r.envelope_failures.empty());
  double worst_speed = 0, worst_ratio = 0, worst_noise = 0;
  for (std::size_t i = 0; i < 20; ++i) {
    const study::PassageResult& p = r.passages[i];
    INFO(p.name << ": " << p.failure << " identified " << p.speed * 3.6 << " km/h, se " << p.speed_se * 3.6);
    REQUIRE(p.failure.empty());
    CHECK(std::abs(p.speed - truth[i]) / truth[i] < 0.005);
    CHECK(std::abs(p.speed - truth[i]) <= 3 * p.speed_se);
    worst_speed = std::max(worst_speed, std::abs(p.speed - truth[i]) / truth[i]);
    for (std::size_t k = 0; k < 3; ++k) {
      const study::ChannelVerdict& c = p.channels[k];
      INFO(c.channel << ": measured " << c.measured << ", predicted " << c.predicted << " [" << c.predicted_low << ", "
                     << c.predicted_high << "], noise " << c.noise_rms << " (put in " << noise[i][k] << ")");
      CHECK(c.within);
      // The noise it reports is the noise put in, filtered (the model is exact): within 25 %
      // (the residual also holds the misfit of a speed off by its standard error).
      CHECK(c.noise_rms == Approx(noise[i][k]).epsilon(0.25));
      worst_ratio = std::max(worst_ratio, std::abs(c.ratio - 1.0));
      worst_noise = std::max(worst_noise, std::abs(c.noise_rms / noise[i][k] - 1.0));
    }
  }
  // The stronger bridge is outside the band on every channel, and its ratio says by how much
  // (within the noise: 5 % of the RMS, filtered, is well under 2 % of the peak).
  for (const auto& c : r.passages[20].channels) {
    CHECK_FALSE(c.within);
    CHECK(c.ratio == Approx(1.2).epsilon(0.02));
  }
  CHECK(r.passages[21].failure.find("non-finite") != std::string::npos);
  CHECK(r.passages[21].input_error);
  // The envelope is the model's filtered peak at each speed: one point recomputed.
  const study::EnvelopeCurve& c = r.curves[4];  // HSLM-A7, deflection
  REQUIRE(c.speeds.size() == speeds.size());
  const Vector d = study::station_response(study::simulate(s.pm, s.trains[1], c.speeds[7], s.rs), 0, c.kind);
  CHECK(c.peaks[7] == Approx(study::filtered_peak(d, 1.0 / s.rs.dt, study::filter_for(s.sc.settings.filter, c.kind))).epsilon(1e-12));
  WARN("worst speed error " << worst_speed * 100 << " %, worst |ratio - 1| " << worst_ratio << ", worst noise estimate error "
                            << worst_noise * 100 << " %");
}
