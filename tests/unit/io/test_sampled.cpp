// Sampled studies from scenario files: the study and its samples' variants, bad distributions
// refused with file, line and key, the stream of per-sample peaks resumed after a batch cut
// short, shard ranges.
#include <unistd.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "viaduct/io/sampled.hpp"

namespace sampled_io_test {

using namespace viaduct;
namespace fs = std::filesystem;

struct Dir {
  fs::path dir;
  Dir() {
    static int n = 0;
    dir = fs::temp_directory_path() / ("viaduct-sampled-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    fs::create_directories(dir);
  }
  ~Dir() { fs::remove_all(dir); }
  // A 10 m span under three axles; `sweep` is the [sweep] section and its variants.
  std::string scenario(const std::string& sweep) const {
    const std::string path = (dir / "s.toml").string();
    std::ofstream(path) << "[bridge]\nspan_lengths = [10.0]\nEI = 2e9\nmass_per_m = 5000.0\n[bridge.damping]\nratio = 0.02\n"
                           "[train]\nfiles = [\"hslm:A1\"]\n"
                           "[[stations]]\nname = \"mid\"\nspan = 1\nat = 0.5\n"
                        << sweep;
    return path;
  }
  std::string text(const std::string& name) const {
    std::ifstream in(dir / name);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
};

// Line 13 is the [sweep] header: keys follow from line 14.
const char* kEI = "[sweep]\nmode = \"sample\"\nn_samples = 8\nspeeds_kmh = [100.0]\n"
                  "[[sweep.variants]]\nkey = \"bridge.EI\"\nlabel = \"EI\"\ndistribution = \"lognormal\"\nmean = 1.0\nsd = 0.1\n";

io::SampledStudy study_of(const std::string& path, const std::vector<std::string>& set = {}) {
  return io::sampled_study(io::load_flat(path, set));
}

TEST_CASE("sampled study: read from the scenario, each sample's key scaled by its factor") {
  Dir d;
  const std::string path = d.scenario(std::string(kEI) +
                                      "[[sweep.variants]]\nkey = \"bridge.mass_per_m\"\ndistribution = \"uniform\"\nlow = 0.9\nhigh = 1.1\n");
  const io::FlatScenario flat = io::load_flat(path);
  const io::SampledStudy st = io::sampled_study(flat);
  REQUIRE(st.keys == std::vector<std::string>{"bridge.EI", "bridge.mass_per_m"});
  CHECK(st.labels == std::vector<std::string>{"EI", "bridge.mass_per_m"});
  CHECK(st.n_total() == 8);
  CHECK(st.spec.method == study::SamplingMethod::lhs);
  const study::SampleDesign design = study::sample_design(st.spec);
  const study::Scenario ref = io::to_scenario(flat);
  for (Index s : {Index(0), Index(7)}) {
    const study::Variant v = io::sample_variant(flat, st, design, s, ref);
    CHECK(v.error.empty());
    CHECK(v.scenario.bridge.spans[0].EI == Approx(2e9 * design.factors(s, 0)).epsilon(1e-14));
    CHECK(v.scenario.bridge.spans[0].mass_per_m == Approx(5000.0 * design.factors(s, 1)).epsilon(1e-14));
  }
  // Sensitivity: n (d + 2) samples.
  CHECK(io::sampled_study(io::load_flat(path, {"sweep.sensitivity=true"})).n_total() == 32);
  // The other commands see the reference only.
  CHECK(io::sweep_variants(flat).size() == 1);
}

TEST_CASE("sampled study: bad distributions are errors with file, line and key") {
  Dir d;
  auto error_of = [&](const std::string& path, const std::vector<std::string>& set, const std::vector<std::string>& unset = {}) {
    try {
      io::sampled_study(io::load_flat(path, set, unset));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // The scenario's line for its keys (line 22: sd), "--set" for overrides.
  std::string bad_sd = kEI;
  bad_sd.replace(bad_sd.find("sd = 0.1"), 8, "sd = -0.1");
  CHECK_THAT(error_of(d.scenario(bad_sd), {}), Catch::Contains("s.toml:22") && Catch::Contains("sweep.variants[0].sd") &&
                                                   Catch::Contains("sd > 0"));
  const std::string path = d.scenario(kEI);
  CHECK(error_of(path, {}) == "no error");
  CHECK_THAT(error_of(path, {"sweep.variants[0].distribution=\"uniform\""}),
             Catch::Contains("--set") && Catch::Contains("needs low, high"));
  CHECK_THAT(error_of(path, {"sweep.variants[0].distribution=\"uniform\"", "sweep.variants[0].low=0.5",
                             "sweep.variants[0].high=1.5"}),
             Catch::Contains("s.toml:21") && Catch::Contains("takes no mean"));
  CHECK_THAT(error_of(path, {"sweep.variants[0].distribution=\"uniform\"", "sweep.variants[0].low=2.0", "sweep.variants[0].high=1.0"},
                      {"sweep.variants[0].mean", "sweep.variants[0].sd"}),
             Catch::Contains("sweep.variants[0].low") && Catch::Contains("low < high"));
  CHECK_THAT(error_of(path, {"bridge.damping.ratio=0.0", "sweep.variants[0].key=\"bridge.damping.ratio\""}),
             Catch::Contains("reference value of bridge.damping.ratio is 0"));
  CHECK_THAT(error_of(path, {"sweep.variants[0].mean=0.2", "sweep.variants[0].distribution=\"normal\""}),
             Catch::Contains("mean >= 6 sd") && Catch::Contains("truncated"));
  CHECK_THAT(error_of(path, {"sweep.variants[0].key=\"bridge.EJ\""}), Catch::Contains("not a key of this scenario"));
  CHECK_THAT(error_of(path, {"sweep.variants[0].factors=[1.0, 2.0]"}),
             Catch::Contains("sweep.variants[0].factors") && Catch::Contains("draws each key's factor"));
  CHECK_THAT(error_of(path, {"sweep.n_samples=1"}), Catch::Contains("sweep.n_samples") && Catch::Contains(">= 2"));
  CHECK_THAT(error_of(path, {"sweep.percentiles=[50.0, 120.0]"}), Catch::Contains("[0, 100]"));
  const std::string self = d.scenario(std::string(kEI) + "[[sweep.correlations]]\nkeys = [\"EI\", \"bridge.EI\"]\nrho = 0.5\n");
  CHECK_THAT(error_of(self, {}), Catch::Contains("s.toml:24") && Catch::Contains("itself"));
  CHECK_THAT(error_of(path, {}, {"sweep.n_samples"}), Catch::Contains("needs sweep.n_samples"));
  CHECK_THAT(error_of(path, {}, {"sweep.variants[0].distribution"}),
             Catch::Contains("s.toml:18") && Catch::Contains("sweep.variants[0].distribution = \"uniform\""));
}

TEST_CASE("sampled study: a factor range breaking the key's rule, correlations, and the design's limits") {
  Dir d;
  const std::string two = std::string(kEI) +
                          "[[sweep.variants]]\nkey = \"bridge.mass_per_m\"\ndistribution = \"uniform\"\nlow = 0.0\nhigh = 1.1\n";
  const std::string path =
      d.scenario(two + "[[sweep.correlations]]\nkeys = [\"EI\", \"bridge.mass_per_m\"]\nrho = 0.7\n");
  CHECK_THROWS_WITH(study_of(path), Catch::Contains("factor 0 breaks the rule of") && Catch::Contains("mass_per_m"));
  std::vector<std::string> set{"sweep.variants[1].low=0.5"};
  const io::SampledStudy st = study_of(path, set);
  REQUIRE(st.spec.correlation.rows() == 2);
  CHECK(st.spec.correlation(0, 1) == 0.7);
  set.push_back("sweep.sensitivity=true");
  CHECK_THROWS_WITH(study_of(path, set), Catch::Contains("independent inputs"));
  set = {"sweep.variants[1].low=0.5", "sweep.correlations[0].rho=1.5"};
  CHECK_THROWS_WITH(study_of(path, set), Catch::Contains("[-1, 1]"));
  set = {"sweep.variants[1].low=0.5", "sweep.sampling=\"sobol\""};
  CHECK(study_of(path, set).spec.method == study::SamplingMethod::sobol);
}

TEST_CASE("sample stream: a batch cut short is dropped on resume, the result as if uninterrupted") {
  Dir a, b;
  auto batch = [](Index begin, Index end) {
    study::SampleBatch out;
    out.begin = begin;
    out.end = end;
    for (Index s = begin; s < end; ++s) out.peaks.push_back({s, "T, quoted", "mid", 30.0 + double(s), 0.5 * double(s), 1e-3});
    if (begin == 2) out.failures.push_back({begin, "T, quoted", 30.0, "diverged", false});
    return out;
  };
  {
    io::SampleStream s(a.dir.string(), 0, 6, "fp");
    for (Index k = 0; k < 6; k += 2) s.append(batch(k, k + 2));
    s.finish();
  }
  {
    io::SampleStream s(b.dir.string(), 0, 6, "fp");
    s.append(batch(0, 2));
    std::ofstream(b.dir / "sample_peaks.csv.partial", std::ios::app) << "2,T,30,mid,0.1";  // killed mid-row
  }
  CHECK_THROWS_WITH(io::SampleStream::resume(b.dir.string(), 0, 6, "other"), Catch::Contains("another study"));
  CHECK_THROWS_WITH(io::SampleStream::resume(b.dir.string(), 0, 4, "fp"), Catch::Contains("ran samples [0, 6)"));
  io::SampleStream s = io::SampleStream::resume(b.dir.string(), 0, 6, "fp");
  CHECK(s.next() == 2);
  s.append(batch(2, 4));
  s.append(batch(4, 6));
  s.finish();
  CHECK(b.text("sample_peaks.csv") == a.text("sample_peaks.csv"));
  CHECK(b.text("failures.csv") == a.text("failures.csv"));
  CHECK(a.text("sample_peaks.csv").find("\"T, quoted\"") != std::string::npos);
  CHECK_FALSE(fs::exists(b.dir / "sample_progress.toml"));
  CHECK_THROWS_WITH(io::SampleStream::resume(b.dir.string(), 0, 6, "fp"), Catch::Contains("nothing to resume"));
}

TEST_CASE("shards: ranges of whole groups that join end to end, K/N parsed strictly") {
  for (int n : {1, 2, 7, 40}) {
    Index prev = 0;
    for (int k = 1; k <= n; ++k) {
      const auto [b, e] = io::shard_range(k, n, 36, 6);
      CHECK(b == prev);
      CHECK(b % 6 == 0);
      CHECK(e % 6 == 0);
      prev = e;
    }
    CHECK(prev == 36);
  }
  CHECK(io::parse_shard("3/7") == std::pair<int, int>{3, 7});
  for (const char* bad : {"0/2", "3/2", "1/", "/2", "1/2x", "a/b", "12"}) CHECK_THROWS_AS(io::parse_shard(bad), InputError);
}

}  // namespace sampled_io_test
