#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <tuple>

#include "../scratch.hpp"
#include "source_dir.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/io/traffic_mix.hpp"

using namespace viaduct;

TEST_CASE("EN 1991-2 Annex D's fatigue train Type 1: its total load and length as REFERENCE.md gives them") {
  // REFERENCE.md §11: 6 axles of 225 kN, then 12 coaches of 4 axles of 110 kN; 6630 kN over
  // 262.10 m buffer to buffer, of which 1.4 m ahead of the first axle and 1.8 m behind the last.
  const load::Train t = io::read_train_file(std::string(VIADUCT_SOURCE_DIR) + "/data/trains/fatigue/type1.csv");
  REQUIRE(t.n_axles() == 54);
  CHECK(t.total_load() == Approx(6630e3).epsilon(1e-12));
  CHECK(t.length() + 1.4 + 1.8 == Approx(262.10).epsilon(1e-12));
  // The locomotive's bogies (2.2 m) and the coaches' (2.6 m), 20.3 m a coach.
  CHECK(t.offset[1] - t.offset[0] == Approx(2.2));
  CHECK(t.offset[4] - t.offset[3] == Approx(2.2));
  CHECK(t.offset[7] - t.offset[6] == Approx(2.6));
  CHECK(t.offset[10] - t.offset[6] == Approx(20.3));
  for (std::size_t a = 0; a < t.n_axles(); ++a) CHECK(t.load[a] == (a < 6 ? 225e3 : 110e3));
}

TEST_CASE("EN 1991-2 Annex D's fatigue trains Types 1 to 12: axles, total load and length of each figure's caption") {
  // Sum Q [kN] and L [m] buffer to buffer of figures D.1 to D.12 (to confirm against the
  // standard; the files were written from a public implementation's axle data by
  // scripts/generate/make_fatigue_trains.py, and every type reproduces its caption), and the
  // buffers' overhangs ahead of the first and behind the last axle.
  struct Type {
    int n;
    std::size_t axles;
    double sum_q_kn, length_m, front_m, rear_m;
  };
  const Type types[] = {{1, 54, 6630, 262.10, 1.4, 1.8},   {2, 44, 5300, 281.10, 1.4, 2.5},   {3, 60, 9400, 385.52, 4.7, 4.7},
                        {4, 30, 5100, 237.60, 3.5, 3.5},   {5, 96, 21600, 270.30, 2.0, 2.0},  {6, 76, 14310, 333.10, 2.0, 1.8},
                        {7, 46, 10350, 196.50, 1.4, 1.6},  {8, 46, 10350, 212.50, 1.4, 2.1},  {9, 24, 2960, 134.80, 2.15, 2.15},
                        {10, 32, 3600, 129.60, 1.75, 1.75}, {11, 46, 11350, 198.50, 1.4, 1.5}, {12, 46, 11350, 212.50, 1.4, 2.1}};
  for (const Type& ty : types) {
    INFO("Type " << ty.n);
    const load::Train t =
        io::read_train_file(std::string(VIADUCT_SOURCE_DIR) + "/data/trains/fatigue/type" + std::to_string(ty.n) + ".csv");
    CHECK(t.n_axles() == ty.axles);
    CHECK(t.total_load() == Approx(ty.sum_q_kn * 1e3).epsilon(1e-12));
    CHECK(t.length() + ty.front_m + ty.rear_m == Approx(ty.length_m).epsilon(1e-9));
  }
}

TEST_CASE("EN 1991-2 Annex D's traffic mixes: their trains a day, and about 25e6 t a year each") {
  // Tables D.1 (standard, 67 trains a day), D.2 (heavy, 51) and D.3 (light, 207), to confirm;
  // each is built for 25e6 t a year, which at 10 kN per tonne (the standard's 225 kN = 22.5 t)
  // they carry within 2 %: 24.95e6, 24.78e6 and 25.49e6 t.
  const std::string dir = std::string(VIADUCT_SOURCE_DIR) + "/data/trains/fatigue/";
  for (const auto& [name, trains_a_day, tonnes] : {std::tuple<const char*, double, double>{"standard", 67, 24.95e6},
                                                   {"heavy", 51, 24.78e6},
                                                   {"light", 207, 25.49e6}}) {
    INFO(name);
    const study::TrafficMix mix = io::read_traffic_mix(dir + "mix-" + name + ".toml");
    double per_day = 0.0, kn_a_day = 0.0;
    for (const study::MixTrain& t : mix.trains) {
      per_day += t.per_day;
      kn_a_day += t.per_day * t.train.total_load() / 1e3;
      CHECK(t.speed > 0.0);
    }
    CHECK(per_day == trains_a_day);
    CHECK(kn_a_day / 10.0 * 365.0 == Approx(tonnes).epsilon(1e-3));
    CHECK(kn_a_day / 10.0 * 365.0 == Approx(25e6).epsilon(0.02));
  }
  const study::TrafficMix standard = io::read_traffic_mix(dir + "mix-standard.toml");
  CHECK(standard.trains[0].name == "type1");
  CHECK(standard.trains[0].speed == Approx(200 / 3.6));
}

TEST_CASE("a traffic mix file that is wrong says where: file, line and key") {
  const vt::ScratchDir dir("traffic-mix");
  const std::string train = std::string(VIADUCT_SOURCE_DIR) + "/data/trains/fatigue/type1.csv";
  auto mix_file = [&](const std::string& name, const std::string& body) {
    return dir.write(name + ".toml", "title = \"t\"\n[[trains]]\nfile = \"" + train + "\"\n" + body);
  };
  CHECK(io::read_traffic_mix(mix_file("good", "per_day = 3\nspeed_kmh = 100\n")).trains.size() == 1);
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("neg", "per_day = -3\nspeed_kmh = 100\n")),
                    Catch::Contains("neg.toml:4") && Catch::Contains("trains[0].per_day") && Catch::Contains("per_day >= 0"));
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("nospeed", "per_day = 3\n")),
                    Catch::Contains("nospeed.toml:2") && Catch::Contains("trains[0].speed_kmh") && Catch::Contains("required"));
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("typo", "per_day = 3\nspeed_kmh = 100\nper_dya = 4\n")),
                    Catch::Contains("typo.toml:6") && Catch::Contains("trains[0].per_dya") && Catch::Contains("unknown key"));
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("text", "per_day = \"many\"\nspeed_kmh = 100\n")),
                    Catch::Contains("text.toml:4") && Catch::Contains("must be a number"));
  const std::string missing = dir.write("missing.toml", "[[trains]]\nfile = \"type99.csv\"\nper_day = 1\nspeed_kmh = 100\n");
  CHECK_THROWS_WITH(io::read_traffic_mix(missing),
                    Catch::Contains("missing.toml:2") && Catch::Contains("trains[0].file") && Catch::Contains("type99.csv"));
  CHECK_THROWS_WITH(io::read_traffic_mix(dir.write("empty.toml", "title = \"nothing\"\n")), Catch::Contains("[[trains]]"));
  // One type at two speeds: told apart by the speed; at one speed twice: refused; a name given.
  const std::string two = "per_day = 3\nspeed_kmh = 100\n[[trains]]\nfile = \"" + train + "\"\nper_day = 1\nspeed_kmh = ";
  const study::TrafficMix speeds = io::read_traffic_mix(mix_file("speeds", two + "120\n"));
  REQUIRE(speeds.trains.size() == 2);
  CHECK(speeds.trains[0].name == "type1 at 100 km/h");
  CHECK(speeds.trains[1].name == "type1 at 120 km/h");
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("twice", two + "100\n")),
                    Catch::Contains("twice.toml:6") && Catch::Contains("the same train (type1) at the same speed as trains[0]"));
  CHECK(io::read_traffic_mix(mix_file("named", two + "100\nname = \"slow freight\"\n")).trains[1].name == "slow freight");
  // a name that is not a name is refused, not replaced by the file's (two rows of one name)
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("numname", two + "100\nname = 5\n")),
                    Catch::Contains("numname.toml:10") && Catch::Contains("trains[1].name") && Catch::Contains("non-empty string"));
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("noname", two + "100\nname = \"\"\n")),
                    Catch::Contains("trains[1].name") && Catch::Contains("non-empty string"));
  // a name given equal to another's speed-qualified name: two rows of one name, refused
  const std::string third = two + "120\n[[trains]]\nfile = \"" + train + "\"\nper_day = 1\nspeed_kmh = 80\nname = \"type1 at 100 km/h\"\n";
  CHECK_THROWS_WITH(io::read_traffic_mix(mix_file("clash", third)),
                    Catch::Contains("clash.toml:10") && Catch::Contains("trains[2]") && Catch::Contains("two trains named \"type1 at 100 km/h\""));
  CHECK_THROWS_WITH(io::read_traffic_mix((dir.p / "absent.toml").string()), Catch::Contains("not found"));
}
