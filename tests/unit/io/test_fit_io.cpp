#include <catch2/catch.hpp>
#include <filesystem>

#include "viaduct/io/fit.hpp"
#include "viaduct/io/scenario.hpp"
#include "../scratch.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::io;

namespace {
const std::string fit_io_src = VIADUCT_SOURCE_DIR;
}

TEST_CASE("fit parameters: key, bounds, scale and start checked against the scenario") {
  const FlatScenario f = load_flat(fit_io_src + "/scenarios/old-guadiana-talgo.toml");
  const study::FitParameter p = parse_fit_parameter(f, "track.pad.k=2e7:1e9");
  REQUIRE(p.key == "track.pad.k");
  REQUIRE(p.unit == "N/m");
  REQUIRE(p.initial == 1e8);  // from the track component file
  REQUIRE(p.scale == study::ParameterScale::log);  // auto: lower > 0
  REQUIRE(parse_fit_parameter(f, "bridge.damping.ratio1=0:0.1").scale == study::ParameterScale::linear);
  REQUIRE(parse_fit_parameter(f, "bridge.EI=5e9:1e10:linear").scale == study::ParameterScale::linear);
  auto refused = [&](const std::string& text, const std::string& why) {
    INFO(text);
    REQUIRE_THROWS_WITH(parse_fit_parameter(f, text), Catch::Contains(why));
  };
  refused("track.pad.kk=1:2", "unknown scenario key");
  refused("bridge.span_lengths=1:20", "not a number");
  const FlatScenario two = load_flat(fit_io_src + "/scenarios/old-guadiana-talgo.toml", {"bridge.EI=[7e9, 7.1e9]"});
  REQUIRE_THROWS_WITH(parse_fit_parameter(two, "bridge.EI=5e9:1e10"), Catch::Contains("list of several values"));
  refused("filter.order=1:5", "not a number");
  refused("title=1:2", "not a number");
  refused("track.pad.k=1e9:2e7", "lower < upper");
  refused("track.pad.k=2e8:1e9", "outside the bounds");
  refused("track.pad.k=-1:1e9", "violates the key's constraint > 0");
  refused("track.pad.k=0:1e9:log", "log scale needs lower > 0");
  refused("track.pad.k=1e7:1e9:cubic", "scale must be auto, log or linear");
  refused("track.pad.k=1e7", "expected track.pad.k=LO:HI");
  refused("track.pad.k=a:1e9", "lower bound 'a' is not a number");
  refused("=1:2", "expected KEY=LO:HI");
}

TEST_CASE("the [fit] section declares parameters, records and weights and errors name file and line") {
  vt::ScratchDir d("fitio");
  const std::string base = "[bridge]\nspan_lengths = [10.0]\nEI = 2e9\nmass_per_m = 5000.0\n"
                           "[train]\nfiles = [\"" + fit_io_src + "/data/trains/talgo-altaria.csv\"]\n"
                           "[[stations]]\nname = \"mid\"\nspan = 1\nat = 0.5\n";
  const std::string ok = d.write("ok.toml", base +
                                            "[fit]\nstarts = 3\nmodes = \"modes\"\n[fit.weights]\ntime = 1.0\nspectrum = 0.5\n"
                                            "[[fit.params]]\nkey = \"bridge.EI\"\nlower = 1e9\nupper = 4e9\n"
                                            "[[fit.params]]\nkey = \"bridge.damping.ratio\"\nlower = 0.0\nupper = 0.1\n"
                                            "[[fit.records]]\nfile = \"rec.csv\"\nmap = [\"a_mps2=mid\"]\nspeed_kmh = 120\n");
  const FitDeclaration decl = fit_declaration(load_flat(ok));
  REQUIRE(decl.params.size() == 2);
  REQUIRE(decl.params[0].initial == 2e9);
  REQUIRE(decl.params[1].scale == study::ParameterScale::linear);
  REQUIRE(decl.records.size() == 1);
  REQUIRE(decl.records[0].file == (d.p / "rec.csv").string());  // relative to the scenario
  REQUIRE(decl.records[0].speed_kmh == 120);
  REQUIRE(decl.records[0].map == std::vector<std::string>{"a_mps2=mid"});
  REQUIRE(decl.modes == (d.p / "modes").string());
  REQUIRE(decl.options.starts == 3);
  REQUIRE(decl.options.weights.time == 1.0);
  REQUIRE(decl.options.weights.spectrum == 0.5);
  REQUIRE(decl.options.weights.modal == -1.0);  // not given: the CLI decides
  // A bound outside the declared range names the file, line and key.
  const std::string bad = d.write("bad.toml", base + "[[fit.params]]\nkey = \"bridge.EI\"\nlower = 3e9\nupper = 4e9\n");
  REQUIRE_THROWS_WITH(fit_declaration(load_flat(bad)), Catch::Contains("bad.toml:") && Catch::Contains("outside the bounds"));
  const std::string missing = d.write("missing.toml", base + "[[fit.params]]\nkey = \"bridge.EI\"\nlower = 1e9\n");
  REQUIRE_THROWS_WITH(fit_declaration(load_flat(missing)), Catch::Contains("needs key, lower and upper"));
  const std::string typo = d.write("typo.toml", base + "[fit]\nstart = 3\n");
  REQUIRE_THROWS_WITH(load_flat(typo), Catch::Contains("typo.toml:") && Catch::Contains("did you mean"));
}

TEST_CASE("a fitted scenario is written out and loads back with the same values") {
  vt::ScratchDir d("fitted");
  FlatScenario f = load_flat(fit_io_src + "/scenarios/old-guadiana-talgo.toml");
  set_number(f, "bridge.EI", 7.123456789e9);
  set_number(f, "track.pad.k", 1.5e8);
  REQUIRE_THROWS_WITH(set_number(f, "track.pad.k", -1.0), Catch::Contains("must be > 0"));
  REQUIRE(f.at("track.pad.k").x == 1.5e8);  // a refused value changes nothing
  const std::string path = (d.p / "fitted.toml").string();
  write_scenario_toml(path, f, "test");
  const FlatScenario g = load_flat(path);
  for (const auto& [key, v] : f.values) {
    if (key == "bridge.file" || key == "track.file") continue;
    INFO(key);
    REQUIRE(g.has(key));
    const Value& w = g.at(key);
    if (v.type == ValueType::number) REQUIRE(w.x == v.x);  // written with 17 digits: exact
    if (v.type == ValueType::string && key != "train.files") REQUIRE(w.s == v.s);
  }
  REQUIRE(g.at("bridge.EI").x == 7.123456789e9);
  REQUIRE(g.at("train.files").ss.size() == 1);
  REQUIRE(std::filesystem::exists(g.at("train.files").ss[0]));  // absolute: loads from anywhere
  const study::Scenario a = to_scenario(f), b = to_scenario(g);
  REQUIRE(b.stations.size() == a.stations.size());
  REQUIRE(b.bridge.spans[0].EI == a.bridge.spans[0].EI);
}

TEST_CASE("identified modes are read from modal-fit's modes.csv and shapes.csv") {
  vt::ScratchDir d("modes");
  d.write("modes.csv",
          "method,mode,frequency_hz,damping_ratio,response,note\n"
          "peak-picking,1,10.1,0.03,S1_mid,\"channels disagree, a note with a comma\"\n"
          "lscf,1,10.0,0.029,,\n"
          "lscf,2,10.06,0.030,,\n");
  d.write("shapes.csv",
          "method,mode,response,re,im\n"
          "lscf,1,S1_mid,1.0,0.01\nlscf,1,S2_mid,0.98,0.0\n"
          "lscf,2,S1_mid,1.0,0.0\nlscf,2,S2_mid,-0.97,0.02\n");
  const study::ModalTarget t = read_identified_modes(d.p.string(), "lscf");
  REQUIRE(t.sensors == std::vector<std::string>{"S1_mid", "S2_mid"});
  REQUIRE(t.modes.size() == 2);
  REQUIRE(t.modes[1].frequency_hz == 10.06);
  REQUIRE(t.modes[1].shape[1] == -0.97);
  const study::ModalTarget pp = read_identified_modes((d.p / "modes.csv").string(), "peak-picking");
  REQUIRE(pp.modes.size() == 1);
  REQUIRE(pp.modes[0].shape.size() == 0);  // no shapes of that method: frequency only
  REQUIRE_THROWS_WITH(read_identified_modes(d.p.string(), "circle-fit"),
                      Catch::Contains("no mode of method 'circle-fit'") && Catch::Contains("lscf"));
  REQUIRE(t.modes[1].damping_ratio == 0.030);
  // viaduct decay's summary: one mode, mean frequency and envelope-fit damping.
  vt::ScratchDir dd("decay");
  dd.write("decay_summary.csv", "estimate,mean,std,n\nfrequency_hz,10.02,0.01,3\nzeta_log_decrement,0.029,0.001,3\n"
                                "zeta_envelope_fit,0.0285,0.001,3\nzeta_hilbert,0.0288,0.001,3\n");
  const study::ModalTarget dt = read_identified_modes(dd.p.string(), "lscf");
  REQUIRE(dt.modes.size() == 1);
  REQUIRE(dt.modes[0].frequency_hz == 10.02);
  REQUIRE(dt.modes[0].damping_ratio == 0.0285);
  REQUIRE(dt.modes[0].shape.size() == 0);
  REQUIRE(dt.sensors.empty());
  d.write("modes.csv", "method,mode,frequency_hz\nlscf,1,abc\n");
  REQUIRE_THROWS_WITH(read_identified_modes(d.p.string(), "lscf"), Catch::Contains("modes.csv:2") && Catch::Contains("not a number"));
}
