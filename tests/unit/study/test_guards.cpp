// Accuracy guards: the shipped scenarios lie in the measured region (no warning); a step too
// coarse for the filter's band edge or for the crossing of a span warns with the risked error.
#include <catch2/catch.hpp>

#include "viaduct/io/scenario.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/study/tradeoff.hpp"
#include "source_dir.hpp"

using namespace viaduct;

namespace {
const std::string src = VIADUCT_SOURCE_DIR;
study::Scenario shipped(const std::string& name, const std::vector<std::string>& set = {}) {
  return io::to_scenario(io::load_flat(src + "/scenarios/" + name + ".toml", set));
}
}  // namespace

TEST_CASE("accuracy guards: silent on the shipped scenarios, a warning with the risk outside") {
  for (const char* name : {"old-guadiana-sensitivity", "hslm-simply-supported", "old-guadiana-talgo"}) {
    INFO(name);
    const study::Scenario sc = shipped(name);
    std::vector<double> speeds = sc.sweep_speeds;
    if (sc.run_speed) speeds.push_back(*sc.run_speed);
    CHECK(study::accuracy_warnings(sc, speeds).empty());
  }
  // 4 ms against the 60 Hz band edge: f_c·dt = 0.24.
  const study::Scenario coarse = shipped("old-guadiana-sensitivity", {"analysis.dt=0.004"});
  const auto w = study::accuracy_warnings(coarse, coarse.sweep_speeds);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Catch::Contains("analysis.dt = 0.004 s samples the filter's band edge 60 Hz 4.2 times per period (f_c·dt = 0.24)") &&
                       Catch::Contains("15 % at 0.24") && Catch::Contains("take analysis.dt <= 0.001 s"));
  // Without the filter the band edge does not apply; a train at 10⁶ km/h crosses 15 m in a step.
  const study::Scenario raw = shipped("hslm-simply-supported", {"filter.enabled=false"});
  CHECK(study::accuracy_warnings(raw, raw.sweep_speeds).empty());
  const auto fast = study::accuracy_warnings(raw, {1e6 / 3.6});
  REQUIRE(fast.size() == 1);
  CHECK_THAT(fast[0], Catch::Contains("at 1e+06 km/h the axles cross the shortest span (15 m) in") &&
                          Catch::Contains("52 % at 2.5"));
}

TEST_CASE("soft pads: a modal basis below the rail's resonance on its pads warns, the presets take Newmark") {
  // Old Guadiana track: UIC60 (60.3 kg/m) every 0.6 m; pads of 3e6 N/m resonate at 45.8 Hz.
  const study::Scenario soft = shipped("old-guadiana-talgo", {"track.pad.k=3e6", "analysis.method=\"modal\"", "modal.max_frequency_hz=60"});
  CHECK(study::rail_on_pad_hz(*soft.track) == Approx(45.8).epsilon(2e-3));
  const auto w = study::accuracy_warnings(soft, {*soft.run_speed});
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Catch::Contains("resonance on its pads at 45.8 Hz, below the modal basis' 60 Hz") && Catch::Contains("+6.4 % at 46 Hz"));
  // The shipped pads (f = 265 Hz) keep the presets modal; soft ones make them Newmark at the same step.
  const study::Scenario normal = shipped("old-guadiana-talgo");
  CHECK(study::preset_settings("default", normal).method == study::Method::modal);
  const study::Scenario soft_preset = shipped("old-guadiana-talgo", {"track.pad.k=3e6"});
  const study::RunSettings p = study::preset_settings("default", soft_preset);
  CHECK(p.method == study::Method::newmark);
  CHECK(p.dt == Approx(study::preset_settings("default", normal).dt));
  CHECK(study::preset_settings("fast", shipped("old-guadiana-talgo", {"track.pad.k=1e7"})).method == study::Method::modal);  // 84 Hz > 45 Hz
}

TEST_CASE("a two-rail track on the whole deck: the half-deck model's responses, and load factors that do not fit warn") {
  // The shipped half-deck model (track.rails = "one", load_factor 0.5) is silent (above); the
  // same under whole axle loads warns that it computes twice the model's responses.
  const study::Scenario half = shipped("old-guadiana-talgo");
  CHECK(half.track_rails == "one");
  const study::Scenario doubled = shipped("old-guadiana-talgo", {"train.load_factor=1.0"});
  const auto w = study::accuracy_warnings(doubled, {*doubled.run_speed});
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Catch::Contains("track.rails = \"one\"") && Catch::Contains("2 times that is computed"));
  // The two-rail track on the full deck (every value doubled) under whole loads: the deck moves as
  // the half-deck model does under half loads (a linear model scaled: equal to rounding, 1e-9).
  const study::Scenario full = shipped("old-guadiana-talgo", {"bridge.file=\"" + src + "/data/bridges/old-guadiana-full-deck.toml\"",
                                                              "track.file=\"" + src + "/data/tracks/old-guadiana-ballasted-two-rails.toml\"",
                                                              "train.load_factor=1.0"});
  CHECK(full.track_rails == "both");
  CHECK(study::accuracy_warnings(full, {*full.run_speed}).empty());
  const study::RunResult a = study::simulate(study::prepare_model(half), half.trains.front(), *half.run_speed, half.settings);
  const study::RunResult b = study::simulate(study::prepare_model(full), full.trains.front(), *full.run_speed, full.settings);
  REQUIRE(a.stations.size() == b.stations.size());
  for (std::size_t i = 0; i < a.stations.size(); ++i) {
    INFO(a.stations[i].name);
    CHECK((a.stations[i].disp - b.stations[i].disp).cwiseAbs().maxCoeff() <= 1e-9 * a.stations[i].disp.cwiseAbs().maxCoeff());
    CHECK((a.stations[i].acc - b.stations[i].acc).cwiseAbs().maxCoeff() <= 1e-9 * a.stations[i].acc.cwiseAbs().maxCoeff());
  }
  // Both rails under half loads warns too.
  const study::Scenario halved = shipped("old-guadiana-talgo", {"bridge.file=\"" + src + "/data/bridges/old-guadiana-full-deck.toml\"",
                                                                "track.file=\"" + src + "/data/tracks/old-guadiana-ballasted-two-rails.toml\""});
  const auto wh = study::accuracy_warnings(halved, {*halved.run_speed});
  REQUIRE(wh.size() == 1);
  CHECK_THAT(wh[0], Catch::Contains("track.rails = \"both\"") && Catch::Contains("load_factor = 0.5"));
}

TEST_CASE("vehicles on a track's modes: a basis below 1.5 x the rail's resonance on its pads warns") {
  // Old Guadiana's pads: 265 Hz. Modes to 200 Hz leave the wheels a massless track (measured:
  // contact forces 69 % of the static load off); 400 Hz is in the measured region, and so is
  // Newmark on every DOF. The soft-pad warning of moving loads does not apply to vehicles.
  const std::vector<std::string> veh = {"train.files=[\"" + src + "/data/trains/ave-s103-8.toml\"]", "train.vehicle=\"multibody\""};
  auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), veh.begin(), veh.end());
    return shipped("old-guadiana-talgo", more);
  };
  for (const char* method : {"modal", "ida"}) {
    INFO(method);
    const study::Scenario low = with({std::string("analysis.method=\"") + method + "\"", "modal.max_frequency_hz=200"});
    const auto w = study::accuracy_warnings(low, {*low.run_speed});
    REQUIRE(w.size() == 1);
    CHECK_THAT(w[0], Catch::Contains("modal.max_frequency_hz = 200 Hz stops the modes below 1.5 x the rail's resonance on its pads (265 Hz)") &&
                         Catch::Contains("take modal.max_frequency_hz >= 397 Hz"));
    const study::Scenario high = with({std::string("analysis.method=\"") + method + "\"", "modal.max_frequency_hz=400"});
    CHECK(study::accuracy_warnings(high, {*high.run_speed}).empty());
  }
  const study::Scenario full = with({"analysis.method=\"newmark\"", "modal.max_frequency_hz=200"});
  CHECK(study::accuracy_warnings(full, {*full.run_speed}).empty());
  const study::Scenario forces = shipped("old-guadiana-talgo", {"analysis.method=\"modal\"", "modal.max_frequency_hz=200"});
  CHECK(study::accuracy_warnings(forces, {*forces.run_speed}).empty());
}

TEST_CASE("the guard's influence maxima a model keeps are those of the outputs asked for") {
  // A sweep's jobs share them through PreparedModel::imax; asked for other outputs it must give
  // theirs (a value kept per model alone would give the first outputs' numbers), the same as a
  // model that keeps nothing computes each time.
  const study::Scenario sc = shipped("hslm-simply-supported");
  const study::PreparedModel m = study::prepare_model(sc, false, true);
  study::PreparedModel fresh = study::prepare_model(sc, false, true);
  fresh.imax.reset();
  REQUIRE(m.effects.size() >= 2);
  const std::vector<solve::Functional> a = {m.effects.front().functional},
                                       b = {m.effects.back().functional, m.effects.front().functional};
  const Vector va = study::guard_influence_maxima(m, a), vb = study::guard_influence_maxima(m, b),
               va2 = study::guard_influence_maxima(m, a);
  CHECK(va == study::guard_influence_maxima(fresh, a));
  CHECK(vb == study::guard_influence_maxima(fresh, b));
  CHECK(va2 == va);
  REQUIRE(vb.size() == 2);
  CHECK(vb[1] == va[0]);
  CHECK(vb[0] != va[0]);  // the two outputs differ: a mix-up would show
  CHECK(va[0] > 0.0);
}
