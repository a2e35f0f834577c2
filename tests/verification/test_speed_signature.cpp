// Speed and entry time from the train's axle positions (issue #19 part 3): simulated passages of
// five trains at three speeds, 5 % white noise, acceleration, deflection and strain channels,
// matched against the same model at trial speeds (study::match_signature, as `viaduct speed
// --model` does). The identified speed must be within 0.5 % and within its stated uncertainty
// (three standard errors) of the truth, and the record time of the first axle's entry within its
// own.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "helpers.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/study/speed.hpp"

using namespace viaduct;

namespace {

// A two-car multiple unit: 26 m cars, bogie centres 19 m apart, 2.7 m bogies, 150 kN axles.
load::Train two_car_unit() {
  load::Train t;
  t.name = "two-car unit";
  for (double car : {0.0, 26.0})
    for (double x : {0.0, 2.7, 19.0, 21.7}) t.offset.push_back(car + x), t.load.push_back(150e3);
  return t;
}

// A Bo'Bo' locomotive (215 kN axles, bogies 2.9 m, centres 10.3 m) hauling eight 26.4 m coaches
// (bogies 2.5 m, centres 19 m, 120 kN axles).
load::Train loco_hauled() {
  load::Train t;
  t.name = "locomotive-hauled";
  for (double x : {0.0, 2.9, 10.3, 13.2}) t.offset.push_back(x), t.load.push_back(215e3);
  for (int c = 0; c < 8; ++c)
    for (double x : {0.0, 2.5, 19.0, 21.5}) t.offset.push_back(17.3 + 26.4 * c + x), t.load.push_back(120e3);
  return t;
}

struct Channel {
  const char* name;
  int kind;  // 0 acceleration, 1 deflection, 2 strain
};

Vector quantity(const study::RunResult& r, int kind) {
  if (kind == 0) return r.stations[0].acc;
  if (kind == 1) return r.stations[0].disp;
  for (const auto& e : r.effects)
    if (e.name == "mid_strain_ue") return e.value;
  return {};
}

}  // namespace

TEST_CASE("speed and entry time from the train's signature: five trains, three speeds, three quantities, 5 % noise", "[long]") {
  study::Scenario sc = vt::shipped("hslm-simply-supported", {"stations[0].fibre_m=0.6", "analysis.free_vibration_s=0.5"});
  study::RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  rs.method = study::Method::modal;
  const study::PreparedModel pm = study::prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, rs, true, true);
  const std::vector<load::Train> trains = {load::hslm_a("HSLM-A1", load::hslm_a_row(1)), load::hslm_a("HSLM-A9", load::hslm_a_row(9)),
                                           io::read_train_file(vt::source("data/trains/talgo-altaria.csv")), two_car_unit(), loco_hauled()};
  const double fs = 1.0 / rs.dt;
  const double lead = 0.81234;  // [s] of quiet record before the template's t = 0: not a whole number of samples
  std::mt19937 rng(19);
  double worst = 0, worst_cover = 0;
  for (const auto& train : trains)
    for (double v_kmh : {110.0, 190.0, 280.0})
      for (const Channel ch : {Channel{"acceleration", 0}, Channel{"deflection", 1}, Channel{"strain", 2}}) {
        const double v = v_kmh / 3.6;
        const Vector truth = quantity(study::simulate(pm, train, v, rs), ch.kind);
        // The record: the passage delayed by `lead` (linear interpolation), then 5 % noise.
        const auto n_lead = static_cast<Index>(std::ceil(lead * fs));
        Vector rec = Vector::Zero(truth.size() + n_lead);
        for (Index j = 0; j < rec.size(); ++j) {
          const double s = (static_cast<double>(j) / fs - lead) * fs;
          const auto i = static_cast<Index>(std::floor(s));
          if (s >= 0 && i + 1 < truth.size()) rec[j] = truth[i] + (s - static_cast<double>(i)) * (truth[i + 1] - truth[i]);
        }
        const double rms = std::sqrt(truth.squaredNorm() / static_cast<double>(truth.size()));
        std::normal_distribution<double> noise(0.0, 0.05 * rms);
        for (Index j = 0; j < rec.size(); ++j) rec[j] += noise(rng);
        study::SignatureOptions o;
        o.v_min = 0.75 * v;  // the line speed known to ±25 %
        o.v_max = 1.25 * v;
        o.filter = sc.settings.filter;  // 45 Hz low-pass
        o.max_shift_s = 10.0;
        const std::function<Vector(double)> at = [&](double u) { return quantity(study::simulate(pm, train, u, rs), ch.kind); };
        const study::SignatureMatch m = study::match_signature(rec, fs, 0.0, at, fs, o);
        const double err = (m.speed - v) / v;
        INFO(train.name << " at " << v_kmh << " km/h, " << ch.name << ": " << m.speed * 3.6 << " km/h, se " << m.speed_se * 3.6
                        << " km/h, shift " << m.shift_s << " s (se " << m.shift_se << "), correlation " << m.correlation);
        CHECK(std::abs(err) < 0.005);
        CHECK(std::abs(m.speed - v) <= 3 * m.speed_se);
        CHECK(std::abs(m.shift_s - lead) <= 3 * m.shift_se + 0.5 / fs);  // + half a sample: the alignment's interpolation
        CHECK(m.amplitude == Approx(1.0).epsilon(0.02));
        worst = std::max(worst, std::abs(err));
        worst_cover = std::max(worst_cover, std::abs(m.speed - v) / m.speed_se);
      }
  WARN("worst speed error " << worst * 100 << " %, worst error / standard error " << worst_cover);
}
