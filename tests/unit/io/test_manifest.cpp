#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "viaduct/io/output_dir.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/sweep.hpp"
#include "source_dir.hpp"

using namespace viaduct;

namespace manifest_tests {
// Writes the manifest to `out`, reads it back and removes the file.
std::string manifest_text(const std::filesystem::path& out, const io::Manifest& m, const io::FlatScenario& flat) {
  io::write_manifest(out.string(), m, flat);
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  std::filesystem::remove(out);
  return ss.str();
}
}  // namespace manifest_tests
using namespace manifest_tests;

TEST_CASE("SHA-256 of the FIPS 180-4 test vectors, in memory and from a file") {
  // Empty input, one block, a message whose padding needs a second block, and a million bytes.
  REQUIRE(io::sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  REQUIRE(io::sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  REQUIRE(io::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  const std::string million(1000000, 'a');
  REQUIRE(io::sha256_hex(million) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  const auto path = std::filesystem::temp_directory_path() / "viaduct_sha_test.bin";
  std::ofstream(path, std::ios::binary) << million;
  REQUIRE(io::sha256_file(path.string()) == io::sha256_hex(million));
  std::filesystem::remove(path);
  REQUIRE_THROWS_AS(io::sha256_file("/nonexistent/file"), InputError);
}

TEST_CASE("a manifest records the command line, the settings that ran and every input file's checksum") {
  const std::string src = VIADUCT_SOURCE_DIR;
  const std::string scen = src + "/scenarios/old-guadiana-sensitivity.toml";
  const io::FlatScenario flat = io::load_flat(scen, {"analysis.preset=\"default\""});
  const study::Scenario sc = io::to_scenario(flat);
  io::Manifest m;
  m.command = "sweep";
  m.command_line = "viaduct sweep x.toml --set 'analysis.preset=\"default\"'";
  m.as_run = io::settings_as_run(sc.settings);
  m.inputs = {src + "/data/records/synthetic-deck.csv"};
  const auto out = std::filesystem::temp_directory_path() / "viaduct_manifest_test.toml";
  const std::string t = manifest_text(out, m, flat);
  REQUIRE(t.find("command_line = ") != std::string::npos);
  REQUIRE(t.find("git_commit = ") != std::string::npos);
  // The preset ran the modal method, though the [scenario] table keeps analysis.method's default.
  REQUIRE(t.find("[analysis_as_run]\n\"analysis.method\" = \"modal\"") != std::string::npos);
  REQUIRE(t.find("\"analysis.method\" = \"newmark\"") != std::string::npos);
  // The scenario, its component files, its train and the extra input, each with its checksum.
  for (const std::string& f : {scen, m.inputs.front()}) {
    INFO(f);
    REQUIRE(t.find("file = \"" + f + "\"\nsha256 = \"" + io::sha256_file(f) + "\"") != std::string::npos);
  }
  std::size_t n_inputs = 0;
  for (std::size_t at = t.find("[[inputs]]"); at != std::string::npos; at = t.find("[[inputs]]", at + 1)) ++n_inputs;
  REQUIRE(n_inputs >= 4);  // scenario, bridge and track components, train, record
}

TEST_CASE("a manifest lists the coach file a train of coaches names, with its checksum") {
  const std::string src = VIADUCT_SOURCE_DIR;
  const std::string scen = src + "/scenarios/vehicles-25m.toml";
  const io::FlatScenario flat = io::load_flat(scen, {});
  io::Manifest m;
  m.command = "run";
  const auto out = std::filesystem::temp_directory_path() / "viaduct_manifest_coaches.toml";
  const std::string t = manifest_text(out, m, flat);
  const std::string coach =
      std::filesystem::path(src + "/data/vehicles/ave-s103.toml").lexically_normal().string();
  INFO(t);
  REQUIRE(t.find("ave-s103.toml\"\nsha256 = \"" + io::sha256_file(coach) + "\"") != std::string::npos);
  REQUIRE(io::coach_file_of(src + "/data/trains/ave-s103-8.toml") ==
          std::filesystem::path(src + "/data/trains/../vehicles/ave-s103.toml").lexically_normal().string());
  REQUIRE(io::coach_file_of(src + "/data/records/synthetic-deck.csv").empty());
}

TEST_CASE("outputs: a file hashed as it was written gives the manifest its bytes' checksum, one written otherwise is read back") {
  // load_effects.csv is written through AtomicFile::write (its checksum known at commit);
  // failures.csv through the FILE (read back); a path written the first way and then the second
  // loses the first checksum. The manifest's [[outputs]] are the files' checksums either way, and
  // check_output_dir accepts the directory.
  const auto dir = std::filesystem::temp_directory_path() / "viaduct_hashed_outputs";
  std::filesystem::remove_all(dir);
  io::begin_outputs(dir.string());
  std::vector<study::Variant> variants(1);
  variants[0].label = "reference";
  std::vector<study::QuantityRow> rows(5000);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    rows[k].variant = "reference";
    rows[k].train = "HSLM-A" + std::to_string(k % 10 + 1);
    rows[k].quantity = "mid_moment_Nm";
    rows[k].speed = 40.0 + 0.01 * static_cast<double>(k);
    rows[k].dynamic = {1e6 + static_cast<double>(k), -3e5};
    rows[k].quasi_static = {9e5, 0.0};
  }
  const std::string le = (dir / "load_effects.csv").string(), fa = (dir / "failures.csv").string(),
                    twice = (dir / "twice.csv").string();
  for (int threads : {1, 2}) {
    io::write_quantities_csv(le, rows, variants, threads);
    CHECK(io::output_checksum(le) == io::sha256_file(le));
  }
  io::write_failures_csv(fa, {{"reference", "HSLM-A1", 40.0, "diverged", false}});
  CHECK(io::output_checksum(fa).empty());
  io::write_text_file(twice, "a,b\n1,2\n");
  CHECK(io::output_checksum(twice) == io::sha256_hex("a,b\n1,2\n"));
  io::write_failures_csv(twice, {});
  CHECK(io::output_checksum(twice).empty());
  io::Manifest m;
  m.command = "sweep";
  io::write_manifest((dir / "manifest.toml").string(), m, nullptr);
  std::ifstream in(dir / "manifest.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  for (const std::string& f : {le, fa, twice})
    CHECK_THAT(ss.str(), Catch::Contains("file = \"" + std::filesystem::path(f).filename().string() + "\"\nsha256 = \"" +
                                         io::sha256_file(f) + "\""));
  CHECK_NOTHROW(io::check_output_dir(dir.string()));
  std::filesystem::remove_all(dir);
}
