#include <unistd.h>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "viaduct/io/profile.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/simulation.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::io;
namespace fs = std::filesystem;

namespace {
const std::string scenario_src = VIADUCT_SOURCE_DIR;

// A scratch directory with a scenario and component files.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("viaduct-io-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    fs::create_directories(dir / "parts");
    write("parts/bridge.toml", "span_lengths = [10.0]\nEI = 2e9\nmass_per_m = 5000.0\n[damping]\nratio = 0.02\n");
    write("parts/train.toml", "kind = \"regular\"\nn_axles = 3\nspacing = 12.0\naxle_load_kN = 150\n");
  }
  ~Scratch() { fs::remove_all(dir); }
  static int& counter() {
    static int c = 0;
    return c;
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
  std::string scenario(const std::string& extra) const {
    return write("s.toml", "[bridge]\nfile = \"parts/bridge.toml\"\n[train]\nfiles = [\"parts/train.toml\"]\n"
                           "[[stations]]\nname = \"mid\"\nspan = 1\nat = 0.5\n" + extra);
  }
};
}  // namespace

TEST_CASE("shipped scenarios load and resolve") {
  for (const char* s : {"old-guadiana-sensitivity", "old-guadiana-talgo", "hslm-simply-supported"}) {
    INFO(s);
    const FlatScenario f = load_flat(scenario_src + "/scenarios/" + s + ".toml");
    const study::Scenario sc = to_scenario(f);
    REQUIRE_FALSE(sc.stations.empty());
    REQUIRE_FALSE(sc.sweep_speeds.empty());
  }
  const FlatScenario og = load_flat(scenario_src + "/scenarios/old-guadiana-sensitivity.toml");
  const study::Scenario sc = to_scenario(og);
  REQUIRE(sc.track.has_value());
  REQUIRE(sc.sweep_speeds.size() == 60);
  REQUIRE(sc.sweep_speeds.front() == Approx(40.0));
  REQUIRE(sc.sweep_speeds.back() == Approx(100.0));
  REQUIRE(sc.track->pad.k == 1e8);
  REQUIRE(sc.bridge.spans.size() == 2);
  // 4 parameters x 4 factors, the four factor-1 cases being one reference: 13 distinct models.
  const auto v = sweep_variants(og);
  REQUIRE(v.size() == 13);
  REQUIRE(v[0].label == "reference");
  REQUIRE(v[1].label == "Kp x0.5");
  REQUIRE(v[1].scenario.track->pad.k == Approx(0.5e8));
  REQUIRE(v[4].label == "Cp x0");
  REQUIRE(v[4].scenario.track->pad.c == 0.0);
  REQUIRE(sweep_variants(load_flat(scenario_src + "/scenarios/old-guadiana-sensitivity.toml", {"sweep.mode=reference"})).size() == 1);
  const study::Scenario hs = to_scenario(load_flat(scenario_src + "/scenarios/hslm-simply-supported.toml"));
  REQUIRE(hs.trains.size() == 10);
  REQUIRE(hs.sweep_speeds.size() == 281);
  REQUIRE_FALSE(hs.track.has_value());  // no track section: no track DOFs
}

TEST_CASE("component files, relative paths, defaults and origins") {
  Scratch s;
  const FlatScenario f = load_flat(s.scenario(""));
  REQUIRE(f.at("bridge.EI").x == 2e9);
  REQUIRE(f.at("bridge.EI").where.file.find("parts/bridge.toml") != std::string::npos);
  REQUIRE(f.at("bridge.EI").where.line == 2);
  REQUIRE(f.defaulted.count("analysis.dt") == 1);
  REQUIRE(f.at("analysis.dt").x == 0.001);
  REQUIRE_FALSE(f.has("track.pad.k"));     // no track section: no track defaults
  REQUIRE_FALSE(f.has("sweep.mode"));
  const study::Scenario sc = to_scenario(f);
  REQUIRE(sc.trains[0].n_axles() == 3);
  REQUIRE(sc.stations[0].x_local == 5.0);
  const std::string text = format_resolved(f);
  REQUIRE(text.find("analysis.dt = 0.001   # [s] default") != std::string::npos);
  REQUIRE(text.find("bridge.EI = 2000000000.0   # [N·m²] ") != std::string::npos);
}

TEST_CASE("set overrides scenario and component keys and precedence set > scenario > component") {
  Scratch s;
  const std::string p = s.scenario("[bridge.damping]\nratio = 0.03\n");
  FlatScenario f = load_flat(p);
  REQUIRE(f.at("bridge.damping.ratio").x == 0.03);  // scenario beats component
  f = load_flat(p, {"bridge.damping.ratio=0.05", "bridge.EI=[3e9]", "filter.band=lowpass", "stations[0].at=0.25"});
  REQUIRE(f.at("bridge.damping.ratio").x == 0.05);
  REQUIRE(f.at("bridge.damping.ratio").where.file == "--set");
  REQUIRE(f.at("bridge.EI").xs == std::vector<double>{3e9});
  REQUIRE(f.at("filter.band").s == "lowpass");      // bare word taken as a string
  REQUIRE(to_scenario(f).stations[0].x_local == 2.5);
  REQUIRE_THROWS_WITH(load_flat(p, {"bridge.damping.ration=1"}), Catch::Contains("did you mean 'bridge.damping.ratio'"));
  REQUIRE_THROWS_WITH(load_flat(p, {"nonsense"}), Catch::Contains("expected key=value"));
}

TEST_CASE("bad scenarios give file, line and key") {
  Scratch s;
  auto error_of = [&](const std::string& extra) {
    try {
      to_scenario(load_flat(s.scenario(extra)));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string e = error_of("[analysis]\ndtt = 0.001\n");
  REQUIRE(e.find("s.toml:10: key 'analysis.dtt': unknown key (did you mean 'analysis.dt'?)") != std::string::npos);
  e = error_of("[analysis]\ndt = \"fast\"\n");
  REQUIRE(e.find("s.toml:10: key 'analysis.dt': must be a number") != std::string::npos);
  e = error_of("[analysis]\ndt = 0.0\n");
  REQUIRE(e.find("key 'analysis.dt': must be > 0 [s], got 0") != std::string::npos);
  e = error_of("[analysis]\ndt = -1e-3\n");
  REQUIRE(e.find("must be > 0") != std::string::npos);
  e = error_of("[run]\nspeed_kmh = -5\n");
  REQUIRE(e.find("key 'run.speed_kmh': must be > 0 [km/h]") != std::string::npos);
  e = error_of("[track]\nsleeper_mass = 300\n");  // a track section without its required keys
  REQUIRE(e.find("key 'track.rail.E': required key is missing") != std::string::npos);
  e = error_of("[bridge.bearings]\nrigid = false\n");
  REQUIRE(e.find("key 'bridge.bearings.k': must be > 0 [N/m] when bridge.bearings.rigid = false") != std::string::npos);
  e = error_of("[[stations]]\nname = \"mid\"\nspan = 1\nat = 0.2\n");
  REQUIRE(e.find("duplicate station name 'mid'") != std::string::npos);
  e = error_of("[[stations]]\nname = \"far\"\nspan = 3\nat = 0.2\n");
  REQUIRE(e.find("span 3 does not exist") != std::string::npos);
  e = error_of("[filter]\nhigh_hz = 900.0\n");
  REQUIRE(e.find("high_hz in (0, fs/2 = 500) Hz") != std::string::npos);
  e = error_of("[sweep]\nspeeds_kmh = [100]\nspeed_min_kmh = 50\n");
  REQUIRE(e.find("give speeds one way only") != std::string::npos);
  // Zero span length is caught in the component file with its line.
  s.write("parts/bridge.toml", "span_lengths = [0.0]\nEI = 2e9\nmass_per_m = 5000.0\n");
  e = error_of("");
  REQUIRE(e.find("bridge.toml:1: key 'bridge.span_lengths': must be > 0 [m], got 0") != std::string::npos);
  // Syntax errors name the file and line (toml11's message).
  s.write("parts/bridge.toml", "span_lengths = [10.0\nEI = 2e9\n");
  e = error_of("");
  REQUIRE(e.find("TOML syntax error") != std::string::npos);
  REQUIRE(e.find("bridge.toml") != std::string::npos);
}

TEST_CASE("a method this build lacks is refused at the key that chose it") {
  // The tests are built with IDA only (CMakeLists.txt, VIADUCT_IDA): here every method is built and
  // a scenario taking ida resolves. A build without SUNDIALS reports traits.built = false for ida
  // (integrator.cpp), which to_scenario() refuses through require_method_built: checked here with
  // such traits, as a build without IDA would give them.
  Scratch s;
  for (const solve::Method m : {solve::Method::newmark, solve::Method::modal, solve::Method::ida})
    REQUIRE(solve::method_traits(m).built);
  const FlatScenario f = load_flat(s.scenario("[analysis]\nmethod = \"ida\"\n"));
  REQUIRE(to_scenario(f).settings.method == solve::Method::ida);
  solve::MethodTraits missing = solve::method_traits(solve::Method::ida);
  missing.built = false;
  missing.not_built = "this viaduct was built without SUNDIALS IDA";
  REQUIRE_THROWS_WITH(require_method_built(f.at("analysis.method"), missing),
                      Catch::Contains("s.toml:10: key 'analysis.method': this viaduct was built without SUNDIALS IDA"));
  REQUIRE_NOTHROW(require_method_built(f.at("analysis.method"), solve::method_traits(solve::Method::ida)));
}

TEST_CASE("train files: CSV and TOML, with clear errors") {
  const load::Train talgo = read_train_file(scenario_src + "/data/trains/talgo-altaria.csv");
  REQUIRE(talgo.n_axles() == 12);
  REQUIRE(talgo.total_load() == Approx(1880e3));
  REQUIRE(talgo.length() == Approx(109.02));
  // Shared Talgo axles are d = 13.14 m apart (Table 2).
  REQUIRE(talgo.offset[6] - talgo.offset[5] == Approx(13.14));
  const load::Train a1 = read_train_file(scenario_src + "/data/trains/hslm/A1.toml");
  REQUIRE(a1.name == "HSLM-A1");
  REQUIRE(a1.n_axles() == 50);
  Scratch s;
  auto error_of = [&](const std::string& name, const std::string& text) {
    try {
      read_train_file(s.write(name, text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  REQUIRE(error_of("a.csv", "x,y\n1,2\n").find("a.csv:1: train CSV header must be 'position_m,load_kN'") != std::string::npos);
  REQUIRE(error_of("b.csv", "# c\nposition_m,load_kN\n0,100\n3,abc\n").find("b.csv:4: not a number") != std::string::npos);
  REQUIRE(error_of("c.csv", "position_m,load_kN\n0,100\n3,-5\n").find("load must be > 0") != std::string::npos);
  REQUIRE(error_of("d.csv", "position_m,load_kN\n5,100\n3,100\n").find("d.csv:3: axle positions must be listed head to tail, not decreasing") !=
          std::string::npos);
  REQUIRE(error_of("e.csv", "position_m,load_kN\n").find("no axles") != std::string::npos);
  REQUIRE(error_of("f.toml", "kind = \"regular\"\nn_axle = 3\n").find("f.toml:2: key 'n_axle': unknown train key") != std::string::npos);
  REQUIRE(error_of("g.toml", "kind = \"magic\"\n").find("must be hslm, regular, axles or coaches") != std::string::npos);
  REQUIRE(error_of("h.toml", "kind = \"hslm\"\nhslm_number = 12\n").find("h.toml:2: key 'hslm_number': must be a whole number from 1 to 10, got 12") !=
          std::string::npos);
  // Sizes are checked before they become integers: no overflow, no billion-axle train.
  REQUIRE(error_of("i.toml", "kind = \"regular\"\nn_axles = 1e12\nspacing = 2.0\naxle_load_kN = 100\n")
              .find("i.toml:2: key 'n_axles': must be a whole number from 1 to 10000, got 1e+12") != std::string::npos);
  REQUIRE(error_of("j.toml", "kind = \"regular\"\nn_axles = 2.5\nspacing = 2.0\naxle_load_kN = 100\n").find("whole number") !=
          std::string::npos);
  // Invalid UTF-8 is refused before toml11 reads it (found by fuzzing: toml11 read past its
  // buffer on such bytes in a literal string).
  REQUIRE(error_of("m.toml", "kind = \"regular\"\nname = 'x\xff\xff'\n").find("m.toml:2: not UTF-8 text or a control character (byte 0xff)") !=
          std::string::npos);
  // Overlong forms and surrogates too (the second fuzz finding: C1 8D in a multi-line string).
  REQUIRE(error_of("o.toml", "kind = \"regular\"\nname = '''x\xc1\x8d'''\n").find("o.toml:2: not UTF-8 text") != std::string::npos);
  REQUIRE(error_of("q.toml", "kind = \"regular\"\nname = 'x\xed\xa0\x80'\n").find("q.toml:2: not UTF-8 text") != std::string::npos);
  // Valid 2-, 3- and 4-byte characters pass (the error is the next key's).
  REQUIRE(error_of("r.toml", "kind = \"regular\"\nname = \"Mart\xc3\xadnez \xe2\x80\x94 \xf0\x9f\x9a\x84\"\nn_axles = 0\nspacing = 2.0\naxle_load_kN = 100\n").find("whole number") !=
          std::string::npos);
  // A key of another kind of train is an error, not silently ignored.
  REQUIRE(error_of("k.toml", "kind = \"regular\"\nn_axles = 4\nspacing = 2.0\naxle_load_kN = 100\nhslm_number = 3\n")
              .find("k.toml:5: key 'hslm_number': belongs to hslm trains, not to kind = \"regular\"") != std::string::npos);
  REQUIRE(error_of("l.toml", "kind = \"hslm\"\nhslm_number = 3\nspacing = 2.0\n").find("belongs to regular trains") !=
          std::string::npos);
  REQUIRE_THROWS_WITH(read_train_file(s.dir.string() + "/missing.toml"), Catch::Contains("train file not found"));
}

TEST_CASE("vehicles: coach files, trains of coaches and the vehicle keys, with file, line and key") {
  // The shipped scenario: eight AVE S103 coaches as multibody vehicles on an FRA class 5 rail.
  const study::Scenario v = to_scenario(load_flat(scenario_src + "/scenarios/vehicles-25m.toml"));
  REQUIRE(v.trains.size() == 1);
  CHECK(v.trains[0].coaches.size() == 8);
  CHECK(v.trains[0].n_axles() == 32);
  CHECK(v.trains[0].load[0] == Approx(152055.0).epsilon(1e-12));
  CHECK(v.settings.vehicle.model == study::VehicleModel::multibody);
  CHECK(v.settings.irregularity.spectrum == "fra5");
  const load::CoachSpec m = read_coach_file(scenario_src + "/data/vehicles/manchester-benchmark.toml");
  CHECK(m.mass() == Approx(32000 + 2 * 2615 + 4 * 1813).epsilon(1e-15));

  Scratch s;
  const std::string coach = "kind = \"coach\"\nbody_mass_kg = 47800\nbody_pitch_inertia_kgm2 = 1957888\nbogie_spacing_m = 17.375\n"
                            "bogie_mass_kg = 3500\nbogie_pitch_inertia_kgm2 = 1715\nwheelbase_m = 2.5\nwheelset_mass_kg = 1800\n"
                            "primary_stiffness_N_m = 2.4e6\nprimary_damping_Ns_m = 2e4\nsecondary_stiffness_N_m = 7e5\n"
                            "secondary_damping_Ns_m = 4e4\nlength_m = 25.0\n";
  auto train_error = [&](const std::string& coach_text) {
    s.write("parts/coach.toml", coach_text);
    try {
      read_train_file(s.write("parts/coaches.toml", "kind = \"coaches\"\nvehicle = \"coach.toml\"\nn_coaches = 2\n"));
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("no error");
  };
  CHECK(train_error(coach) == "no error");
  std::string e = train_error(std::regex_replace(coach, std::regex("body_mass_kg = 47800"), "body_mass_kg = -5"));
  CHECK(e.find("coaches.toml:2: key 'vehicle'") != std::string::npos);
  CHECK(e.find("coach.toml:2: key 'body_mass_kg': -5: violated constraint > 0") != std::string::npos);
  e = train_error(std::regex_replace(coach, std::regex("length_m = 25.0"), "length_m = 19.0"));
  CHECK(e.find("coach.toml:13: key 'length_m'") != std::string::npos);
  CHECK(e.find("next coach") != std::string::npos);
  e = train_error(coach + "wheel_radius = 0.4\n");
  CHECK(e.find("coach.toml:14: key 'wheel_radius': unknown vehicle key") != std::string::npos);
  e = train_error(std::regex_replace(coach, std::regex("wheelset_mass_kg = 1800\n"), ""));
  CHECK(e.find("key 'wheelset_mass_kg': required") != std::string::npos);

  // A scenario with [train] lines (from line 5) and more sections after the station.
  auto vehicle_scenario = [&](const std::string& train, const std::string& extra) {
    return s.write("v.toml", "[bridge]\nfile = \"parts/bridge.toml\"\n[train]\nfiles = [\"parts/train.toml\"]\n" + train +
                                 "[[stations]]\nname = \"mid\"\nspan = 1\nat = 0.5\n" + extra);
  };
  auto error_of = [&](const std::string& train, const std::string& extra) {
    try {
      to_scenario(load_flat(vehicle_scenario(train, extra)));
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("no error");
  };
  // parts/train.toml is a list of axles.
  const std::string sprung = "vehicle = \"sprung\"\nunsprung_mass_kg = 1800\nsuspension_stiffness_N_m = 3e5\n";
  e = error_of("vehicle = \"multibody\"\n", "");
  CHECK(e.find("v.toml:5: key 'train.vehicle': multibody needs trains of coaches") != std::string::npos);
  e = error_of("vehicle = \"sprung\"\n", "");
  CHECK(e.find("v.toml:5: key 'train.vehicle': sprung: 'train' is a list of axles: give train.unsprung_mass_kg") != std::string::npos);
  e = error_of("vehicle = \"sprung\"\nunsprung_mass_kg = 1800\n", "");
  CHECK(e.find("v.toml:6: key 'train.unsprung_mass_kg': needs train.suspension_stiffness_N_m too") != std::string::npos);
  CHECK(error_of(sprung, "") == "no error");
  e = error_of("vehicle = \"bogies\"\n", "");
  CHECK(e.find("v.toml:5: key 'train.vehicle'") != std::string::npos);
  CHECK(e.find("forces|sprung|multibody") != std::string::npos);
  e = error_of(sprung, "[irregularity]\nspectrum = \"fra7\"\n");
  CHECK(e.find("v.toml:13: key 'irregularity.spectrum'") != std::string::npos);
  e = error_of("", "[irregularity]\nspectrum = \"fra4\"\n");
  CHECK(e.find("v.toml:10: key 'irregularity.spectrum': moving forces do not see the rail's profile") != std::string::npos);
  e = error_of(sprung, "[irregularity]\nspectrum = \"fra4\"\ntaper_m = 200\n");
  CHECK(e.find("v.toml:14: key 'irregularity.taper_m': must not exceed irregularity.run_in_m") != std::string::npos);
  e = error_of(sprung, "[irregularity]\nspectrum = \"fra4\"\nprofile = \"parts/p.csv\"\n");
  CHECK(e.find("v.toml:14: key 'irregularity.profile': give a measured profile or irregularity.spectrum, not both") != std::string::npos);
  // A measured profile shorter than the run: refused with the key's line (and again when a
  // model is prepared, for sweep variants that change the path).
  s.write("parts/p.csv", "x_m,z_mm\n0,0\n1,0.5\n2,0\n3,-0.5\n4,0\n");
  e = error_of(sprung, "[irregularity]\nprofile = \"parts/p.csv\"\n");
  CHECK(e.find("v.toml:13: key 'irregularity.profile': irregularity.profile covers x = 0 to 4 m; the run needs -100 to 30 m") !=
        std::string::npos);
  study::Scenario sc = to_scenario(load_flat(vehicle_scenario(sprung, "")));
  sc.settings.irregularity.measured = std::make_shared<const load::RailProfile>(read_rail_profile(s.dir.string() + "/parts/p.csv"));
  CHECK_THROWS_WITH(study::prepare_model(sc), Catch::Contains("irregularity.profile covers x = 0 to 4 m; the run needs -100 to 30 m"));
}

TEST_CASE("grid variants and variant keys are checked") {
  Scratch s;
  const std::string p = s.scenario(
      "[sweep]\nspeeds_kmh = [100, 200]\nmode = \"grid\"\n"
      "[[sweep.variants]]\nkey = \"bridge.EI\"\nlabel = \"EI\"\nfactors = [0.5, 1.0, 2.0]\n"
      "[[sweep.variants]]\nkey = \"bridge.damping.ratio\"\nfactors = [1.0, 2.0]\n");
  const auto v = sweep_variants(load_flat(p));
  REQUIRE(v.size() == 6);  // 3 x 2 combinations, the all-ones one being the reference
  REQUIRE(v[0].label == "reference");
  REQUIRE(v.back().label == "EI x2, bridge.damping.ratio x2");
  REQUIRE(v.back().scenario.bridge.spans[0].EI == Approx(4e9));
  const std::string q = s.scenario("[sweep]\nspeeds_kmh = [100]\n[[sweep.variants]]\nkey = \"bridge.EI\"\nfactors = [-1.0]\n");
  REQUIRE_THROWS_WITH(load_flat(q), Catch::Contains("key 'sweep.variants[0].factors': must be >= 0, got -1"));
  // A factor that breaks the varied key's own constraint is caught when the variant is made.
  const std::string z = s.scenario("[sweep]\nspeeds_kmh = [100]\n[[sweep.variants]]\nkey = \"bridge.EI\"\nfactors = [0.0]\n");
  REQUIRE_THROWS_WITH(sweep_variants(load_flat(z)), Catch::Contains("factor 0 breaks the rule of") && Catch::Contains("key 'bridge.EI': must be > 0"));
  // For a sweep, that variant alone fails (its cases, with the reason); the others stand.
  const std::string z2 = s.scenario("[sweep]\nspeeds_kmh = [100]\n[[sweep.variants]]\nkey = \"bridge.EI\"\nfactors = [0.0, 2.0]\n");
  const auto iso = sweep_variants(load_flat(z2), /*isolate_failures=*/true);
  REQUIRE(iso.size() == 3);
  CHECK(iso[0].error.empty());
  CHECK(iso[1].label == "bridge.EI x0");
  CHECK_THAT(iso[1].error, Catch::Contains("variant 'bridge.EI x0': ") && Catch::Contains("s.toml:12: key 'sweep.variants[0].key': factor 0 breaks the rule of") && Catch::Contains("must be > 0"));
  CHECK(iso[1].scenario.sweep_speeds == iso[0].scenario.sweep_speeds);
  CHECK(iso[2].error.empty());
  CHECK(iso[2].scenario.bridge.spans[0].EI == Approx(4e9));
  const std::string r = s.scenario("[sweep]\nspeeds_kmh = [100]\n[[sweep.variants]]\nkey = \"filter.order\"\nfactors = [2.0]\n");
  // Reported at the variant's entry, with its line.
  REQUIRE_THROWS_WITH(sweep_variants(load_flat(r)), Catch::Contains(":12: key 'sweep.variants[0].key': variant key 'filter.order' must be numeric"));
}

TEST_CASE("a scenario with a megabyte line reads in linear time, with its values and line numbers") {
  // toml11 alone takes minutes on a 1 MB line (issue #18): long lines are split after their
  // array commas before parsing. 150000 speeds: the values, then a bad key after the long line
  // reported on its own line (13), not on a line of the split.
  Scratch s;
  std::string speeds = "speeds_kmh = [";
  for (int i = 0; i < 150000; ++i) speeds += (i ? ", " : "") + std::to_string(100 + i % 200) + ".5";
  speeds += "]  # a comment, with [brackets], and commas\n";
  REQUIRE(speeds.size() > 1000000);
  const std::string p = s.scenario("[sweep]\n" + speeds + "[filter]\norder = 3\n");
  const FlatScenario f = load_flat(p);
  const auto& v = f.at("sweep.speeds_kmh");
  REQUIRE(v.xs.size() == 150000);
  CHECK(v.xs[149999] == Approx(100 + 149999 % 200 + 0.5));
  CHECK(v.where.line == 10);
  CHECK(f.at("filter.order").where.line == 12);
  const std::string q = s.scenario("[sweep]\n" + speeds + "[filter]\norder = 3\nhigh_hz = -1\n");
  REQUIRE_THROWS_WITH(load_flat(q), Catch::Contains(":13: key 'filter.high_hz'"));
  // Strings keep their commas and brackets.
  std::string names = "files = [";
  for (int i = 0; i < 400; ++i) names += std::string(i ? ", " : "") + "\"a, [b] 'c' \\\" " + std::to_string(i) + ".toml\"";
  names += "]\n";
  REQUIRE(names.size() > 4096);
  Scratch t;
  const FlatScenario g = load_flat(t.write("r.toml", "[train]\n" + names));
  const auto& files = g.at("train.files").ss;
  REQUIRE(files.size() == 400);
  CHECK_THAT(files[7], Catch::EndsWith("/a, [b] 'c' \" 7.toml"));  // resolved against the file's directory
  // An inline table in a long line is not split (TOML keeps it on one line): the scenario's own
  // message for it, not a syntax error of the split.
  std::string inl = "speeds_kmh = [{a = 1, b = 2}";
  while (inl.size() < 5000) inl += ", {a = 1, b = 2}";
  inl += "]\n";
  REQUIRE_THROWS_WITH(load_flat(t.write("i.toml", "[sweep]\n" + inl)), Catch::Contains("i.toml:2: key 'sweep.speeds_kmh[0].a': unknown key"));
}

TEST_CASE("train.files entry hslm:A1-A10 gives the ten Eurocode trains the shipped files give") {
  const std::string hs = scenario_src + "/scenarios/hslm-simply-supported.toml";
  const study::Scenario files = to_scenario(load_flat(hs));
  const study::Scenario named = to_scenario(load_flat(hs, {"train.files=[\"hslm:A1-A10\"]"}));
  REQUIRE(named.trains.size() == 10);
  REQUIRE(files.trains.size() == 10);
  for (std::size_t i = 0; i < 10; ++i) {
    CHECK(named.trains[i].name == files.trains[i].name);
    CHECK(named.trains[i].offset == files.trains[i].offset);
    CHECK(named.trains[i].load == files.trains[i].load);
  }
  const study::Scenario some = to_scenario(load_flat(hs, {"train.files=[\"hslm:A3,A5-A6\"]"}));
  REQUIRE(some.trains.size() == 3);
  CHECK(some.trains[1].name == "HSLM-A5");
  REQUIRE_THROWS_WITH(to_scenario(load_flat(hs, {"train.files=[\"hslm:A11\"]"})), Catch::Contains("HSLM trains are A1 to A10, not A11"));
  REQUIRE_THROWS_WITH(to_scenario(load_flat(hs, {"train.files=[\"hslm:B2\"]"})), Catch::Contains("are named A1 to A10"));
  REQUIRE_THROWS_WITH(to_scenario(load_flat(hs, {"train.files=[\"hslm:A5-A2\"]"})), Catch::Contains("must go up"));
}

TEST_CASE("arrays nested thousands deep are refused before they overflow the parser's stack") {
  // The third fuzz finding: toml11 parses arrays recursively; 100000 '[' overflowed the stack.
  Scratch s;
  const std::string p = s.scenario("[sweep]\nspeeds_kmh = " + std::string(100000, '[') + "\n");
  REQUIRE_THROWS_WITH(load_flat(p), Catch::Contains(":10: arrays or tables nested more than 64 deep"));
  // Brackets inside strings and comments do not count.
  const std::string q = s.write("t.toml", "title = \"" + std::string(200, '[') + "\"  # " + std::string(200, '{') + "\n");
  CHECK(load_flat(q).at("title").s == std::string(200, '['));
}

TEST_CASE("the number of sweep speeds is limited before any is made") {
  Scratch s;
  const std::string p = s.scenario("[sweep]\nspeed_min_mps = 10\nspeed_max_mps = 90\nn_speeds = 10000000\n");
  REQUIRE_THROWS_WITH(to_scenario(load_flat(p)), Catch::Contains(":12: key 'sweep.n_speeds': must be at most a million speeds"));
  const std::string q = s.scenario("[sweep]\nspeed_min_kmh = 10\nspeed_max_kmh = 400\nspeed_step_kmh = 1e-6\n");
  REQUIRE_THROWS_WITH(to_scenario(load_flat(q)), Catch::Contains("gives more than a million speeds"));
  const std::string r = s.scenario("[sweep]\nspeed_min_kmh = 10\nspeed_max_kmh = 400\nspeed_step_kmh = 1e-300\n");
  REQUIRE_THROWS_WITH(to_scenario(load_flat(r)), Catch::Contains("gives more than a million speeds"));
  // Found by the fuzzer: 1e999 reads as the largest double, whose arithmetic overflowed to an
  // infinite speed; TOML's inf and nan are refused for every key.
  const std::string big = s.scenario("[sweep]\nspeed_min_mps = 40\nspeed_max_mps = 100.1e999\nn_speeds = 60\n");
  REQUIRE_THROWS_WITH(to_scenario(load_flat(big)), Catch::Contains("the speeds are too large to compute"));
  const std::string inf = s.scenario("[analysis]\ndt = inf\n");
  REQUIRE_THROWS_WITH(load_flat(inf), Catch::Contains(":10: key 'analysis.dt': must be a finite number, got inf"));
  const std::string nan = s.scenario("[sweep]\nspeeds_kmh = [100, nan]\n");
  REQUIRE_THROWS_WITH(load_flat(nan), Catch::Contains("key 'sweep.speeds_kmh': must hold finite numbers, got nan"));
}

TEST_CASE("docs/scenarios.md documents every key (regenerate with scripts/generate/gen_docs.sh)") {
  std::ifstream in(scenario_src + "/docs/scenarios.md");
  std::stringstream ss;
  ss << in.rdbuf();
  REQUIRE(ss.str().find(schema_markdown()) != std::string::npos);
}

TEST_CASE("solution methods and presets resolve from the scenario and explicit keys override a preset") {
  Scratch s;
  // Default: Newmark, direct.
  study::Scenario d = to_scenario(load_flat(s.scenario("")));
  REQUIRE(d.settings.method == study::Method::newmark);
  REQUIRE(d.settings.superposition == study::Superposition::direct);
  // A preset scales with the band edge: the default filter's 30 Hz here.
  study::Scenario f = to_scenario(load_flat(s.scenario("[analysis]\npreset = \"fast\"\n")));
  REQUIRE(f.settings.method == study::Method::modal);
  REQUIRE(f.settings.modal.max_frequency_hz == Approx(45.0));
  REQUIRE(f.settings.dt == Approx(1.0 / (16 * 30.0)));
  REQUIRE(f.settings.modal.static_correction);
  study::Scenario r = to_scenario(load_flat(s.scenario("[analysis]\npreset = \"reference\"\n")));
  REQUIRE(r.settings.method == study::Method::newmark);
  REQUIRE(r.settings.dt == Approx(1.0 / (80 * 30.0)));
  // Explicit keys win over the preset, from the file or from --set.
  study::Scenario e = to_scenario(load_flat(s.scenario("[analysis]\npreset = \"default\"\ndt = 0.002\n[modal]\nn_modes = 4\n"),
                                            {"modal.static_correction=false"}));
  REQUIRE(e.settings.method == study::Method::modal);
  REQUIRE(e.settings.dt == 0.002);
  REQUIRE(e.settings.modal.n_modes == 4);
  REQUIRE(e.settings.modal.max_frequency_hz == Approx(60.0));  // default: 2 f_c
  REQUIRE_FALSE(e.settings.modal.static_correction);
  REQUIRE(e.settings.modal.damping_vectors == 1);  // the default block
  study::Scenario dv = to_scenario(load_flat(s.scenario("[modal]\ndamping_vectors = 0\n")));
  REQUIRE(dv.settings.modal.damping_vectors == 0);
  REQUIRE_THROWS_WITH(load_flat(s.scenario("[modal]\ndamping_vectors = 4\n")), Catch::Contains("modal.damping_vectors"));
  // IDA and unit-response keys.
  study::Scenario i = to_scenario(load_flat(s.scenario("[analysis]\nmethod = \"ida\"\nsuperposition = \"unit-response\"\n"
                                                       "[ida]\nrtol = 1e-4\nmax_order = 3\n")));
  REQUIRE(i.settings.method == study::Method::ida);
  REQUIRE(i.settings.superposition == study::Superposition::unit_response);
  REQUIRE(i.settings.ida.rtol == 1e-4);
  REQUIRE(i.settings.ida.max_order == 3);
}

TEST_CASE("every numeric constraint of the schema is enforced, none is silently ignored") {
  // check_constraint knows a fixed list of forms; one it does not know is a logic_error (a
  // programming error), never a key whose constraint passes unchecked. Each numeric key with a
  // default is set to that default through an override (the path of --set): it must pass.
  Scratch s;
  const std::string path = s.scenario("");
  int checked = 0;
  for (const KeySpec& k : scenario_schema()) {
    if (k.constraint.empty() || k.constraint.find('|') != std::string::npos || k.key.find("[]") != std::string::npos ||
        k.default_toml.empty())
      continue;
    if (k.type != ValueType::number && k.type != ValueType::integer) continue;
    INFO(k.key << " " << k.constraint << " default " << k.default_toml);
    REQUIRE_NOTHROW(load_flat(path, {k.key + "=" + k.default_toml}));
    ++checked;
  }
  REQUIRE(checked > 20);
  REQUIRE_THROWS_WITH(load_flat(path, {"modal.damping_vectors=4"}), Catch::Contains("must be [0, 3]"));
  REQUIRE_THROWS_WITH(load_flat(path, {"ida.max_order=0"}), Catch::Contains("must be [1, 5]"));
}

TEST_CASE("each scenario key is declared once: its schema entry sets its field, or it is one of the keys read by hand") {
  // The keys without a setter are those that combine several keys into one field (per-span
  // lists, the rail's E·I and ρ·A), arrays and files (trains, stations), speeds, the preset, the
  // fit section (read by io/fit.cpp), the assess section (read by viaduct assess), and free text.
  // Any other key must name its field.
  const std::vector<std::string> by_hand = {"description", "bridge.file", "bridge.notes", "bridge.span_lengths",
                                            "bridge.EI", "bridge.mass_per_m", "track.file", "track.notes",
                                            "track.rail.", "train.files", "analysis.preset", "stations[].",
                                            "train.unsprung_mass_kg", "train.suspension_stiffness_N_m",
                                            "train.suspension_damping_Ns_m", "irregularity.profile",
                                            "sweep.", "fit.", "assess."};
  int with_setter = 0;
  for (const KeySpec& k : scenario_schema()) {
    INFO(k.key);
    bool hand = false;
    for (const auto& h : by_hand) hand = hand || k.key == h || (h.back() == '.' && k.key.compare(0, h.size(), h) == 0);
    REQUIRE((k.set != nullptr) != hand);
    with_setter += k.set != nullptr;
  }
  REQUIRE(with_setter > 45);

  // Each numeric setter moves the field it names: the scenario with the key set to another valid
  // value differs from the reference one (the values are compared through what viaduct check
  // shows of them: the resolved scenario after to_scenario).
  Scratch s;
  const std::string path = s.scenario("[track]\nfile = \"parts/track.toml\"\n");
  s.write("parts/track.toml",
          "rail.E = 2.1e11\nrail.I = 3e-5\nrail.A = 7.7e-3\nsleeper_mass = 300\nballast_mass = 318\npad.k = 1e8\n"
          "ballast.k = 1.9e8\nsubgrade.k = 7.4e7\nsubgrade_on_bridge.k = 7.4e9\n");
  const study::Scenario ref = to_scenario(load_flat(path));
  auto differs = [&](const study::Scenario& a) {
    const auto& x = a.settings;
    const auto& y = ref.settings;
    const auto& t = *a.track;
    const auto& u = *ref.track;
    return x.dt != y.dt || x.newmark.beta != y.newmark.beta || x.newmark.gamma != y.newmark.gamma ||
           x.newmark.alpha != y.newmark.alpha || x.ida.rtol != y.ida.rtol || x.ida.atol_disp != y.ida.atol_disp ||
           x.ida.atol_vel != y.ida.atol_vel || x.ida.max_order != y.ida.max_order ||
           x.modal.n_modes != y.modal.n_modes || x.modal.max_frequency_hz != y.modal.max_frequency_hz ||
           x.modal.damping_vectors != y.modal.damping_vectors || x.free_vibration_s != y.free_vibration_s ||
           x.load_factor != y.load_factor || x.filter.cheby.order != y.filter.cheby.order ||
           x.filter.cheby.ripple_db != y.filter.cheby.ripple_db || x.filter.cheby.low_hz != y.filter.cheby.low_hz ||
           x.filter.cheby.high_hz != y.filter.cheby.high_hz || a.bridge.element_size != ref.bridge.element_size ||
           a.bridge.added_mass_per_m != ref.bridge.added_mass_per_m || a.bridge.bearings.k != ref.bridge.bearings.k ||
           a.bridge.bearings.c != ref.bridge.bearings.c || a.bridge.bearings.rotational_k != ref.bridge.bearings.rotational_k || a.bridge.damping.ratio != ref.bridge.damping.ratio ||
           a.bridge.damping.f1_hz != ref.bridge.damping.f1_hz || a.bridge.damping.ratio1 != ref.bridge.damping.ratio1 ||
           a.bridge.damping.f2_hz != ref.bridge.damping.f2_hz || a.bridge.damping.ratio2 != ref.bridge.damping.ratio2 ||
           t.approach_length != u.approach_length || t.exit_length != u.exit_length ||
           t.first_sleeper_offset != u.first_sleeper_offset ||
           t.sleeper_spacing != u.sleeper_spacing || t.rail_elements_per_bay != u.rail_elements_per_bay ||
           t.sleeper_mass != u.sleeper_mass || t.ballast_mass != u.ballast_mass || t.pad.k != u.pad.k ||
           t.pad.c != u.pad.c || t.ballast.k != u.ballast.k || t.ballast.c != u.ballast.c || t.shear.k != u.shear.k ||
           t.shear.c != u.shear.c || t.subgrade.k != u.subgrade.k || t.subgrade.c != u.subgrade.c ||
           t.subgrade_on_bridge.k != u.subgrade_on_bridge.k || t.subgrade_on_bridge.c != u.subgrade_on_bridge.c ||
           a.run_speed != ref.run_speed || x.vehicle.contact_stiffness != y.vehicle.contact_stiffness ||
           x.vehicle.wheel_radius != y.vehicle.wheel_radius || x.vehicle.end_transition != y.vehicle.end_transition ||
           x.vehicle.comfort_lowpass_hz != y.vehicle.comfort_lowpass_hz || x.irregularity.seed != y.irregularity.seed ||
           x.irregularity.lambda_min != y.irregularity.lambda_min || x.irregularity.lambda_max != y.irregularity.lambda_max ||
           x.irregularity.dx != y.irregularity.dx || x.irregularity.run_in != y.irregularity.run_in ||
           x.irregularity.taper != y.irregularity.taper;
  };
  int moved = 0;
  for (const KeySpec& k : scenario_schema()) {
    if (!k.set || (k.type != ValueType::number && k.type != ValueType::integer)) continue;
    INFO(k.key);
    const FlatScenario base = load_flat(path);
    // A value 1.5 times the current one (or 2 for an integer, 0.5 for ratios and alpha), within
    // every constraint of these keys.
    const double cur = base.has(k.key) ? base.at(k.key).x : 100.0;
    std::string value;
    if (k.key == "irregularity.seed") value = "7";
    else if (k.key == "irregularity.min_wavelength_m") value = "2.0";  // below the 80 m longest
    else if (k.key == "irregularity.taper_m") value = "30.0";          // within the 100 m run-in  // not in the base scenario: cur is not its default 1
    else if (k.type == ValueType::integer) value = std::to_string(static_cast<long>(cur) == 1 ? 2 : 1);
    else if (k.key == "analysis.alpha") value = "-0.1";
    else if (k.key == "filter.low_hz") value = "2.0";
    else if (k.key == "analysis.gamma") value = "0.6";
    else if (k.key == "track.first_sleeper_offset") value = "0.25";  // below the spacing
    else value = format_number(cur == 0.0 ? 0.01 : cur * (cur < 1.0 ? 0.5 : 1.5), 12);
    const study::Scenario changed = to_scenario(load_flat(path, {k.key + "=" + value}));
    REQUIRE(differs(changed));
    ++moved;
  }
  REQUIRE(moved > 40);
}

TEST_CASE("a scenario of overrides alone: no file read, the keys checked as --set values") {
  const io::FlatScenario f = io::load_flat("", {"bridge.span_lengths=[12.0]", "bridge.EI=5e9", "bridge.mass_per_m=1e4",
                                               "train.files=[\"hslm:A1\"]", "stations[0].name=\"mid\"", "stations[0].span=1",
                                               "stations[0].at=0.5"});
  CHECK(f.at("bridge.EI").x == 5e9);
  CHECK(f.at("stations[0].name").s == "mid");
  CHECK(f.at("bridge.EI").where.file == "--set");
  CHECK(io::to_scenario(f).stations.size() == 1);
  REQUIRE_THROWS_WITH(io::load_flat("", {"bridge.EI=-1.0"}), Catch::Contains("--set: key 'bridge.EI': must be > 0"));
}

TEST_CASE("stations along a span: round(L/every_m) equal parts, both ends, named by their x, the entry's keys on each") {
  auto along = [](const std::string& every, const std::string& extra) {
    std::vector<std::string> set = {"bridge.span_lengths=[12.0, 7.0]", "bridge.EI=5e9", "bridge.mass_per_m=1e4",
                                    "train.files=[\"hslm:A1\"]", "stations[0].name=\"mid\"", "stations[0].span=1",
                                    "stations[0].at=0.5", "stations[1].name=\"L2\"", "stations[1].span=2",
                                    "stations[1].every_m=" + every};
    if (!extra.empty()) set.push_back(extra);
    return io::to_scenario(io::load_flat("", set));
  };
  // 7 m every 2 m: round(3.5) = 4 parts of 1.75 m (rounding half away from zero), 5 stations.
  // They are stations of load effects only: the accelerations and deflections stay at "mid".
  const study::Scenario sc = along("2.0", "stations[1].fibre_m=0.3");
  REQUIRE(sc.stations.size() == 1);
  CHECK(sc.stations[0].name == "mid");
  const auto& st = sc.effect_stations;
  const std::vector<std::string> names = {"L2_0.00m", "L2_1.75m", "L2_3.50m", "L2_5.25m", "L2_7.00m"};
  REQUIRE(st.size() == names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    CHECK(st[k].name == names[k]);
    CHECK(st[k].span == 1);
    CHECK(st[k].on_deck);
    CHECK(st[k].fibre_m == 0.3);
    CHECK(st[k].x_local == Approx(1.75 * static_cast<double>(k)).margin(1e-12));
  }
  CHECK(st.back().x_local == 7.0);  // the span's end exactly, not 4 × 1.75 rounded
  // A spacing longer than the span: its two ends.
  CHECK(along("100.0", "").effect_stations.size() == 2);
  // The effects of a prepared model: per station deflection, moment, strain, shear, after the
  // station's own moment and shear.
  const study::PreparedModel pm = study::prepare_model(sc, false, true);
  std::vector<std::string> effect_names;
  for (const auto& e : pm.effects) effect_names.push_back(e.name);
  REQUIRE(effect_names.size() >= 2 + 4 * names.size());
  CHECK(effect_names[2] == "L2_0.00m_disp_m");
  CHECK(effect_names[3] == "L2_0.00m_moment_Nm");
  CHECK(effect_names[4] == "L2_0.00m_strain_ue");
  CHECK(effect_names[5] == "L2_0.00m_shear_N");
  CHECK(pm.stations.size() == 1);
  REQUIRE_THROWS_WITH(along("1e-4", ""), Catch::Contains("would place 70001 stations"));
  // Closer than 1 cm: one decimal more than the spacing needs (7 m in 1000 parts of 7 mm: 4).
  const auto fine = along("0.007", "").effect_stations;
  REQUIRE(fine.size() == 1001);
  CHECK(fine[1].name == "L2_0.0070m");
  CHECK(fine[2].name == "L2_0.0140m");
  REQUIRE_THROWS_WITH(along("1.0", "stations[1].at=0.5"), Catch::Contains("exactly one of 'at' (fraction), 'x' (metres) or 'every_m'"));
}

// The filter's defaults are declared twice, in the schema and in signal::Cheby1Spec (used where
// no scenario is read: the Python package, code): they must be the same numbers (issue #37 item
// 3: filter.high_hz was 30 Hz in one and 60 Hz in the other).
TEST_CASE("the filter keys' schema defaults equal signal::Cheby1Spec's") {
  const signal::Cheby1Spec spec;
  auto def = [](const std::string& key) { return std::stod(io::find_key_spec(key)->default_toml); };
  CHECK(def("filter.order") == spec.order);
  CHECK(def("filter.ripple_db") == spec.ripple_db);
  CHECK(def("filter.low_hz") == spec.low_hz);
  CHECK(def("filter.high_hz") == spec.high_hz);
  CHECK(io::find_key_spec("filter.band")->default_toml == "\"bandpass\"");
  CHECK(spec.band == signal::BandType::bandpass);
}

// Keys declared once (issue #37 item 3): a key's default is written in the schema and, for the
// keys that set one field, in that field's initialiser; a program that fills study::Scenario
// itself (the Python package's dictionaries, code using the library) gets the struct's. Every
// such number and boolean must be the same in both.
TEST_CASE("every key that sets a field: its schema default equals the study::Scenario field's default") {
  const study::Scenario defaults;
  int checked = 0;
  for (const io::KeySpec& k : io::scenario_schema()) {
    if (!k.get || k.default_toml.empty()) continue;
    INFO(k.key << " = " << k.default_toml);
    const double want = k.type == io::ValueType::boolean ? (k.default_toml == "true" ? 1.0 : 0.0) : std::stod(k.default_toml);
    CHECK(k.get(defaults) == want);
    ++checked;
  }
  CHECK(checked >= 50);  // the number and boolean keys that set a field (60 when this was written)
  int texts = 0;
  for (const io::KeySpec& k : io::scenario_schema()) {
    if (!k.get_text || k.default_toml.empty()) continue;
    INFO(k.key << " = " << k.default_toml);
    CHECK("\"" + k.get_text(defaults) + "\"" == k.default_toml);
    ++texts;
  }
  CHECK(texts == 9);  // title, the six enumerations, irregularity.spectrum, track.rails
  // Every key that sets a field can be read back (a setter without a getter escapes the check).
  for (const io::KeySpec& k : io::scenario_schema())
    if (k.set && k.key != "run.speed_kmh") {
      INFO(k.key);
      CHECK((k.get != nullptr || k.get_text != nullptr));
    }
}
