// Outputs are written atomically: a write that fails part-way (here: the file size limit, as a
// full disk would) leaves the earlier file whole and no temporary file behind.
#include <sys/resource.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"

using namespace viaduct;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Files in `dir`, hidden ones included.
std::size_t n_files(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
  return n;
}

// Runs `fn` with the process's file size limit at `bytes` and SIGXFSZ ignored, so that a write
// beyond it fails with EFBIG (as one on a full disk fails with ENOSPC); restores both.
template <class F>
void with_file_size_limit(rlim_t bytes, F fn) {
  rlimit old{};
  REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
  auto* previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit lim = old;
  lim.rlim_cur = bytes;
  REQUIRE(setrlimit(RLIMIT_FSIZE, &lim) == 0);
  try {
    fn();
  } catch (...) {
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    throw;
  }
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
}
}  // namespace

TEST_CASE("a failed write leaves the earlier output whole and no temporary file") {
  const fs::path dir = fs::temp_directory_path() / ("viaduct-atomic-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "envelope.csv").string();
  io::write_table_csv(path, {"a", "b"}, {{"1", "2"}});
  const std::string before = slurp(path);
  REQUIRE(before == "a,b\n1,2\n");
  // A table of 200 kB against a 64 kB limit: the write fails part-way.
  std::vector<std::vector<std::string>> big(20000, {"123456789", "0.5"});
  with_file_size_limit(64 * 1024, [&] {
    REQUIRE_THROWS_AS(io::write_table_csv(path, {"a", "b"}, big), SolverError);
    io::Record r;
    r.fs_hz = 100;
    r.channels = {"x_m"};
    r.units = {"m"};
    r.data = Matrix::Constant(20000, 1, 0.123456789);
    REQUIRE_THROWS_WITH(io::write_record_csv((dir / "rec.csv").string(), r), Catch::Contains("error writing"));
  });
  CHECK(slurp(path) == before);
  CHECK_FALSE(fs::exists(dir / "rec.csv"));
  // A table whose numbers came out non-finite is not written either, and says where.
  for (const char* bad : {"nan", "-nan", "inf", "-Inf"})
    REQUIRE_THROWS_WITH(io::write_table_csv(path, {"a", "b"}, {{"1", "2"}, {"3", bad}}), Catch::Contains("column b holds a non-finite value (row 2"));
  CHECK(slurp(path) == before);
  CHECK(n_files(dir) == 1);  // no temporary file left
  // A write that succeeds replaces the file.
  io::write_table_csv(path, {"a", "b"}, big);
  CHECK(slurp(path).size() > 64 * 1024);
  CHECK(n_files(dir) == 1);
  fs::remove_all(dir);
}
